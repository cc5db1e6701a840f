// lgi/core/driver.hpp — drivers: step a state through time, land on output times, call observers.
//
// Time is t_n = t0 + n·h on a fixed grid, never a running sum (Boost.Odeint, integrate_const). An
// output time that falls between grid points t_m < t_out < t_m+1 is reached by one extra step of size
// t_out − t_m taken from a copy of the state: the main trajectory stays on the grid, so the states at
// grid points do not depend on which output times were asked for, and a symplectic method keeps a
// constant step. Output times within 16 ulps of a grid point (relative to (t − t0)/h) are on the grid.
//
// The step loop allocates nothing and does nothing but step: observers run only at output times, the
// monitor (progress, budgets, interruption) only every `monitor_stride` steps, and `NoMonitor` compiles
// away. On a failed step the run stops; x holds the last good state and the summary says where and why.
#pragma once

#include "integrator.hpp"
#include "state.hpp"

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
  stopped,      // the monitor asked to stop (budget, interruption)
};

struct IntegrationSummary {
  RunStatus status = RunStatus::completed;
  StepStatus step_status = StepStatus::ok;
  std::int64_t steps = 0;  // steps taken, output side-steps included
  double t = 0;            // time of the state left in x (the last good state)
};

// A monitor is called as monitor(steps_done) every monitor_stride grid steps; returning false stops.
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

// Steps y from grid index n to m. Returns false when the run must end (failure or monitor).
template <Stepper S, class Monitor>
bool advance(S& stepper, typename S::Internal& y, const typename S::Scalar& t0, const typename S::Scalar& h,
             std::int64_t& n, std::int64_t m, IntegrationSummary& summary, Monitor& monitor) {
  using T = typename S::Scalar;
  for (; n < m; ++n) {
    const StepStatus status = stepper.step(y, t0 + T(static_cast<double>(n)) * h, h);
    if (status != StepStatus::ok) [[unlikely]] {
      summary.status = RunStatus::step_failed;
      summary.step_status = status;
      return false;
    }
    ++summary.steps;
    if constexpr (!std::is_same_v<std::remove_cvref_t<Monitor>, NoMonitor>) {
      if (((n + 1) % monitor_stride) == 0 && !monitor(summary.steps)) [[unlikely]] {
        ++n;
        summary.status = RunStatus::stopped;
        return false;
      }
    }
  }
  return true;
}

// The common driver: observe t0, then for each event from next(event) advance on the grid and observe.
// The last event's side-step (if any) is taken on the trajectory itself, so x ends at the last output
// time; after a failure or a stop x is the last good state and summary.t its time.
template <Stepper S, class Next, class Observer, class Monitor>
IntegrationSummary drive(S& stepper, State<typename S::Scalar>& x, const typename S::Scalar& t0,
                         const typename S::Scalar& h, Next&& next, Observer& observe, Monitor& monitor) {
  using T = typename S::Scalar;
  using Internal = typename S::Internal;
  if (!(value_of(h) > 0)) throw std::invalid_argument("lgi::integrate: step h must be positive");
  IntegrationSummary summary;
  summary.t = static_cast<double>(value_of(t0));
  observe(t0, static_cast<const State<T>&>(x));
  Internal y = stepper.to_internal(x, t0);
  bool moved = false;  // x is returned as given unless a step succeeded (no J⁻¹(Jx) round trip)
  std::int64_t n = 0;
  const auto grid_time = [&] { return t0 + T(static_cast<double>(n)) * h; };
  detail::OutputEvent<T> event;
  bool more = next(event);
  while (more) {
    detail::OutputEvent<T> following;
    more = next(following);
    const std::int64_t before = summary.steps;
    const bool ok = advance(stepper, y, t0, h, n, event.at.m, summary, monitor);
    moved = moved || summary.steps > before;
    summary.t = static_cast<double>(value_of(grid_time()));
    if (!ok) break;
    if (event.at.on_grid) {
      summary.t = static_cast<double>(value_of(event.t));
      observe(event.t, moved ? stepper.to_state(y) : x);
    } else {
      Internal side = y;
      Internal& z = more ? side : y;  // the final side-step moves the trajectory itself
      const StepStatus status = stepper.step(z, grid_time(), event.t - grid_time());
      if (status != StepStatus::ok) [[unlikely]] {
        summary.status = RunStatus::step_failed;
        summary.step_status = status;
        break;
      }
      ++summary.steps;
      if (!more) {
        summary.t = static_cast<double>(value_of(event.t));
        moved = true;
      }
      observe(event.t, stepper.to_state(z));
    }
    event = following;
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
  using T = typename S::Scalar;
  for (std::size_t i = 0; i < times.size(); ++i)
    if (!(value_of(times[i]) >= value_of(t0)) || (i > 0 && !(value_of(times[i]) > value_of(times[i - 1]))))
      throw std::invalid_argument("lgi::integrate_times: output times must be increasing and >= t0");
  std::size_t i = 0;
  if (!times.empty() && value_of(times[0]) == value_of(t0)) i = 1;  // t0 is always observed once
  auto next = [&](detail::OutputEvent<T>& e) {
    if (i == times.size()) return false;
    e = {times[i], detail::locate(t0, h, times[i])};
    ++i;
    return true;
  };
  return detail::drive(stepper, x, t0, h, next, observe, monitor);
}

// Integrates from t0 to t_end with step h, calling observe(t, x) at t0, every `every` steps, and at t_end.
template <Stepper S, class Observer = NoObserver, class Monitor = NoMonitor>
IntegrationSummary integrate_every(S& stepper, State<typename S::Scalar>& x, const typename S::Scalar& t0,
                                   const typename S::Scalar& h, const typename S::Scalar& t_end,
                                   std::int64_t every, Observer&& observe = {}, Monitor&& monitor = {}) {
  using T = typename S::Scalar;
  if (every < 1) throw std::invalid_argument("lgi::integrate_every: every must be >= 1");
  if (!(value_of(t_end) >= value_of(t0))) throw std::invalid_argument("lgi::integrate_every: t_end < t0");
  const detail::GridPoint end = detail::locate(t0, h, t_end);
  std::int64_t m = 0;
  bool done = end.m == 0 && end.on_grid;
  auto next = [&](detail::OutputEvent<T>& e) {
    if (done) return false;
    m += every;
    if (m < end.m || (m == end.m && !end.on_grid)) {
      e = {t0 + T(static_cast<double>(m)) * h, {m, true}};
    } else {
      e = {t_end, end};
      done = true;
    }
    return true;
  };
  return detail::drive(stepper, x, t0, h, next, observe, monitor);
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
