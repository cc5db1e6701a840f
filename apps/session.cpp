// lgi/apps/session.cpp — a run of `lgi run` or of a sweep's member, compiled once: the scene's integrator (built by
// its problem's runner, runner_impl.hpp) through the library's drivers, CSV rows at the output times, in-run
// observation, the monitor, checkpoints and resumes, and the run's report. Nothing here depends on the method or the
// problem's type: they are behind lgi::Integrator (core/engine.hpp) and ProblemRunner (runner_detail.hpp).
#include "runner_detail.hpp"

#include <lgi/core/engine.hpp>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace lgi::app {
namespace runner_detail {

namespace {

// The run's side of in-run observation (runner.hpp, RunObserver and StepAccess): the previous state for side-steps,
// the shadow trajectory, and which step led to each observed state, in the integrator's slots (previous, shadow,
// scratch). fixed: a fixed-step run (else side-steps and the shadow fail).
class Observation final : public StepAccess {
 public:
  Observation(Integrator& engine, const State<double>& x0, double dt, bool fixed)
      : engine_(engine), x0_(x0), dt_(dt), fixed_(fixed) {}

  // An event of the observed run (every step): `initial` is the initial state x0 at t = 0, else the engine's
  // Slot::event.
  void event(double t, bool initial, RunObserver& observer) {
    if (initial) {
      engine_.set(Slot::previous, x0_, 0.0);  // the run's own initial Internal
      t_prev_ = t_now_ = 0;
      n_prev_ = 0;
      last_ = x0_;
      observer.start(x0_, *this);
      return;
    }
    // The step just taken, with the driver's arguments: a grid step (n·dt, dt) or the final side-step to t_end.
    double tau = t - t_prev_;
    if (fixed_) {
      // the grid's events are at exactly (n + 1)·dt; t_end within 16 ulps of a grid point is on it (locate)
      if (t == static_cast<double>(n_prev_ + 1) * dt_) {
        tau = dt_;
        ++n_prev_;
      } else if (const lgi::detail::GridPoint at = lgi::detail::locate(0.0, dt_, t); at.on_grid && at.m == n_prev_ + 1) {
        tau = dt_;
        n_prev_ = at.m;
      }
    }
    if (shadow_active_ && shadow_ok_ && engine_.step(Slot::shadow, t_prev_, tau) != StepStatus::ok) shadow_ok_ = false;
    t_now_ = t;
    tau_ = tau;
    last_ = engine_.state(Slot::event);
    observer.step(t_prev_, t, last_, *this);
    engine_.copy(Slot::event, Slot::previous);
    t_prev_ = t;
  }
  // The run ended: its last observed state.
  void finish(RunObserver& observer) { observer.finish(t_prev_, last_, *this); }

  bool can_step() const override { return fixed_; }
  double step_size() const override { return tau_; }
  bool side_step(double tau, State<double>& x) override {
    if (!fixed_) return false;
    engine_.copy(Slot::previous, Slot::scratch);
    if (engine_.step(Slot::scratch, t_prev_, tau) != StepStatus::ok) return false;
    x = engine_.state(Slot::scratch);
    return true;
  }
  void shadow_set(const State<double>& x) override {
    engine_.set(Slot::shadow, x, t_now_);
    shadow_active_ = true;
    shadow_ok_ = fixed_;
  }
  bool shadow_ok() const override { return shadow_active_ && shadow_ok_; }
  State<double> shadow_state() const override { return engine_.state(Slot::shadow); }

 private:
  Integrator& engine_;
  State<double> x0_;
  double dt_;
  bool fixed_;
  double t_prev_ = 0, t_now_ = 0, tau_ = 0;
  std::int64_t n_prev_ = 0;
  State<double> last_;
  bool shadow_active_ = false, shadow_ok_ = false;
};

// Where a row's state comes from.
enum class From : std::uint8_t { initial, event, current };

// The session: rows, observation, the monitor and checkpoints, as the drivers' RunSink.
class Session final : public RunSink {
 public:
  Session(const ProblemRunner& problem, Integrator& engine, const Scene& scene, const RunOptions& options,
          RunReport& report, std::int64_t steps_before)
      : problem_(problem), engine_(engine), scene_(scene), options_(options), report_(report),
        rows_(options.csv, options.rows), observation_(engine, scene.initial, scene.dt, !(scene.options.rtol > 0)),
        monitor_(options, scene, steps_before),
        checkpointer_(options, scene), numbers_(engine.state_size()) {}

  RowWriter& rows() { return rows_; }
  ColumnMapper& mapper() { return mapper_; }
  SessionMonitor& monitor() { return monitor_; }
  Checkpointer& checkpointer() { return checkpointer_; }
  Observation& observation() { return observation_; }

  // A row at time t (and the observer's event): `from` says whose state.
  void row(double t, From from) {
    if (options_.observer && from != From::current) observation_.event(t, from == From::initial, *options_.observer);
    if (!options_.csv && !options_.rows) return;
    columns_.clear();
    if (from == From::initial) problem_.initial_columns(scene_, t, columns_);
    else problem_.columns(t, engine_, from == From::event ? Slot::event : Slot::current, columns_);
    if (!scene_.columns.empty()) {
      chosen_.clear();
      mapper_.map(columns_, chosen_);
      for (const double v : chosen_) rows_.add(v);
    } else {
      for (const double v : columns_) rows_.add(v);
    }
    rows_.end_row();
  }

  // A checkpoint of the current state at cursor `at`; false when it could not be written.
  bool checkpoint(const Cursor& at) {
    engine_.save(Slot::current, numbers_);
    const double t = at.adaptive ? at.t : static_cast<double>(at.n) * scene_.dt;
    const bool ok =
        checkpointer_.write(at, numbers_, t, engine_.state(Slot::current), rows_, mapper_.previous_quaternion(), report_);
    if (ok) monitor_.checkpointed(at.steps);
    return ok;
  }

  void observe(double t, bool initial) override { row(t, initial ? From::initial : From::event); }
  std::int64_t check(const Cursor& at) override {
    switch (monitor_.check(at.steps, at.adaptive ? at.t : static_cast<double>(at.n) * scene_.dt)) {
      case SessionMonitor::Action::stop: return 0;
      case SessionMonitor::Action::checkpoint:
        if (!checkpoint(at)) {  // the first failed write stops the run; the last checkpoint stays
          monitor_.stop(StopReason::write_failed);
          return 0;
        }
        break;
      case SessionMonitor::Action::proceed: break;
    }
    return monitor_.stride();
  }

 private:
  const ProblemRunner& problem_;
  Integrator& engine_;
  const Scene& scene_;
  const RunOptions& options_;
  RunReport& report_;
  RowWriter rows_;
  Observation observation_;
  SessionMonitor monitor_;
  Checkpointer checkpointer_;
  std::vector<double> numbers_;
  std::vector<double> columns_;
  ColumnMapper mapper_{scene_.columns};  // "output.columns"
  std::vector<double> chosen_;
};

// The columns' energy and integrals into the report (initial or final values).
void report_values(const std::vector<double>& columns, std::size_t integrals, double& energy,
                   std::vector<InvariantChange>& invariants, const std::vector<std::string>& names, bool initial) {
  energy = columns[13];
  for (std::size_t i = 0; i < integrals; ++i) {
    if (initial) invariants.push_back({names[i], columns[15 + i], 0.0});
    else invariants[i].final = columns[15 + i];
  }
}

}  // namespace

// One invocation of a run, fresh or resumed: the integrator from the checkpoint's state or the scene's, the
// drivers (drive_grid, drive_adaptive) through Integrator::run_*, rows at the output times, and where the run ends
// early — a failed step, a signal, a budget — a checkpoint (signal or budget, when asked for) and a last row with
// the last good state.
RunReport run_session(const ProblemRunner& problem, const Scene& scene, const RunOptions& options) {
  RunReport report;
  report.expected_steps = static_cast<std::int64_t>(std::ceil(scene.t_end / scene.dt - 1e-9));
  if (options.csv && !options.resume && !options.csv->write_record(output_header(scene) + "\n")) report.write_failed = true;
  const std::vector<std::string> names = integral_names(scene);
  std::vector<double> columns;
  problem.initial_columns(scene, 0.0, columns);
  report_values(columns, names.size(), report.energy_initial, report.invariants, names, true);
  const std::unique_ptr<Integrator> engine = problem.integrator(scene);
  engine->set(Slot::current, scene.initial, 0.0);
  if (!problem.start(scene, report)) {  // no state to start from (the Euler-angle top at its singularity)
    for (InvariantChange& inv : report.invariants) inv.final = inv.initial;
    if (options.observer) {  // observed: the initial state alone
      Observation observation(*engine, scene.initial, scene.dt, true);
      observation.event(0.0, true, *options.observer);
      observation.finish(*options.observer);
    }
    return report;
  }
  const bool adaptive = scene.options.rtol > 0;
  if (adaptive && !engine->adaptive()) throw std::logic_error("lgi: rtol given to a method without an embedded pair");

  // adaptive runs: the output times (t_end included), options.every N as every N accepted steps. An observed run
  // (RunOptions::observer) has an event after every step instead.
  const bool observing = options.observer != nullptr;
  std::vector<double> times = observing ? std::vector<double>{} : scene.output_times;
  if (times.empty() || times.back() < scene.t_end) times.push_back(scene.t_end);
  AdaptiveOptions adaptive_options;
  if (observing) adaptive_options.every = 1;
  else if (scene.output_times.empty() && scene.output_every > 0) adaptive_options.every = scene.output_every;
  adaptive_options.check();
  const std::int64_t every = observing ? 1 : scene.output_every > 0 ? scene.output_every : std::int64_t{1} << 62;
  const bool at_times = !scene.output_times.empty() && !observing;
  const GridEvents<double> events = at_times ? GridEvents<double>(std::span<const double>(times), 0.0, scene.dt)
                                             : GridEvents<double>(every, 0.0, scene.t_end, scene.dt);

  Cursor c;
  if (const Checkpoint* ck = options.resume) {
    if (ck->internal.size() != engine->state_size() || ck->cursor.adaptive != adaptive)
      throw InputError(options.resume_path + ": /internal: " + std::to_string(ck->internal.size()) +
                       " numbers for a stepper of method " + std::string(scene.method->traits.name) + " that keeps " +
                       std::to_string(engine->state_size()) + (adaptive ? " (adaptive)" : " (fixed steps)") +
                       ": written by another version of lgi?");
    engine->restore(Slot::current, ck->internal);
    c = ck->cursor;
    // The cursor must be a place this scene's run passes through (the checksum guards against damage; this
    // against a checkpoint of another scene's run pasted in).
    const auto bad_cursor = [&](const std::string& what) {
      throw InputError(options.resume_path + ": /cursor: " + what + " (not a place this scene's run passes through)");
    };
    if (adaptive) {
      if (!(c.t <= scene.t_end)) bad_cursor("t = " + format_number(c.t) + " beyond t_end = " + format_number(scene.t_end));
      if (c.next > static_cast<std::int64_t>(times.size()))
        bad_cursor("next output " + std::to_string(c.next) + " of " + std::to_string(times.size()));
      if (c.next > 0 && times[static_cast<std::size_t>(c.next - 1)] > c.t)
        bad_cursor("output time " + format_number(times[static_cast<std::size_t>(c.next - 1)]) + " not yet reached at t = " +
                   format_number(c.t));
    } else {
      const lgi::detail::GridPoint end = lgi::detail::locate(0.0, scene.dt, scene.t_end);
      if (c.n > end.m) bad_cursor("grid index n = " + std::to_string(c.n) + " beyond t_end (" + std::to_string(end.m) + ")");
      if (!events.accepts(c.n, c.event))
        throw InputError(options.resume_path + ": /cursor/event: output event " + std::to_string(c.event) +
                         " does not follow grid index n = " + std::to_string(c.n) +
                         " (not a place this scene's run passes through)");
    }
  } else if (adaptive) {
    c = adaptive_start(0.0, scene.dt, adaptive_options);
    while (static_cast<std::size_t>(c.next) < times.size() && times[static_cast<std::size_t>(c.next)] == 0.0) ++c.next;
  }

  Session session(problem, *engine, scene, options, report, c.steps);
  if (options.resume) {
    session.rows().set_last_row(options.resume->has_last_row, options.resume->last_row_t);
    session.mapper().set_previous_quaternion(options.resume->output_quaternion);
    if (options.resume_accepted && !options.resume_accepted(report.checkpoint_error)) {
      report.summary.status = RunStatus::stopped;
      report.summary.steps = c.steps;
      report.summary.t = adaptive ? c.t : static_cast<double>(c.n) * scene.dt;
      report.stop_reason = StopReason::write_failed;
      report.final_state = engine->state(Slot::current);
      return report;
    }
  } else {
    session.row(0.0, From::initial);
  }
  const Cursor start = c;

  IntegrationSummary summary;
  bool moved = false;
  Halt halt = Halt::none;
  const auto clock_start = Clock::now();
  if (adaptive) {
    const std::int64_t budget = scene.max_steps > 0 ? scene.max_steps : adaptive_options.max_steps;
    halt = engine->run_adaptive(std::span<const double>(times), std::abs(scene.t_end), adaptive_options,
                                start.attempts + budget, c, summary, moved, session);
  } else {
    const std::int64_t limit =
        scene.max_steps > 0 ? start.steps + scene.max_steps : std::numeric_limits<std::int64_t>::max();
    halt = engine->run_grid(scene.dt, events, limit, c, summary, moved, session);
  }
  report.wall_seconds = std::chrono::duration<double>(Clock::now() - clock_start).count();
  session.monitor().finish();

  report.summary = summary;
  report.session_steps = c.steps - start.steps;
  if (adaptive) {
    report.attempts = c.attempts - start.attempts;
    report.rejected = c.rejected - start.rejected;
  }
  if (halt == Halt::monitor) report.stop_reason = session.monitor().reason();
  if (halt == Halt::budget) report.stop_reason = StopReason::max_steps;
  // A checkpoint where a signal or a budget stopped the run — not after a failed write: the rows it would count
  // did not all reach the file, and the last checkpoint written still counts only rows that did.
  if ((halt == Halt::monitor || halt == Halt::budget) && report.stop_reason != StopReason::write_failed &&
      session.checkpointer().enabled() && session.checkpoint(c))
    report.checkpoint_written = options.checkpoint_path;
  RowWriter& rows = session.rows();
  if (halt != Halt::none && (options.csv || options.rows) && !(rows.has_row() && rows.last_t() == summary.t)) {
    session.row(summary.t, moved ? From::current : From::initial);  // the last good state, the file's last row
    report.final_row = true;
  }
  report.has_rows = rows.has_row();
  report.rows_not_finite = rows.not_finite();
  report.first_not_finite_t = rows.first_not_finite_t();
  report.write_failed = report.write_failed || rows.failed();
  if (options.observer) session.observation().finish(*options.observer);

  report.final_state = moved ? engine->state(Slot::current) : scene.initial;
  columns.clear();
  if (moved) problem.columns(summary.t, *engine, Slot::current, columns);
  else problem.initial_columns(scene, summary.t, columns);
  report.final_columns = columns;
  report_values(columns, names.size(), report.energy_final, report.invariants, names, false);
  report.newton_iterations = engine->newton_iterations();
  problem.finish(scene, *engine, report);
  return report;
}

}  // namespace runner_detail

RunReport run_scene(const Scene& scene, const RunOptions& options) {
  const std::unique_ptr<runner_detail::ProblemRunner> problem = scene.problem->runner();
  return runner_detail::run_session(*problem, scene, options);
}

}  // namespace lgi::app
