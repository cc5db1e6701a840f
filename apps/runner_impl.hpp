// lgi/apps/runner_impl.hpp — the runner's templates: a scene's stepper through the drivers, CSV rows at the
// output times, the run report. Included only by the runner parts (runner_part.cpp.in), each of which
// instantiates run_problem for one problem; see runner_detail.hpp for why.
#pragma once

#include "runner_detail.hpp"

#include <lgi/core/invariants.hpp>
#include <lgi/integrators/adaptive.hpp>
#include <lgi/integrators/projection.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

namespace lgi::app {
namespace runner_detail {

// The stepper's numbers (runner_checkpoint.hpp), for a checkpoint.
template <class Internal>
std::array<double, internal_size<Internal>()> numbers_of(const Internal& y) {
  std::array<double, internal_size<Internal>()> a{};
  std::size_t i = 0;
  for_each_number(y, [&](const double& v) { a[i++] = v; });
  return a;
}

// The run's side of in-run observation (runner.hpp, RunObserver and StepAccess): the previous state for side-steps,
// the shadow trajectory, and which step led to each observed state. S: the run's stepper; from_state(x, t) its
// Internal for a State (Stepper::to_internal). fixed: a fixed-step run (else side-steps and the shadow fail).
template <class S, class FromState>
class Observation final : public StepAccess {
 public:
  using Internal = typename S::Internal;
  Observation(S& stepper, FromState from_state, double dt, bool fixed)
      : stepper_(stepper), from_state_(from_state), dt_(dt), fixed_(fixed) {}

  // An event of the observed run (every step): y nullptr is the initial state x0 at t = 0.
  void event(double t, const Internal* y, const State<double>& x0, RunObserver& observer) {
    if (!y) {
      prev_ = from_state_(x0, 0.0);  // the run's own initial Internal
      t_prev_ = t_now_ = 0;
      n_prev_ = 0;
      last_ = x0;
      observer.start(x0, *this);
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
    if (shadow_active_ && shadow_ok_ && step_once(shadow_, t_prev_, tau) != StepStatus::ok) shadow_ok_ = false;
    t_now_ = t;
    tau_ = tau;
    last_ = stepper_.to_state(*y);
    observer.step(t_prev_, t, last_, *this);
    prev_ = *y;
    t_prev_ = t;
  }
  // The run ended: its last observed state.
  void finish(RunObserver& observer) { observer.finish(t_prev_, last_, *this); }

  bool can_step() const override { return fixed_; }
  double step_size() const override { return tau_; }
  bool side_step(double tau, State<double>& x) override {
    if (!fixed_) return false;
    Internal z = prev_;
    if (step_once(z, t_prev_, tau) != StepStatus::ok) return false;
    x = stepper_.to_state(z);
    return true;
  }
  void shadow_set(const State<double>& x) override {
    shadow_ = from_state_(x, t_now_);
    shadow_active_ = true;
    shadow_ok_ = fixed_;
  }
  bool shadow_ok() const override { return shadow_active_ && shadow_ok_; }
  State<double> shadow_state() const override { return stepper_.to_state(shadow_); }

 private:
  // One call site of the (large, flattened) step for the shadow and the side-steps: compile time.
  [[gnu::noinline]] StepStatus step_once(Internal& z, double t, double h) { return stepper_.step(z, t, h); }

  S& stepper_;
  FromState from_state_;
  double dt_;
  bool fixed_;
  Internal prev_{}, shadow_{};
  double t_prev_ = 0, t_now_ = 0, tau_ = 0;
  std::int64_t n_prev_ = 0;
  State<double> last_;
  bool shadow_active_ = false, shadow_ok_ = false;
};

// One invocation of a run, fresh or resumed, through the library's drivers (drive_grid, drive_adaptive): rows at the output times
// (row(t, y), y nullptr for the initial state), the monitor (signals, wall-clock budget, flushing, periodic
// checkpoints), and where the run ends early — a failed step, a signal, a budget — a checkpoint (signal or budget,
// when asked for) and a last row with the last good state. S: a Stepper, or an AdaptiveStepper when the scene
// gave rtol and atol; to_state(y) for the checkpoint's readable state and the report.
// y: the initial state on entry, the last good state on return; returns whether y moved (else: use the initial
// state as given, no round trip through the stepper's coordinates).
template <class S, class Row>
bool run_session(S& stepper, typename S::Internal& y, const Scene& scene, const RunOptions& options, Row& row,
                 RowWriter& rows, RunReport& report) {
  using Internal = typename S::Internal;
  constexpr bool can_adapt = AdaptiveStepper<S>;
  const bool adaptive = scene.options.rtol > 0;
  if (adaptive && !can_adapt) throw std::logic_error("lgi: rtol given to a method without an embedded pair");

  // adaptive runs: the output times (t_end included), options.every N as every N accepted steps. An observed run
  // (RunOptions::observer) has an event after every step instead.
  const bool observing = options.observer != nullptr;
  std::vector<double> times = observing ? std::vector<double>{} : scene.output_times;
  if (times.empty() || times.back() < scene.t_end) times.push_back(scene.t_end);
  AdaptiveOptions adaptive_options;
  if (observing) adaptive_options.every = 1;
  else if (scene.output_times.empty() && scene.output_every > 0) adaptive_options.every = scene.output_every;
  adaptive_options.check();

  Cursor c;
  if (const Checkpoint* ck = options.resume) {
    if (ck->internal.size() != internal_size<Internal>() || ck->cursor.adaptive != adaptive)
      throw InputError(options.resume_path + ": /internal: " + std::to_string(ck->internal.size()) +
                       " numbers for a stepper of method " + std::string(scene.method->traits.name) + " that keeps " +
                       std::to_string(internal_size<Internal>()) + (adaptive ? " (adaptive)" : " (fixed steps)") +
                       ": written by another version of lgi?");
    std::size_t i = 0;
    for_each_number(y, [&](double& v) { v = ck->internal[i++]; });
    c = ck->cursor;
    rows.set_last_row(ck->has_last_row, ck->last_row_t);
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
    }
  } else {
    row(0.0, static_cast<const Internal*>(nullptr));
    if (adaptive) {
      c = adaptive_start(0.0, scene.dt, adaptive_options);
      while (static_cast<std::size_t>(c.next) < times.size() && times[static_cast<std::size_t>(c.next)] == 0.0) ++c.next;
    }
  }
  if (options.resume) {  // the fixed-step cursor against the output events: checked by the drive below, first
    if (!adaptive) {
      const bool ok = !scene.output_times.empty() && !observing
                          ? GridEvents<double>(std::span<const double>(times), 0.0, scene.dt).accepts(c.n, c.event)
                          : GridEvents<double>(observing ? 1 : scene.output_every > 0 ? scene.output_every : std::int64_t{1} << 62,
                                               0.0, scene.t_end, scene.dt)
                                .accepts(c.n, c.event);
      if (!ok)
        throw InputError(options.resume_path + ": /cursor/event: output event " + std::to_string(c.event) +
                         " does not follow grid index n = " + std::to_string(c.n) +
                         " (not a place this scene's run passes through)");
    }
    if (options.resume_accepted && !options.resume_accepted(report.checkpoint_error)) {
      report.summary.status = RunStatus::stopped;
      report.summary.steps = c.steps;
      report.summary.t = adaptive ? c.t : static_cast<double>(c.n) * scene.dt;
      report.stop_reason = StopReason::write_failed;
      return true;
    }
  }
  const Cursor start = c;

  SessionMonitor session(options, scene, adaptive ? 0 : report.expected_steps, c.steps);
  Checkpointer checkpointer(options, scene);
  const auto checkpoint = [&](const Cursor& at, const Internal& z) {
    const auto numbers = numbers_of(z);
    const double t = at.adaptive ? at.t : static_cast<double>(at.n) * scene.dt;
    const bool ok = checkpointer.write(at, numbers, t, stepper.to_state(z), rows, report);
    if (ok) session.checkpointed(at.steps);
    return ok;
  };
  // The drivers' monitor (core/driver.hpp, DriveMonitor): after the first step, then after the steps it returns; 0
  // stops the run.
  struct {
    SessionMonitor& session;
    decltype(checkpoint)& write;
    std::int64_t first(const Cursor&) const { return 1; }
    std::int64_t operator()(const Cursor& at, const Internal& z) {
      switch (session.check(at.steps)) {
        case SessionMonitor::Action::stop: return 0;
        case SessionMonitor::Action::checkpoint:
          if (!write(at, z)) {  // the first failed write stops the run; the last checkpoint stays
            session.stop(StopReason::write_failed);
            return 0;
          }
          break;
        case SessionMonitor::Action::proceed: break;
      }
      return session.stride();
    }
  } monitor{session, checkpoint};

  IntegrationSummary summary;
  bool moved = false;
  Halt halt = Halt::none;
  const auto clock_start = Clock::now();
  if constexpr (can_adapt) {
    if (adaptive) {
      const std::int64_t budget = scene.max_steps > 0 ? scene.max_steps : adaptive_options.max_steps;
      halt = drive_adaptive(stepper, y, std::span<const double>(times), std::abs(scene.t_end), adaptive_options,
                            start.attempts + budget, c, summary, moved, row, monitor);
    }
  }
  if (!adaptive) {
    const std::int64_t limit =
        scene.max_steps > 0 ? start.steps + scene.max_steps : std::numeric_limits<std::int64_t>::max();
    const auto drive = [&](const GridEvents<double>& events) {
      return drive_grid(stepper, y, 0.0, scene.dt, events, limit, c, summary, moved, row, monitor);
    };
    if (!scene.output_times.empty() && !observing) {
      halt = drive(GridEvents<double>(std::span<const double>(times), 0.0, scene.dt));
    } else {
      const std::int64_t every = observing               ? 1
                                 : scene.output_every > 0 ? scene.output_every
                                                          : std::int64_t{1} << 62;
      halt = drive(GridEvents<double>(every, 0.0, scene.t_end, scene.dt));
    }
  }
  report.wall_seconds = std::chrono::duration<double>(Clock::now() - clock_start).count();
  session.finish();

  report.summary = summary;
  report.session_steps = c.steps - start.steps;
  if (adaptive) {
    report.attempts = c.attempts - start.attempts;
    report.rejected = c.rejected - start.rejected;
  }
  if (halt == Halt::monitor) report.stop_reason = session.reason();
  if (halt == Halt::budget) report.stop_reason = StopReason::max_steps;
  // A checkpoint where a signal or a budget stopped the run — not after a failed write: the rows it would count
  // did not all reach the file, and the last checkpoint written still counts only rows that did.
  if ((halt == Halt::monitor || halt == Halt::budget) && report.stop_reason != StopReason::write_failed &&
      checkpointer.enabled() && checkpoint(c, y))
    report.checkpoint_written = options.checkpoint_path;
  if (halt != Halt::none && options.csv && !(rows.has_row() && rows.last_t() == summary.t)) {
    row(summary.t, moved ? &y : nullptr);  // the last good state, the file's last row
    report.final_row = true;
  }
  report.has_rows = rows.has_row();
  report.rows_not_finite = rows.not_finite();
  report.first_not_finite_t = rows.first_not_finite_t();
  report.write_failed = report.write_failed || rows.failed();
  return moved;
}

// The scene's stepper S: Method<P>, or Projected<Method<P>> when the scene asks for projection.
template <class S, class P>
RunReport run_stepper(S& stepper, const P& problem, const Scene& scene, const RunOptions& options) {
  using Internal = typename S::Internal;
  RunReport report;
  report.expected_steps = static_cast<std::int64_t>(std::ceil(scene.t_end / scene.dt - 1e-9));
  RowWriter rows(options.csv);
  if (options.csv && !options.resume && !options.csv->write_record(header_for<P>() + "\n")) report.write_failed = true;
  const State<double>& x0 = scene.initial;
  const auto from_state = [&stepper](const State<double>& x, double t) { return stepper.to_internal(x, t); };
  Observation<S, decltype(from_state)> observation(stepper, from_state, scene.dt, !(scene.options.rtol > 0));
  // The columns of a row (csv_header) at time t, state y (nullptr: the initial state as given), one add(v) each.
  const auto columns = [&](double t, const Internal* y, auto&& add) {
    const State<double> x = y ? stepper.to_state(*y) : x0;
    add(t);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) add(x.R(r, c));
    for (int i = 0; i < 3; ++i) add(x.Omega(i));
    add(energy_at(problem, t, x));
    add(so3::orthogonality_error(x.R));
    for (const double v : invariants_at(problem, t, x)) add(v);
  };
  auto row = [&](double t, const Internal* y) {
    if (options.observer) observation.event(t, y, x0, *options.observer);
    if (!options.csv) return;
    columns(t, y, [&](double v) { rows.add(v); });
    rows.end_row();
  };
  report.energy_initial = energy_at(problem, 0.0, x0);
  const auto inv0 = invariants_at(problem, 0.0, x0);
  Internal y = stepper.to_internal(x0, 0.0);
  const bool moved = run_session(stepper, y, scene, options, row, rows, report);
  const State<double> x = moved ? stepper.to_state(y) : x0;
  columns(report.summary.t, moved ? &y : nullptr, [&](double v) { report.final_columns.push_back(v); });
  if (options.observer) observation.finish(*options.observer);
  report.final_state = x;
  report.energy_final = energy_at(problem, report.summary.t, x);
  const auto inv1 = invariants_at(problem, report.summary.t, x);
  for (std::size_t i = 0; i < inv0.size(); ++i)
    report.invariants.push_back({std::string(P::invariant_names[i]), inv0[i], inv1[i]});
  if constexpr (requires { stepper.newton_iterations(); }) report.newton_iterations = stepper.newton_iterations();
  return report;
}

template <template <class> class Method, class P>
RunReport run_with(const P& problem, const Scene& scene, const RunOptions& options) {
  if (scene.options.projection) {
    if constexpr (ProjectableStepper<Method<P>>) {  // the scene accepts "projection" only where traits list it
      Projected<Method<P>> stepper(problem, scene.options);
      return run_stepper(stepper, problem, scene, options);
    } else {
      throw std::logic_error("lgi: projection asked of a method that does not take it");
    }
  }
  Method<P> stepper(problem, scene.options);
  return run_stepper(stepper, problem, scene, options);
}

template <class P, template <class> class... Ms>
RunReport dispatch(const P& problem, const Scene& scene, const RunOptions& options, MethodList<Ms...>) {
  RunReport report;
  bool found = false;
  const auto try_method = [&]<template <class> class M>() {
    if constexpr (method_applies_v<M, P>) {
      if (!found && M<P>::traits.name == scene.method->traits.name) {
        report = run_with<M>(problem, scene, options);
        found = true;
      }
    }
  };
  (try_method.template operator()<Ms>(), ...);
  if (!found) throw std::logic_error("lgi: method registry out of sync");
  return report;
}

// The Euler-angle top's Runge–Kutta stepper for the drivers: the library's domain-checked step
// (CheckedEuclideanStep: a step whose result leaves sin θ ≥ min_sin_theta fails, the state untouched, and says so)
// with the problem's map to (R, Ω) for rows and observers.
template <const auto& Tableau>
struct EulerAngleSteps : CheckedEuclideanStep<EuclideanRk<Tableau, EulerAngleTop<double>>> {
  EulerAngleSteps(const EuclideanRk<Tableau, EulerAngleTop<double>>& rk, const EulerAngleTop<double>& p)
      : CheckedEuclideanStep<EuclideanRk<Tableau, EulerAngleTop<double>>>(rk), problem(p) {}
  const EulerAngleTop<double>& problem;
  State<double> to_state(const typename EulerAngleSteps::Internal& y) const { return problem.to_state(y); }
};

// The seed paper's Euler-angle top (problems/euler_angle_top.hpp): its state (φ, θ, ψ, φ', θ', m_ψ) is not
// on SO(3), so it runs on its own path — the scene's RKMK tableau as plain Runge–Kutta on the angles
// (integrators/euclidean_rk.hpp, apps/problems_paper.hpp) — with the standard columns (R by (6.3), Ω from
// the angle rates, the total energy) and the problem's own. A step that takes sin θ below min_sin_theta
// ends the run (status `stopped`, a warning with the time on stderr, the last admissible state kept).
template <const auto& Tableau>
RunReport run_euler_angles(const EulerAngleTop<double>& problem, const Scene& scene, const RunOptions& options) {
  using Vector = EulerAngleTop<double>::Vector;
  RunReport report;
  report.expected_steps = static_cast<std::int64_t>(std::ceil(scene.t_end / scene.dt - 1e-9));
  const EuclideanRk<Tableau, EulerAngleTop<double>> rk(problem);
  EulerAngleSteps<Tableau> stepper(rk, problem);
  RowWriter rows(options.csv);
  if (options.csv && !options.resume && !options.csv->write_record(header_for<EulerAngleTop<double>>() + "\n"))
    report.write_failed = true;
  const Vector y0 = problem.from_state(scene.initial);
  // Side-steps and the shadow trajectory of an observed run step a copy: a step of theirs that leaves the domain
  // does not mark the run.
  EulerAngleSteps<Tableau> observed_steps(rk, problem);
  const auto from_state = [&problem](const State<double>& x, double) { return problem.from_state(x); };
  Observation<EulerAngleSteps<Tableau>, decltype(from_state)> observation(observed_steps, from_state, scene.dt, true);
  const auto columns = [&](double t, const Vector* v, auto&& add) {
    const Vector& y = v ? *v : y0;
    const State<double> x = problem.to_state(y);
    add(t);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) add(x.R(r, c));
    for (int i = 0; i < 3; ++i) add(x.Omega(i));
    add(problem.energy(y));
    add(so3::orthogonality_error(x.R));
    for (const double v2 : problem.invariants(y)) add(v2);
  };
  auto row = [&](double t, const Vector* v) {
    if (options.observer) observation.event(t, v, scene.initial, *options.observer);
    if (!options.csv) return;
    columns(t, v, [&](double x) { rows.add(x); });
    rows.end_row();
  };
  const auto final_columns = [&](double t, const Vector* v) {
    columns(t, v, [&](double x) { report.final_columns.push_back(x); });
  };

  report.energy_initial = problem.energy(y0);
  const auto inv0 = problem.invariants(y0);
  if (!problem.admissible(y0)) {  // already at t = 0: no admissible state at all
    report.summary.status = RunStatus::stopped;
    report.stop_reason = StopReason::left_domain;
    std::fprintf(stderr,
                 "lgi: warning: %s: at t = 0 sin(theta) = %.3g < min_sin_theta = %s: the initial attitude is at the Euler "
                 "angles' coordinate singularity (symmetry axis near the laboratory e3); the run stops at t = 0 (the "
                 "same motion runs on SO(3) as problem.type heavy_top, or lower /problem/min_sin_theta)\n",
                 scene.file.c_str(), std::sin(value_of(y0[1])), format_number(problem.min_sin_theta).c_str());
    report.final_state = scene.initial;
    if (options.observer) {  // observed: the initial state alone
      observation.event(0.0, nullptr, scene.initial, *options.observer);
      observation.finish(*options.observer);
    }
    // The angle rates (hence the angle-form energy) are undefined at sin θ = 0: the energy of the same state
    // on SO(3) instead.
    report.energy_initial = report.energy_final = energy(problem.heavy_top(), scene.initial);
    final_columns(0.0, nullptr);
    return report;
  }
  Vector y = y0;
  const bool moved = run_session(stepper, y, scene, options, row, rows, report);
  final_columns(report.summary.t, moved ? &y : nullptr);
  if (options.observer) observation.finish(*options.observer);
  if (stepper.left() && report.summary.status == RunStatus::step_failed) {
    // t_outside: the time of the rejected state (sin θ < min_sin_theta); the last admissible one is kept.
    report.summary.status = RunStatus::stopped;
    report.summary.step_status = StepStatus::ok;
    report.stop_reason = StopReason::left_domain;
    std::fprintf(stderr,
                 "lgi: warning: %s: at t = %s sin(theta) falls below min_sin_theta = %s: the Euler angles are near "
                 "their coordinate singularity (symmetry axis near the laboratory e3); the run stops at t = %s, the "
                 "last admissible state (sin(theta) = %.3g there; the same motion runs on SO(3) as problem.type "
                 "heavy_top, or lower /problem/min_sin_theta)\n",
                 scene.file.c_str(), format_number(stepper.t_outside()).c_str(),
                 format_number(problem.min_sin_theta).c_str(), format_number(report.summary.t).c_str(),
                 std::sin(y[1]));
  }
  report.final_state = problem.to_state(y);
  report.energy_final = problem.energy(y);
  const auto inv1 = problem.invariants(y);
  for (std::size_t i = 0; i < integral_count<EulerAngleTop<double>>(); ++i)  // momentum_k, momentum_psi
    report.invariants.push_back({std::string(EulerAngleTop<double>::invariant_names[i]), inv0[i], inv1[i]});
  return report;
}

template <template <class> class... Ms>
RunReport dispatch(const EulerAngleTop<double>& problem, const Scene& scene, const RunOptions& options,
                   MethodList<Ms...>) {
  RunReport report;
  bool found = false;
  const auto try_method = [&]<template <class> class M>() {
    if constexpr (method_applies_v<M, EulerAngleTop<double>>) {
      using Tab = rkmk_tableau<M<FreeBody<double>>>;
      if (!found && Tab::tableau.name == scene.method->traits.name) {
        report = run_euler_angles<Tab::tableau>(problem, scene, options);
        found = true;
      }
    }
  };
  (try_method.template operator()<Ms>(), ...);
  if (!found) throw std::logic_error("lgi: method registry out of sync");
  return report;
}

}  // namespace runner_detail

template <class P>
RunReport run_problem(const P& problem, const Scene& scene, const RunOptions& options) {
  return runner_detail::dispatch(problem, scene, options, Methods{});
}

}  // namespace lgi::app
