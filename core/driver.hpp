// lgi/core/driver.hpp — the time loop: step a state through time, land on output times, stop and resume anywhere.
//
// Time is t_n = t0 + n·h on a fixed grid, never a running sum (Boost.Odeint, integrate_const). An
// output time that falls between grid points t_m < t_out < t_m+1 is reached by one extra step of size
// t_out − t_m taken from a copy of the state: the main trajectory stays on the grid, so the states at
// grid points do not depend on which output times were asked for, and a symplectic method keeps a
// constant step. Output times within 16 ulps of a grid point (relative to (t − t0)/h) are on the grid.
// The last output time's side-step is taken on the trajectory itself, so a run ends at its last output time.
//
// drive_grid is the one fixed-step loop of lgi: integrate_times, integrate_every and integrate_to below, the
// batch driver (core/batch.hpp), the Euclidean drivers (integrators/euclidean_rk.hpp) and the engine behind the
// `lgi` command (core/engine.hpp) all run through it; integrators/adaptive.hpp's drive_adaptive is the adaptive one.
// Its state between calls is a Cursor — the grid index, the next output event, the steps taken — so a run can
// stop anywhere (a budget, a signal, a failed step) and continue bit for bit from a copy of the cursor and the
// stepper's internal state (the checkpoints of `lgi run`).
//
// The step loop allocates nothing and does nothing but step: observers run only at output events, the
// monitor (progress, budgets, interruption) after as many steps as it asks for, and `NoMonitor` compiles
// away. On a failed step the run stops; the state is the last good one and the summary says where and why.
#pragma once

#include "integrator.hpp"
#include "state.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <type_traits>

namespace lgi {

enum class RunStatus : std::uint8_t {
  completed = 0,
  step_failed,  // a step returned a status other than ok (see IntegrationSummary::step_status)
  stopped,      // the monitor asked to stop (budget, interruption), or a step budget was reached
};

struct IntegrationSummary {
  RunStatus status = RunStatus::completed;
  StepStatus step_status = StepStatus::ok;
  std::int64_t steps = 0;  // steps taken, output side-steps included
  double t = 0;            // time of the state left in x (the last good state)
};

// The library's monitor protocol: monitor(steps_done) is called every monitor_stride grid steps (adaptive runs:
// attempted steps); returning false stops the run. NoMonitor compiles away.
struct NoMonitor {
  constexpr bool operator()(std::int64_t) const { return true; }
};
inline constexpr std::int64_t monitor_stride = 1024;

struct NoObserver {
  template <class T>
  constexpr void operator()(const T&, const State<T>&) const {}
};

namespace detail {

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

// Where a driver is: with the stepper's internal state, all a run's future depends on. Fixed steps use n, event
// and steps; adaptive runs (integrators/adaptive.hpp) the rest. A fresh run starts from a default Cursor (adaptive:
// adaptive_start).
template <class T = double>
struct Cursor {
  bool adaptive = false;
  std::int64_t steps = 0;  // steps taken: fixed — grid steps and output side-steps; adaptive — accepted steps
  // fixed steps
  std::int64_t n = 0;      // grid index: the state is at t0 + n·h
  std::int64_t event = 0;  // index of the next output event (GridEvents)
  // adaptive steps
  T t{};                             // time of the state
  double h = 0;                      // the next trial step
  double err_old = 1e-4;             // the error of the last accepted step (PI controller)
  bool rejected_last = false;        // the last trial was rejected: the next accepted step may not grow
  StepStatus cause = StepStatus::step_size_underflow;  // what drove h down (reported on underflow)
  std::int64_t attempts = 0, rejected = 0;
  std::int64_t next = 0;             // index of the next requested output time
};

// The output events of a fixed-step run, by index: rows at given times, or every N steps and at t_end.
template <class T = double>
class GridEvents {
 public:
  // Events at `times` (increasing, ≥ t0); t = t0 is observed before any event, so a first time equal to t0 is not
  // an event. The span must outlive this object.
  GridEvents(std::span<const T> times, const T& t0, const T& h) : times_(times), t0_(t0), h_(h) {
    if (!times_.empty() && value_of(times_[0]) == value_of(t0)) first_ = 1;
  }
  // Events every `every` steps (grid points t0 + k·every·h before t_end) and at t_end (none when t_end = t0).
  GridEvents(std::int64_t every, const T& t0, const T& t_end, const T& h)
      : t0_(t0), h_(h), every_(every), t_end_(t_end), end_(detail::locate(t0, h, t_end)) {}
  // One event: grid index m (m ≥ 0 steps; none when m = 0).
  static GridEvents steps(std::int64_t m, const T& t0, const T& h) {
    GridEvents e(std::span<const T>(), t0, h);
    e.every_ = std::max<std::int64_t>(m, 1);
    e.t_end_ = t0 + T(static_cast<double>(m)) * h;
    e.end_ = {m, true};
    return e;
  }

  // The k-th event (k ≥ 0); false past the last.
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

  // True if a run can be at grid index n with `event` its next output event: the events before it are at or
  // before n, and it is not (a resumed run's cursor; every event's grid index is where drive_grid reaches it).
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

// How a drive ended when it did not complete.
enum class Halt : std::uint8_t { none, failed, monitor, budget };

// A drive's monitor: called with the cursor and the state after first() steps, then after as many steps as each call
// returns; 0 stops the run (Halt::monitor). DriveMonitor<M> is true for such an object; NoMonitor (and every other
// type) is no monitor at all: the loop has no check.
template <class M, class Cursor, class Internal>
concept DriveMonitor = requires(M& m, const Cursor& c, const Internal& y) {
  { m.first(c) } -> std::convertible_to<std::int64_t>;
  { m(c, y) } -> std::convertible_to<std::int64_t>;
};

// Fixed steps from the cursor (n, event, steps) with y the state at t0 + n·h (a fresh run: n = event = steps = 0,
// and t0 already observed by the caller). observe(t, y) at each event: y points to the state, or is nullptr for
// the initial state as given (no step was taken: the caller's own copy, without a round trip through the stepper's
// coordinates). step_limit: the run stops (Halt::budget) when c.steps would pass it. On return y is the last good
// state, summary.t its time, `moved` whether any step was taken, and c where the run is (continue from a copy of c
// and y to get the same bits).
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
template <Stepper S, class Observer, class Monitor>
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

// Integrates from t0 with step h, calling observe(t, x) at t0 and at each of `times` (strictly
// increasing, ≥ t0). On return x is the state at times.back() (or the last good state, see summary).
template <Stepper S, class Observer = NoObserver, class Monitor = NoMonitor>
IntegrationSummary integrate_times(S& stepper, State<typename S::Scalar>& x, const typename S::Scalar& t0,
                                   const typename S::Scalar& h, std::span<const typename S::Scalar> times,
                                   Observer&& observe = {}, Monitor&& monitor = {}) {
  for (std::size_t i = 0; i < times.size(); ++i)
    if (!(value_of(times[i]) >= value_of(t0)) || (i > 0 && !(value_of(times[i]) > value_of(times[i - 1]))))
      throw std::invalid_argument("lgi::integrate_times: output times must be increasing and >= t0");
  const GridEvents<typename S::Scalar> events(times, t0, h);
  return detail::drive_library(stepper, x, t0, h, events, observe, monitor);
}

// Integrates from t0 to t_end with step h, calling observe(t, x) at t0, every `every` steps, and at t_end.
template <Stepper S, class Observer = NoObserver, class Monitor = NoMonitor>
IntegrationSummary integrate_every(S& stepper, State<typename S::Scalar>& x, const typename S::Scalar& t0,
                                   const typename S::Scalar& h, const typename S::Scalar& t_end,
                                   std::int64_t every, Observer&& observe = {}, Monitor&& monitor = {}) {
  if (every < 1) throw std::invalid_argument("lgi::integrate_every: every must be >= 1");
  if (!(value_of(t_end) >= value_of(t0))) throw std::invalid_argument("lgi::integrate_every: t_end < t0");
  const GridEvents<typename S::Scalar> events(every, t0, t_end, h);
  return detail::drive_library(stepper, x, t0, h, events, observe, monitor);
}

// Integrates from t0 to t_end with step h and observes only the start and the end: O(1) memory.
template <Stepper S, class Observer = NoObserver, class Monitor = NoMonitor>
IntegrationSummary integrate_to(S& stepper, State<typename S::Scalar>& x, const typename S::Scalar& t0,
                                const typename S::Scalar& h, const typename S::Scalar& t_end,
                                Observer&& observe = {}, Monitor&& monitor = {}) {
  if (!(value_of(t_end) >= value_of(t0))) throw std::invalid_argument("lgi::integrate_to: t_end < t0");
  const typename S::Scalar times[] = {t_end};
  return integrate_times(stepper, x, t0, h, std::span<const typename S::Scalar>(times, value_of(t_end) > value_of(t0) ? 1 : 0),
                         observe, monitor);
}

}  // namespace lgi
