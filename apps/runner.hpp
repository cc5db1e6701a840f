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
// or a budget stops the run, and RunOptions::resume continues one bit for bit (runner_drive.hpp).
// docs/checkpoints.md has the whole contract.
#pragma once

#include "runner_checkpoint.hpp"
#include "scene.hpp"

#include <lgi/core/driver.hpp>

#include <csignal>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace lgi::app {

struct RunOptions {
  std::FILE* csv = nullptr;                         // rows go here; nullptr: no rows
  bool progress = false;                            // a progress line on stderr (for terminals)
  const volatile std::sig_atomic_t* stop = nullptr;  // the run stops when *stop becomes non-zero
  // Long runs flush the rows at least this often (wall seconds; checked with the monitor, every 1024 steps).
  double flush_seconds = 1.0;
  // Checkpoints (runner_checkpoint.hpp), when checkpoint_path is not empty: every checkpoint_every_steps steps
  // or checkpoint_every_seconds of wall time (checked every 1024 steps; adaptive runs: 1024 attempted steps),
  // and where a signal or a budget stops the run. csv must then be the file output.partial names.
  std::string checkpoint_path;
  std::int64_t checkpoint_every_steps = 0;
  double checkpoint_every_seconds = 0;
  CheckpointOutput output;     // target and partial (bytes and hashes are filled in at each checkpoint)
  json scene_document;         // the scene as loaded, recorded in checkpoints
  std::string version;         // lgi's, recorded in checkpoints
  const Checkpoint* resume = nullptr;  // continue this run (csv already holds its rows)
};

// Why a run that did not complete stopped (RunStatus::stopped, or step_failed for left_domain).
enum class StopReason : std::uint8_t {
  none,
  signal,            // *RunOptions::stop became non-zero
  max_steps,         // the scene's limits.max_steps (adaptive runs without it: 1e9 attempted steps)
  max_wall_seconds,  // the scene's limits.max_wall_seconds
  left_domain,       // the Euler-angle top: sin θ fell below min_sin_theta
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
};

RunReport run_scene(const Scene& scene, const RunOptions& options);

// The few lines `lgi run` prints on stderr: method, steps, energy error, orthogonality, wall time.
std::string brief_report(const Scene& scene, const RunReport& report);

// The CSV header row for a scene's problem (without the newline).
std::string csv_header(const Scene& scene);

}  // namespace lgi::app
