// lgi/apps/runner_detail.hpp — what the runner's translation units share (internal to apps/).
//
// A run is compiled once (apps/session.cpp) against two interfaces: lgi::Integrator (core/engine.hpp), the scene's
// method on its problem, and ProblemRunner below, the problem's columns and hooks. Only these are compiled per
// problem: every method that applies to it (with and without projection), in the problem's registration
// (problem_model.hpp: apps/problems/ID.cpp, or a plugin); the scene's ProblemModel makes its runner.
#pragma once

#include "runner.hpp"

#include <lgi/core/engine.hpp>
#include <lgi/core/so3.hpp>

#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace lgi::app {

namespace runner_detail {

// What a run needs of its problem, behind an interface (runner_impl.hpp implements it once per problem type, in
// the runner parts; the session, apps/session.cpp, is compiled once).
class ProblemRunner {
 public:
  virtual ~ProblemRunner() = default;
  // The scene's method on this problem (projected when the scene asks for it).
  virtual std::unique_ptr<Integrator> integrator(const Scene& scene) const = 0;
  // The columns of a row (csv_header) at time t: of the integrator's slot s, or of the scene's initial state as
  // given (no round trip through a stepper's coordinates).
  virtual void columns(double t, const Integrator& engine, Slot s, std::vector<double>& out) const = 0;
  virtual void initial_columns(const Scene& scene, double t, std::vector<double>& out) const = 0;
  // Before the first step: false when the run cannot start (the report says why and holds the final values).
  virtual bool start(const Scene&, RunReport&) const { return true; }
  // After the run: what the problem adds to the report.
  virtual void finish(const Scene&, const Integrator&, RunReport&) const {}
};

// The runner of problem P with the scene's parameters: instantiated once per problem in the runner parts.
template <class P>
std::unique_ptr<ProblemRunner> make_problem_runner(const P& problem);

// One invocation of a run (apps/session.cpp).
RunReport run_session(const ProblemRunner& problem, const Scene& scene, const RunOptions& options);

using Clock = std::chrono::steady_clock;

// Formats one CSV row into a fixed buffer and hands it to the output as one record, or hands the row's numbers to a
// RowSink (runner.hpp): no allocation per row. A row with a column that is not finite is not written (counted, with
// the time of the first): no NaN or infinity reaches the output. After the output's first failed write no row is
// written (failed()).
class RowWriter {
 public:
  explicit RowWriter(OutputFile* out, RowSink* sink = nullptr) : out_(out), sink_(sink) {
    if (sink_) values_.reserve(64);
  }
  void add(double x) {
    if (columns_++ == 0) row_t_ = x;  // the first column is t
    finite_ = finite_ && std::isfinite(x);
    if (sink_) {
      values_.push_back(x);
      return;
    }
    if (n_ > 0) buf_[n_++] = ',';
    n_ = static_cast<std::size_t>(
        std::to_chars(buf_.data() + n_, buf_.data() + buf_.size(), x, std::chars_format::general, 17).ptr -
        buf_.data());
  }
  void end_row() {
    if (!finite_) {
      if (not_finite_++ == 0) first_not_finite_t_ = row_t_;
    } else {
      if (sink_) {
        sink_->row(values_);
      } else {
        buf_[n_++] = '\n';
        failed_ = !out_->write_record(std::string_view(buf_.data(), n_));
      }
      if (!failed_) {
        has_row_ = true;
        last_t_ = row_t_;
      }
    }
    n_ = 0;
    columns_ = 0;
    values_.clear();
    finite_ = true;
  }
  bool failed() const { return failed_; }
  // The time of the last row written (a resumed run: from its checkpoint).
  bool has_row() const { return has_row_; }
  double last_t() const { return last_t_; }
  void set_last_row(bool has, double t) {
    has_row_ = has;
    last_t_ = t;
  }
  std::int64_t not_finite() const { return not_finite_; }
  double first_not_finite_t() const { return first_not_finite_t_; }

 private:
  OutputFile* out_;
  RowSink* sink_;
  std::vector<double> values_;  // the row's numbers, for sink_
  std::array<char, 2048> buf_{};
  std::size_t n_ = 0;
  std::size_t columns_ = 0;
  bool failed_ = false;
  bool finite_ = true;
  bool has_row_ = false;
  double row_t_ = 0, last_t_ = 0, first_not_finite_t_ = 0;
  std::int64_t not_finite_ = 0;
};

// How many of P's invariants (the first ones) are integrals of the motion: P::integral_count where the problem
// declares it (the Euler-angle top: its last invariants are coordinates), else all of them.
template <class P>
constexpr std::size_t integral_count() {
  if constexpr (requires { P::integral_count; }) return P::integral_count;
  else return P::invariant_names.size();
}

// The monitor of one invocation: stops the run on a signal, when the wall-clock budget is spent, or after the
// output's first failed write; shows progress on stderr (RunOptions::progress: the simulated time, its fraction of
// t_end, steps per second, elapsed and remaining wall time) at most four times a second on a terminal, or every
// 2 s as lines, once a run has taken more than a second; flushes the rows every RunOptions::flush_seconds; and says when a checkpoint is due. The drivers
// call it after 1 step, then after the number of steps (adaptive runs: attempted steps) check() returns: doubled
// while the calls come faster than every `target_interval` and cut in proportion when they come slower, between 1
// and max_stride. So it runs about every 10 ms of work whatever a step costs (a step of a million DMV substeps,
// 0.2 s: every step) — the budget and signals are seen within max(10 ms, one step) — and at most once every
// max_stride steps: one clock read per call, nothing per step.
class SessionMonitor {
 public:
  enum class Action { proceed, stop, checkpoint };
  static constexpr std::int64_t max_stride = 1024;
  static constexpr double target_interval = 0.01;  // seconds
  // steps: those taken before this invocation.
  SessionMonitor(const RunOptions& options, const Scene& scene, std::int64_t steps);
  // steps taken and the simulated time reached.
  Action check(std::int64_t steps, double t);
  // The steps (attempted steps) until the next call, as set by the last check().
  std::int64_t stride() const { return stride_; }
  void checkpointed(std::int64_t steps);  // a checkpoint was written: the interval starts again
  void stop(StopReason reason) { reason_ = reason; }  // a checkpoint could not be written
  void finish() const;                    // clears the progress line
  StopReason reason() const { return reason_; }

 private:
  const RunOptions& options_;
  void show_progress(std::int64_t steps, double t, double seconds);
  double max_wall_seconds_;
  double t_end_;
  std::int64_t first_steps_ = -1;  // steps and simulated time at the first check(): the rate is measured from there
  double first_t_ = 0;
  Clock::time_point first_{};
  Clock::time_point start_ = Clock::now(), last_flush_ = start_, last_checkpoint_ = start_,
                    last_check_ = start_;
  std::int64_t checkpoint_steps_;
  std::int64_t stride_ = 1;
  ProgressLine progress_{options_.progress};
  StopReason reason_ = StopReason::none;
};

// Writes a run's checkpoints (runner_checkpoint.hpp) with what the runner knows at the time: the rows first (on
// disk), then the checkpoint that counts them. false on failure, with RunReport::checkpoint_error set; the
// previous checkpoint stays.
class Checkpointer {
 public:
  Checkpointer(const RunOptions& options, const Scene& scene) : options_(options), scene_(scene) {}
  bool enabled() const { return !options_.checkpoint_path.empty(); }
  // Flushes and fsyncs the rows, then writes the checkpoint for cursor c and the stepper's numbers.
  // `quaternion`: the last row's quaternion columns (output_columns.hpp; empty: none).
  bool write(const Cursor& c, std::span<const double> internal, double t, const State<double>& x, const RowWriter& rows,
             std::span<const double> quaternion, RunReport& report);

 private:
  const RunOptions& options_;
  const Scene& scene_;
};

}  // namespace runner_detail
}  // namespace lgi::app
