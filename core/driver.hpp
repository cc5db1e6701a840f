/// \file
/// lgi/core/driver.hpp — the time loop: step a state through time, land on output times, stop and resume anywhere.
///
/// Time is t_n = t0 + n·h on a fixed grid, never a running sum (Boost.Odeint, integrate_const). An
/// output time that falls between grid points t_m < t_out < t_m+1 is reached by one extra step of size
/// t_out − t_m taken from a copy of the state: the main trajectory stays on the grid, so the states at
/// grid points do not depend on which output times were asked for, and a symplectic method keeps a
/// constant step. Output times within 16 ulps of a grid point (relative to (t − t0)/h) are on the grid.
/// The last output time's side-step is taken on the trajectory itself, so a run ends at its last output time.
///
/// drive_grid is the one fixed-step loop of lgi: integrate_times, integrate_every and integrate_to below, the
/// batch driver (core/batch.hpp), the Euclidean drivers (integrators/euclidean_rk.hpp) and the engine behind the
/// `lgi` command (core/engine.hpp) all run through it; integrators/adaptive.hpp's drive_adaptive is the adaptive one.
/// Its state between calls is a Cursor — the grid index, the next output event, the steps taken — so a run can
/// stop anywhere (a budget, a signal, a failed step) and continue bit for bit from a copy of the cursor and the
/// stepper's internal state (the checkpoints of `lgi run`).
///
/// The step loop allocates nothing and does nothing but step: observers run only at output events, the
/// monitor (progress, budgets, interruption) after as many steps as it asks for, and `NoMonitor` compiles
/// away. On a failed step the run stops; the state is the last good one and the summary says where and why.
#pragma once

#include "integrator.hpp"
#include "state.hpp"

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace lgi {

/// How a run ended (IntegrationSummary::status).
enum class RunStatus : std::uint8_t {
  completed = 0,  ///< every requested output time was reached
  step_failed,  ///< a step returned a status other than ok (see IntegrationSummary::step_status)
  stopped,      ///< the monitor asked to stop (budget, interruption), or a step budget was reached
};

/// What a driver reports: how the run ended, why a step failed, how many steps it took and where it stopped.
struct IntegrationSummary {
  RunStatus status = RunStatus::completed;  ///< completed, step_failed or stopped
  StepStatus step_status = StepStatus::ok;  ///< the failed step's status when status is step_failed, else ok
  std::int64_t steps = 0;  ///< steps taken, output side-steps included
  double t = 0;            ///< time of the state left in x (the last good state)
};

/// The library's monitor protocol: monitor(steps_done) is called every monitor_stride grid steps (adaptive runs:
/// attempted steps); returning false stops the run. NoMonitor compiles away.
struct NoMonitor {
  /// Never stops the run.
  constexpr bool operator()(std::int64_t) const { return true; }
};
/// The grid steps (adaptive runs: attempted steps) between two calls of the library's monitor(steps_done).
inline constexpr std::int64_t monitor_stride = 1024;

/// The observer that observes nothing (the drivers' default): compiles away.
struct NoObserver {
  /// Does nothing.
  template <class T>
  constexpr void operator()(const T&, const State<T>&) const {}
};

namespace detail {

// std::invalid_argument naming `function` unless the output times increase strictly from t0 on.
template <class T>
void check_output_times(std::span<const T> times, const T& t0, const char* function) {
  for (std::size_t i = 0; i < times.size(); ++i)
    if (!(value_of(times[i]) >= value_of(t0)) || (i > 0 && !(value_of(times[i]) > value_of(times[i - 1]))))
      throw std::invalid_argument(std::string(function) + ": output times must be increasing and >= t0");
}

struct GridPoint {
  std::int64_t m;  // largest grid index with t0 + m·h ≤ t (to rounding)
  bool on_grid;    // t is t0 + m·h to rounding
};

template <class T>
GridPoint locate(const T& t0, const T& h, const T& t) {
  const double q = static_cast<double>(value_of((t - t0) / h));
  const double r = std::round(q);
  // (t − t0)/h carries a few ulps of rounding; within 16 ulps of an integer, t is that grid point.
  if (std::abs(q - r) <= 16 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(q)))
    return {static_cast<std::int64_t>(r), true};
  return {static_cast<std::int64_t>(std::floor(q)), false};
}

template <class T>
struct OutputEvent {
  T t{};
  GridPoint at{};
};

}  // namespace detail

/// Where a driver is: with the stepper's internal state, all a run's future depends on. Fixed steps use n, event
/// and steps; adaptive runs (integrators/adaptive.hpp) the rest. A fresh run starts from a default Cursor (adaptive:
/// adaptive_start).
template <class T = double>
struct Cursor {
  bool adaptive = false;   ///< an adaptive run's cursor (drive_adaptive) rather than a fixed-step one (drive_grid)
  std::int64_t steps = 0;  ///< steps taken: fixed — grid steps and output side-steps; adaptive — accepted steps
  // fixed steps
  std::int64_t n = 0;      ///< grid index: the state is at t0 + n·h
  std::int64_t event = 0;  ///< index of the next output event (GridEvents)
  // adaptive steps
  T t{};                             ///< time of the state
  double h = 0;                      ///< the next trial step
  double err_old = 1e-4;             ///< the error of the last accepted step (PI controller)
  bool rejected_last = false;        ///< the last trial was rejected: the next accepted step may not grow
  StepStatus cause = StepStatus::step_size_underflow;  ///< what drove h down (reported on underflow)
  ///@{
  /// Trial steps attempted (accepted + rejected), and those rejected.
  std::int64_t attempts = 0, rejected = 0;
  ///@}
  std::int64_t next = 0;             ///< index of the next requested output time
};

/// The output events of a fixed-step run, by index: rows at given times, or every N steps and at t_end.
template <class T = double>
class GridEvents {
 public:
  /// Events at `times` (increasing, ≥ t0); t = t0 is observed before any event, so a first time equal to t0 is not
  /// an event. The span must outlive this object.
  GridEvents(std::span<const T> times, const T& t0, const T& h) : times_(times), t0_(t0), h_(h) {
    if (!times_.empty() && value_of(times_[0]) == value_of(t0)) first_ = 1;
  }
  /// Events every `every` steps (grid points t0 + k·every·h before t_end) and at t_end (none when t_end = t0).
  GridEvents(std::int64_t every, const T& t0, const T& t_end, const T& h)
      : t0_(t0), h_(h), every_(every), t_end_(t_end), end_(detail::locate(t0, h, t_end)) {}
  /// One event: grid index m (m ≥ 0 steps; none when m = 0).
  static GridEvents steps(std::int64_t m, const T& t0, const T& h) {
    GridEvents e(std::span<const T>(), t0, h);
    e.every_ = std::max<std::int64_t>(m, 1);
    e.t_end_ = t0 + T(static_cast<double>(m)) * h;
    e.end_ = {m, true};
    return e;
  }

  /// The k-th event (k ≥ 0); false past the last.
  bool get(std::int64_t k, detail::OutputEvent<T>& e) const {
    if (every_ == 0) {
      if (k < 0) return false;
      const std::size_t i = first_ + static_cast<std::size_t>(k);
      if (i >= times_.size()) return false;
      e = {times_[i], detail::locate(t0_, h_, times_[i])};
      return true;
    }
    if (k < 0 || (end_.m == 0 && end_.on_grid)) return false;  // t_end = t0: no event
    if (k > end_.m / every_ + 1) return false;                // past t_end (and k·every below cannot overflow)
    const auto is_grid = [&](std::int64_t m) { return m < end_.m || (m == end_.m && !end_.on_grid); };
    if (k > 0 && !is_grid(k * every_)) return false;  // event k − 1 was t_end
    const std::int64_t m = (k + 1) * every_;
    if (is_grid(m))
      e = {t0_ + T(static_cast<double>(m)) * h_, {m, true}};
    else
      e = {t_end_, end_};
    return true;
  }

  /// True if a run can be at grid index n with `event` its next output event: the events before it are at or
  /// before n, and it is not (a resumed run's cursor; every event's grid index is where drive_grid reaches it).
  bool accepts(std::int64_t n, std::int64_t event) const {
    detail::OutputEvent<T> e;
    if (event < 0 || n < 0) return false;
    if (event > 0 && (!get(event - 1, e) || e.at.m > n)) return false;
    return !get(event, e) || e.at.m >= n;
  }

 private:
  std::span<const T> times_;
  std::size_t first_ = 0;
  T t0_{}, h_{};
  std::int64_t every_ = 0;
  T t_end_{};
  detail::GridPoint end_{};
};

/// How a drive ended when it did not complete: none (it completed: every event observed), failed (a step failed;
/// IntegrationSummary::step_status says why), monitor (the monitor returned 0), budget (the step limit, adaptive:
/// attempt limit, was reached).
enum class Halt : std::uint8_t { none, failed, monitor, budget };

/// A drive's monitor: called with the cursor and the state after first() steps, then after as many steps as each call
/// returns; 0 stops the run (Halt::monitor). `DriveMonitor<M>` is true for such an object; NoMonitor (and every other
/// type) is no monitor at all: the loop has no check.
template <class M, class Cursor, class Internal>
concept DriveMonitor = requires(M& m, const Cursor& c, const Internal& y) {
  { m.first(c) } -> std::convertible_to<std::int64_t>;
  { m(c, y) } -> std::convertible_to<std::int64_t>;
};

/// Fixed steps from the cursor (n, event, steps) with y the state at t0 + n·h (a fresh run: n = event = steps = 0,
/// and t0 already observed by the caller). observe(t, y) at each event: y points to the state, or is nullptr for
/// the initial state as given (no step was taken: the caller's own copy, without a round trip through the stepper's
/// coordinates). step_limit: the run stops (Halt::budget) when c.steps would pass it. On return y is the last good
/// state, summary.t its time, `moved` whether any step was taken, and c where the run is (continue from a copy of c
/// and y to get the same bits).
template <StepFunction S, class Observe, class Monitor>
Halt drive_grid(S& stepper, typename S::Internal& y, const typename S::Scalar& t0, const typename S::Scalar& h,
                const GridEvents<typename S::Scalar>& events, std::int64_t step_limit, Cursor<typename S::Scalar>& c,
                IntegrationSummary& summary, bool& moved, Observe& observe, Monitor& monitor) {
  using T = typename S::Scalar;
  using Internal = typename S::Internal;
  using C = Cursor<T>;
  constexpr bool monitored = DriveMonitor<Monitor, C, Internal>;
  const auto grid_time = [&](std::int64_t n) { return t0 + T(static_cast<double>(n)) * h; };
  summary.steps = c.steps;
  summary.t = static_cast<double>(value_of(grid_time(c.n)));
  moved = c.n > 0;
  detail::OutputEvent<T> event;
  if (!events.get(c.event, event)) return Halt::none;
  std::int64_t next_check = std::numeric_limits<std::int64_t>::max();  // the grid index of the next monitor call
  if constexpr (monitored) next_check = c.n + monitor.first(static_cast<const C&>(c));
  for (;;) {
    detail::OutputEvent<T> following;
    const bool more = events.get(c.event + 1, following);
    const std::int64_t m = event.at.m;
    const std::int64_t bound = step_limit - c.steps < m - c.n ? c.n + (step_limit - c.steps) : m;
    Halt halt = Halt::none;
    std::int64_t n = c.n;  // in registers: the stepper's stores into y could alias c
    while (n < bound) {
      const StepStatus status = stepper.step(y, grid_time(n), h);
      if (status != StepStatus::ok) [[unlikely]] {
        summary.status = RunStatus::step_failed;
        summary.step_status = status;
        halt = Halt::failed;
        break;
      }
      ++n;
      if constexpr (monitored) {
        if (n == next_check) [[unlikely]] {
          c.steps += n - c.n;
          c.n = n;
          const std::int64_t stride = monitor(static_cast<const C&>(c), static_cast<const Internal&>(y));
          if (stride <= 0) {
            summary.status = RunStatus::stopped;
            halt = Halt::monitor;
            break;
          }
          next_check = n + stride;
        }
      }
    }
    c.steps += n - c.n;
    c.n = n;
    summary.steps = c.steps;
    summary.t = static_cast<double>(value_of(grid_time(c.n)));
    moved = c.n > 0;
    if (halt != Halt::none) return halt;
    if (c.n < m) {
      summary.status = RunStatus::stopped;
      return Halt::budget;
    }
    if (event.at.on_grid) {
      summary.t = static_cast<double>(value_of(event.t));
      observe(event.t, moved ? &y : static_cast<const Internal*>(nullptr));
    } else {
      if (c.steps >= step_limit) {
        summary.status = RunStatus::stopped;
        return Halt::budget;
      }
      const T t_grid = grid_time(c.n);
      Internal side = y;
      Internal& z = more ? side : y;  // the final side-step moves the trajectory itself
      const StepStatus status = stepper.step(z, t_grid, event.t - t_grid);
      if (status != StepStatus::ok) [[unlikely]] {
        summary.status = RunStatus::step_failed;
        summary.step_status = status;
        return Halt::failed;
      }
      ++c.steps;
      summary.steps = c.steps;
      if (!more) {
        summary.t = static_cast<double>(value_of(event.t));
        moved = true;
      }
      observe(event.t, static_cast<const Internal*>(&z));
    }
    ++c.event;
    if (!more) return Halt::none;
    event = following;
  }
}

// ---- adaptive steps --------------------------------------------------------------------------------------
// The loop of integrators/adaptive.hpp (its header has the method: error control on the group, the PI controller,
// dense output), here beside the fixed-step one so that both are the engine's (core/engine.hpp).

/// The smallest relative tolerance accepted: 10 ε, as in DOPRI5 and DOP853. Below it the error estimate (a
/// difference of two solutions) no longer sees the round-off of the solution itself and would "meet" any
/// tolerance with steps too small to mean anything.
inline constexpr double min_rtol = 10 * std::numeric_limits<double>::epsilon();

/// A Stepper with an embedded pair, as drive_adaptive needs it: attempt(y, t, h, y1, err, dense) takes a trial step
/// into y1 with its scaled error err (accepted when ≤ 1) and leaves what dense_output(dense, θ) needs, θ ∈ [0, 1];
/// control_order k > 0 is the exponent of h ∝ err^(−1/k); rtol() and atol() its tolerances.
template <class S>
concept AdaptiveStepper =
    Stepper<S> && requires(const S& s, const typename S::Internal& y, typename S::Internal& y1,
                           const typename S::Scalar& t, double& err, typename S::Dense& d) {
      typename S::Dense;
      { S::control_order } -> std::convertible_to<int>;
      { s.attempt(y, t, t, y1, err, d) } -> std::same_as<StepStatus>;
      { s.dense_output(d, t) } -> std::same_as<typename S::Internal>;
      { s.rtol() } -> std::convertible_to<double>;
      { s.atol() } -> std::convertible_to<double>;
    } && (S::control_order > 0);

/// Step-size control (the defaults are DOPRI5's).
struct AdaptiveOptions {
  double safety = 0.9;     ///< h_new = h · safety · (1/err)^α …
  double fac_min = 0.2;    ///< … at least fac_min · h
  double fac_max = 10.0;   ///< … at most fac_max · h
  double beta = 0.04;      ///< PI controller: exponent of the previous error (0: I controller)
  double h_max = std::numeric_limits<double>::infinity();  ///< no step is longer (time units)
  double h_min = 0;        ///< a step below max(h_min, 16 ε max(|t|, |t_end − t0|)) fails (step_size_underflow)
  std::int64_t max_steps = 1'000'000'000;  ///< attempted steps (accepted + rejected) before the run stops
  std::int64_t every = 0;  ///< also observe every `every` accepted steps (0: only at the requested times)

  /// Throws std::invalid_argument unless the values make sense.
  void check() const {
    if (!(safety > 0 && safety <= 1)) throw std::invalid_argument("lgi::AdaptiveOptions: safety must be in (0, 1]");
    if (!(fac_min > 0 && fac_min < 1)) throw std::invalid_argument("lgi::AdaptiveOptions: fac_min must be in (0, 1)");
    if (!(fac_max > 1)) throw std::invalid_argument("lgi::AdaptiveOptions: fac_max must be > 1");
    if (!(beta >= 0 && beta < 0.2)) throw std::invalid_argument("lgi::AdaptiveOptions: beta must be in [0, 0.2)");
    if (!(h_max > 0)) throw std::invalid_argument("lgi::AdaptiveOptions: h_max must be > 0");
    if (!(h_min >= 0)) throw std::invalid_argument("lgi::AdaptiveOptions: h_min must be >= 0");
    if (max_steps < 1) throw std::invalid_argument("lgi::AdaptiveOptions: max_steps must be >= 1");
    if (every < 0) throw std::invalid_argument("lgi::AdaptiveOptions: every must be >= 0");
  }
};

namespace detail {
// The PI controller's step-size divisors (DOPRI5's; h_new = h / divisor). err^α and err^α / err_old^β are formed
// as exp(α ln err − β ln err_old): two logs and one exp a step instead of two pow calls, equal to the pow form to
// rounding. err = 0 (an exact step) gives the largest increase without taking log(0).
inline double pi_accepted_divisor(double err, double err_old, double alpha, const AdaptiveOptions& o) {
  const double fac = err > 0 ? std::exp(alpha * std::log(err) - o.beta * std::log(err_old)) : 0.0;
  return std::clamp(fac / o.safety, 1.0 / o.fac_max, 1.0 / o.fac_min);
}
inline double pi_rejected_divisor(double err, double alpha, const AdaptiveOptions& o) {  // err > 1
  return std::min(1.0 / o.fac_min, std::exp(alpha * std::log(err)) / o.safety);
}
}  // namespace detail

/// A fresh adaptive cursor at t0: the first trial step h0 (≤ h_max), the integrate_adaptive's initial values.
template <class T>
Cursor<T> adaptive_start(const T& t0, double h0, const AdaptiveOptions& options) {
  Cursor<T> c;
  c.adaptive = true;
  c.t = t0;
  c.h = std::min(h0, options.h_max);
  return c;
}

/// The adaptive loop (the fixed-step one is drive_grid, core/driver.hpp): from the cursor to times.back(), times
/// increasing and, from c.next on, > c.t (a fresh run: t0 observed by the caller and times equal to t0 skipped,
/// adaptive_start). observe(t, y) at each requested time inside an accepted step (y its dense output), at its end,
/// and every options.every accepted steps; the monitor as in drive_grid, counted in attempted steps; attempt_limit:
/// the run stops (Halt::budget) when c.attempts reaches it. span: |t_end − t0| of the whole run (the step-size
/// floor's scale). On return y is the last accepted state, summary.t its time, c where the run is.
template <AdaptiveStepper S, class Observe, class Monitor>
Halt drive_adaptive(S& stepper, typename S::Internal& y, std::span<const typename S::Scalar> times, double span,
                    const AdaptiveOptions& options, std::int64_t attempt_limit, Cursor<typename S::Scalar>& c,
                    IntegrationSummary& summary, bool& moved, Observe& observe, Monitor& monitor) {
  using T = typename S::Scalar;
  using Internal = typename S::Internal;
  using C = Cursor<T>;
  constexpr bool monitored = DriveMonitor<Monitor, C, Internal>;
  summary.steps = c.steps;
  summary.t = static_cast<double>(value_of(c.t));
  moved = c.steps > 0;
  const std::size_t count = times.size();
  if (static_cast<std::size_t>(c.next) >= count) return Halt::none;
  const T t_end = times.back();
  const double alpha = 1.0 / S::control_order - 0.75 * options.beta;
  constexpr double eps = std::numeric_limits<double>::epsilon();
  Internal y1 = y;
  typename S::Dense dense{};
  std::int64_t next_check = std::numeric_limits<std::int64_t>::max();  // the attempt count of the next monitor call
  if constexpr (monitored) next_check = c.attempts + monitor.first(static_cast<const C&>(c));
  for (;;) {
    if (c.attempts >= attempt_limit) {
      summary.status = RunStatus::stopped;
      return Halt::budget;
    }
    if constexpr (monitored) {
      if (c.attempts == next_check) [[unlikely]] {
        const std::int64_t stride = monitor(static_cast<const C&>(c), static_cast<const Internal&>(y));
        if (stride <= 0) {
          summary.status = RunStatus::stopped;
          return Halt::monitor;
        }
        next_check = c.attempts + stride;
      }
    }
    const double remaining = static_cast<double>(value_of(t_end - c.t));
    bool last = false;
    if (c.h * 1.01 >= remaining) {  // land on t_end (stretching a step by ≤ 1 %)
      c.h = remaining;
      last = true;
    }
    const double h_floor = std::max(options.h_min, 16 * eps * std::max(std::abs(static_cast<double>(value_of(c.t))), span));
    if (!(c.h >= h_floor) && !(last && c.h > 0)) {
      summary.status = RunStatus::step_failed;
      summary.step_status = c.cause;
      return Halt::failed;
    }
    ++c.attempts;
    const T hT = last ? T(t_end - c.t) : T(c.h);
    double err = 0;
    const StepStatus status = stepper.attempt(y, c.t, hT, y1, err, dense);
    if (status != StepStatus::ok || !(err <= std::numeric_limits<double>::max())) {
      ++c.rejected;
      c.cause = status == StepStatus::ok ? StepStatus::non_finite : status;
      c.h *= 0.1;
      c.rejected_last = true;
      continue;
    }
    if (err <= 1.0) {
      // accepted: outputs inside the step from its dense output, then the step's end
      const T t_new = last ? t_end : T(c.t + hT);
      while (static_cast<std::size_t>(c.next) < count &&
             value_of(times[static_cast<std::size_t>(c.next)]) < value_of(t_new)) {
        const T& tk = times[static_cast<std::size_t>(c.next)];
        const T theta = (tk - c.t) / hT;
        const Internal z = stepper.dense_output(dense, theta);
        observe(tk, static_cast<const Internal*>(&z));
        ++c.next;
      }
      y = y1;
      c.t = t_new;
      moved = true;
      ++c.steps;
      summary.steps = c.steps;
      summary.t = static_cast<double>(value_of(c.t));
      bool observed = false;
      if (static_cast<std::size_t>(c.next) < count &&
          value_of(times[static_cast<std::size_t>(c.next)]) == value_of(c.t)) {
        observe(times[static_cast<std::size_t>(c.next)], static_cast<const Internal*>(&y));
        ++c.next;
        observed = true;
      }
      if (options.every > 0 && c.steps % options.every == 0 && !observed) observe(c.t, static_cast<const Internal*>(&y));
      double h_new = std::min(c.h / detail::pi_accepted_divisor(err, c.err_old, alpha, options), options.h_max);
      if (c.rejected_last) h_new = std::min(h_new, c.h);
      c.err_old = std::max(err, 1e-4);
      c.rejected_last = false;
      c.cause = StepStatus::step_size_underflow;
      c.h = h_new;
      if (last || static_cast<std::size_t>(c.next) >= count) return Halt::none;
    } else {
      ++c.rejected;
      c.h /= detail::pi_rejected_divisor(err, alpha, options);
      c.rejected_last = true;
    }
  }
}

namespace detail {

// The library's monitor(steps) -> bool, every monitor_stride steps from the start, as a DriveMonitor.
template <class M>
struct StrideMonitor {
  M& monitor;
  template <class C>
  std::int64_t first(const C&) const {
    return monitor_stride;
  }
  template <class C, class Y>
  std::int64_t operator()(const C& c, const Y&) {
    return monitor(c.steps) ? monitor_stride : 0;
  }
};

// The library's fixed-step drivers over drive_grid: observe(t, x) at t0 and at every event, x as given until a step
// was taken (no J⁻¹(Jx) round trip), and x the last good state on return.
template <StateStepper S, class Observer, class Monitor>
IntegrationSummary drive_library(S& stepper, State<typename S::Scalar>& x, const typename S::Scalar& t0,
                                 const typename S::Scalar& h, const GridEvents<typename S::Scalar>& events,
                                 Observer& observe, Monitor& monitor) {
  using T = typename S::Scalar;
  using Internal = typename S::Internal;
  if (!(value_of(h) > 0)) throw std::invalid_argument("lgi::integrate: step h must be positive");
  IntegrationSummary summary;
  summary.t = static_cast<double>(value_of(t0));
  observe(t0, static_cast<const State<T>&>(x));
  Internal y = stepper.to_internal(x, t0);
  Cursor<T> c;
  bool moved = false;
  const auto on_event = [&](const T& t, const Internal* z) {
    observe(t, z ? stepper.to_state(*z) : static_cast<const State<T>&>(x));
  };
  const std::int64_t no_limit = std::numeric_limits<std::int64_t>::max();
  if constexpr (std::is_same_v<std::remove_cvref_t<Monitor>, NoMonitor>) {
    NoMonitor none;
    drive_grid(stepper, y, t0, h, events, no_limit, c, summary, moved, on_event, none);
  } else {
    StrideMonitor<std::remove_reference_t<Monitor>> every{monitor};
    drive_grid(stepper, y, t0, h, events, no_limit, c, summary, moved, on_event, every);
  }
  if (moved) x = stepper.to_state(y);
  return summary;
}

}  // namespace detail

/// Integrates from t0 with step h, calling observe(t, x) at t0 and at each of `times` (strictly
/// increasing, ≥ t0). On return x is the state at times.back() (or the last good state, see summary).
template <StateStepper S, class Observer = NoObserver, class Monitor = NoMonitor>
IntegrationSummary integrate_times(S& stepper, State<typename S::Scalar>& x, const typename S::Scalar& t0,
                                   const typename S::Scalar& h, std::span<const typename S::Scalar> times,
                                   Observer&& observe = {}, Monitor&& monitor = {}) {
  detail::check_output_times(times, t0, "lgi::integrate_times");
  const GridEvents<typename S::Scalar> events(times, t0, h);
  return detail::drive_library(stepper, x, t0, h, events, observe, monitor);
}

/// Integrates from t0 to t_end with step h, calling observe(t, x) at t0, every `every` steps, and at t_end.
template <StateStepper S, class Observer = NoObserver, class Monitor = NoMonitor>
IntegrationSummary integrate_every(S& stepper, State<typename S::Scalar>& x, const typename S::Scalar& t0,
                                   const typename S::Scalar& h, const typename S::Scalar& t_end,
                                   std::int64_t every, Observer&& observe = {}, Monitor&& monitor = {}) {
  if (every < 1) throw std::invalid_argument("lgi::integrate_every: every must be >= 1");
  if (!(value_of(t_end) >= value_of(t0))) throw std::invalid_argument("lgi::integrate_every: t_end < t0");
  const GridEvents<typename S::Scalar> events(every, t0, t_end, h);
  return detail::drive_library(stepper, x, t0, h, events, observe, monitor);
}

/// Integrates from t0 to t_end with step h and observes only the start and the end: O(1) memory.
template <StateStepper S, class Observer = NoObserver, class Monitor = NoMonitor>
IntegrationSummary integrate_to(S& stepper, State<typename S::Scalar>& x, const typename S::Scalar& t0,
                                const typename S::Scalar& h, const typename S::Scalar& t_end,
                                Observer&& observe = {}, Monitor&& monitor = {}) {
  if (!(value_of(t_end) >= value_of(t0))) throw std::invalid_argument("lgi::integrate_to: t_end < t0");
  const typename S::Scalar times[] = {t_end};
  return integrate_times(stepper, x, t0, h, std::span<const typename S::Scalar>(times, value_of(t_end) > value_of(t0) ? 1 : 0),
                         observe, monitor);
}

}  // namespace lgi
