// lgi/apps/runner.hpp — running a loaded scene: CSV rows at the output times, a summary at the end.
//
// CSV (shared/DESIGN.md §3): a header row, then one row per output time with the columns
//   t, R11 … R33 (row-major), omega1 … omega3, energy, orthogonality_error (‖RᵀR − I‖_F),
// followed by the problem's own invariants (heavy_top: momentum_k = m·k; free_body: momentum_1..3 = m,
// momentum_norm = |JΩ|). Numbers carry 17 significant digits.
//
// A run that does not complete — a failed step, a budget (scene "limits"), a signal — ends with the rows so
// far and a last row with the last good state (RunReport::final_row; not repeated when it is the last row
// written); a row with a column that is not finite is never written (RunReport::rows_not_finite). With
// RunOptions::checkpoint_path, checkpoints (runner_checkpoint.hpp) are written periodically and where a signal
// or a budget stops the run, and RunOptions::resume continues one bit for bit (core/driver.hpp's cursor).
// docs/checkpoints.md has the whole contract.
//
// In-run observation (RunOptions::observer; `lgi sweep`'s extrema, Poincaré crossings and Lyapunov estimates,
// apps/sweep_observe.hpp): the run calls the observer with the initial state and after every step of its
// trajectory — fixed steps: each grid step t_n = n·dt and the final side-step to t_end when t_end is off the
// grid; adaptive runs: each accepted step — in place of the scene's output events (no rows: csv must be
// nullptr), and once more when the run ends. Through StepAccess the observer may take side-steps from the
// previous state and run a second ("shadow") trajectory with the same method and steps; neither touches the
// run's own trajectory, whose states are bit for bit those of a run without an observer. A run without an
// observer pays nothing for this: its drivers see only its own output events.
#pragma once

#include "output_file.hpp"
#include "runner_checkpoint.hpp"
#include "scene.hpp"

#include <lgi/core/driver.hpp>

#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace lgi::app {

// What an observed run lets its observer do between steps (fixed-step runs; can_step() is false for adaptive
// runs, and the other calls then fail). "prev" is the state at the previous call (t = 0 for the first step).
class StepAccess {
 public:
  virtual bool can_step() const = 0;
  // The size of the step that led from prev to the state of the current step() call (its driver's own h).
  virtual double step_size() const = 0;
  // The state one step of size tau > 0 from prev reaches — the driver's side-step, as for an output time between
  // grid points; tau = the step just taken gives exactly the trajectory's state. false: the step failed.
  virtual bool side_step(double tau, State<double>& x) = 0;
  // The shadow trajectory: set to x at the current time; from then on advanced with the run's own step sizes and
  // times (before each call of RunObserver::step) until a step of it fails (shadow_ok() false; it stays there).
  virtual void shadow_set(const State<double>& x) = 0;
  virtual bool shadow_ok() const = 0;
  virtual State<double> shadow_state() const = 0;

 protected:
  ~StepAccess() = default;
};

class RunObserver {
 public:
  virtual void start(const State<double>& x0, StepAccess& access) = 0;                         // at t = 0
  virtual void step(double t_prev, double t, const State<double>& x, StepAccess& access) = 0;  // after each step
  // When the run ends (completed or not): t and x its last good state (that of the last step() call, or x0).
  virtual void finish(double t, const State<double>& x, StepAccess& access) = 0;

 protected:
  ~RunObserver() = default;
};

// Where a run's rows go as numbers rather than text (RunOptions::rows; the Python package's results): one call per
// row with the columns `lgi run` writes (output_header's), the values it prints with 17 significant digits — read
// back from its CSV they are these doubles. A row with a column that is not finite is not passed, as it is not
// written.
class RowSink {
 public:
  virtual void row(std::span<const double> columns) = 0;

 protected:
  ~RowSink() = default;
};

// How a command shows its progress on stderr: not at all, on a terminal (one line rewritten at most four times a
// second), or as whole lines every 2 s (a log).
enum class Progress : std::uint8_t { none, terminal, lines };

// terminal when stderr is one, lines when asked (--progress), none with -q.
Progress progress_mode(bool quiet, bool asked);

// The progress display of `lgi run`, `lgi sweep` and `lgi fit`: due() is true once the command has run a second,
// then every 250 ms on a terminal or 2 s as lines; show() writes a line (rewritten in place on a terminal, prefixed
// "lgi: progress: " otherwise); clear() removes a terminal's line before the command's own output.
class ProgressLine {
 public:
  explicit ProgressLine(Progress mode) : mode_(mode) {}
  Progress mode() const { return mode_; }
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }
  bool due() const;
  void show(const std::string& text);
  void clear() const;

 private:
  using Clock = std::chrono::steady_clock;
  Progress mode_;
  Clock::time_point start_ = Clock::now(), last_ = start_;
  bool shown_ = false;
};

struct RunOptions {
  OutputFile* csv = nullptr;                        // rows go here, one record each; nullptr: no rows
  RowSink* rows = nullptr;  // or here, as numbers (instead of csv; not with checkpoints, resume or an observer)
  Progress progress = Progress::none;
  const volatile std::sig_atomic_t* stop = nullptr;  // the run stops when *stop becomes non-zero
  // Long runs flush the rows at least this often (wall seconds; checked with the monitor).
  double flush_seconds = 1.0;
  // Checkpoints (runner_checkpoint.hpp), when checkpoint_path is not empty: every checkpoint_every_steps steps
  // or checkpoint_every_seconds of wall time (checked with the monitor), and where a signal or a budget stops the
  // run. csv must then be the atomic output whose temporary file output.partial names. A checkpoint that cannot
  // be written stops the run (StopReason::write_failed; the previous checkpoint and the rows it counts stay).
  std::string checkpoint_path;
  std::int64_t checkpoint_every_steps = 0;
  double checkpoint_every_seconds = 0;
  CheckpointOutput output;     // target and partial (bytes and hashes are filled in at each checkpoint)
  json scene_document;         // the scene as loaded, recorded in checkpoints
  std::string version;         // lgi's, recorded in checkpoints
  const Checkpoint* resume = nullptr;  // continue this run (csv already holds its rows)
  std::string resume_path;             // the file `resume` was read from (for messages)
  // Called once the checkpoint `resume` was checked against the scene and the stepper, before the first step: what
  // a resume changes on disk (the checkpoint moved to the new rows file, the old one removed) happens here, so that
  // a checkpoint refused by those checks changes nothing. false (with the reason): the run does not start
  // (StopReason::write_failed).
  std::function<bool(std::string& error)> resume_accepted;
  RunObserver* observer = nullptr;     // in-run observation (see the header); csv, checkpoints, resume: none
};

// Why a run that did not complete stopped (RunStatus::stopped, or step_failed for left_domain).
enum class StopReason : std::uint8_t {
  none,
  signal,            // *RunOptions::stop became non-zero
  max_steps,         // the scene's limits.max_steps (adaptive runs without it: 1e9 attempted steps)
  max_wall_seconds,  // the scene's limits.max_wall_seconds
  left_domain,       // the Euler-angle top: sin θ fell below min_sin_theta
  write_failed,      // a row or a checkpoint could not be written (a full disk, ...): nothing more is written
};

struct InvariantChange {
  std::string name;
  double initial, final;
};

struct RunReport {
  IntegrationSummary summary;
  std::int64_t expected_steps = 0;
  State<double> final_state;
  double energy_initial = 0, energy_final = 0;
  std::vector<InvariantChange> invariants;  // the problem's own, initial and final values
  double wall_seconds = 0;
  std::int64_t newton_iterations = -1;  // implicit methods only (this invocation's)
  bool write_failed = false;            // the CSV stream reported an error
  StopReason stop_reason = StopReason::none;
  std::int64_t session_steps = 0;       // steps taken by this invocation (a resumed run: since the checkpoint)
  std::int64_t rejected = -1;           // adaptive runs: rejected trial steps (this invocation's)
  std::int64_t attempts = -1;           // adaptive runs: attempted steps (this invocation's)
  bool final_row = false;               // an incomplete run: a last row with the last good state was added
  bool has_rows = false;                // the output has rows (not only its header)
  std::int64_t rows_not_finite = 0;     // rows not written because a column was not finite
  double first_not_finite_t = 0;
  std::string checkpoint_written;       // the checkpoint written where the run stopped (empty: none)
  std::string checkpoint_error;         // why a checkpoint could not be written (empty: none failed)
  std::int64_t checkpoints = 0;         // checkpoints written by this invocation
  std::string checkpoint_checksum;      // the checksum of the last checkpoint this invocation wrote (empty: none)
  // The columns of the run's last row (those of csv_header), whether or not rows were written: what a sweep
  // records as the member's "final" group, character for character the row `lgi run` writes.
  std::vector<double> final_columns;
};

RunReport run_scene(const Scene& scene, const RunOptions& options);

// An estimate of the global error of a completed run at its last state (`lgi run --error-estimate`), from a second
// run of the scene compared with it at the same time:
//   fixed steps, a method of order p (free_body_order on torque-free problems): the run with 2·dt, Richardson's
//     err(x_h) ≈ |x_h − x_2h| / (2^p − 1) (the second run costs about half the first); with dt/2 instead when 2·dt
//     exceeds t_end or the run with 2·dt fails (a step beyond an implicit method's limit), err(x_h) ≈ |x_h − x_{h/2}|
//     · 2^p / (2^p − 1);
//   adaptive steps: the run with rtol and atol divided by 1000 (rtol not below 10 ε): err(x) ≈ |x − x_tight|.
// |·| is measured as R's rotation angle |log(R_bᵀ R_a)| (radians) and |Ω_a − Ω_b| / max(|Ω_a|, |Ω0|), a the run's
// state (relative to the initial speed when the motion slows down: a slew brought to rest). Assumes the asymptotic
// regime of the method (an error ∝ h^p, or a tight run ≫ more accurate): within a factor 10 of the true error on the
// random tops of tests/cli/test_error_estimate.cpp. Not available for the exact solution (no truncation error), a run
// that did not complete, or a comparison run that did not.
struct ErrorEstimate {
  bool available = false;
  double R = 0;      // estimated error of the attitude at t, radians
  double Omega = 0;  // estimated error of Ω at t, relative to max(|Ω(t)|, |Ω0|)
  double t = 0;      // the time compared (the run's last state)
  std::string how;   // e.g. "Richardson with dt = 0.02 (order 4)"; when not available: why
  double seconds = 0;  // the comparison run's wall time
};
// The difference of state a from state b that --error-estimate and auto's tolerance measure: R's rotation angle
// |log(b.Rᵀ a.R)| (radians) and |Ω_a − Ω_b| / max(|Ω_a|, omega_scale) (absolute when both are 0).
struct StateDifference {
  double angle = 0, omega = 0;
};
StateDifference state_difference(const State<double>& a, const State<double>& b, double omega_scale);

// `stop`: the comparison run stops when *stop becomes non-zero (then not available).
ErrorEstimate estimate_error(const Scene& scene, const RunReport& report,
                             const volatile std::sig_atomic_t* stop = nullptr);
// The summary's line for e (two spaces, "estimated error", the figures, how, and the comparison run's cost relative to
// the run's wall time).
std::string error_estimate_line(const ErrorEstimate& e, const RunReport& report);

// The few lines `lgi run` prints on stderr: method, steps, energy error, orthogonality, wall time.
std::string brief_report(const Scene& scene, const RunReport& report);

// The CSV header row for a scene's problem (without the newline).
std::string csv_header(const Scene& scene);
// The header `lgi run` writes: the scene's "output.columns" (output_columns.hpp), or csv_header without them.
std::string output_header(const Scene& scene);

// The names of the problem's integrals of the motion among its CSV columns (RunReport::invariants): all of its
// invariants, but for the Euler-angle top, whose last columns are coordinates (sin_theta, phi, theta, psi).
std::vector<std::string> integral_names(const Scene& scene);

// The columns of a row (csv_header) for state x at time t, as `lgi run` computes them from a state on SO(3) (not
// for the Euler-angle top, whose columns come from its angles: std::logic_error).
std::vector<double> state_columns(const Scene& scene, double t, const State<double>& x);

}  // namespace lgi::app
