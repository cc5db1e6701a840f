// lgi/apps/runner_drive.hpp — the drivers of `lgi run`: the library's drivers (core/driver.hpp integrate_times
// and integrate_every, integrators/adaptive.hpp integrate_adaptive) with their loop variables in a Cursor, so that
// a run can stop anywhere, be checkpointed (runner_checkpoint.hpp) and continue bit for bit.
//
// Same arithmetic, step for step, as the library's: t_n = n·dt on the grid (t0 = 0), an output time between
// grid points reached by a side-step from a copy, the last one on the trajectory itself; adaptive steps with
// the PI controller, rejection, dense output and the landing rule of integrate_adaptive. tests/test_checkpoint.cpp
// compares `lgi run`'s rows with the library drivers' states bit for bit. Differences, all at the edges:
//   - the monitor is called with the cursor and the state (to checkpoint) after the number of steps (adaptive:
//     attempted steps) its previous call returned — the first time after one step; it returns 0 to stop the run
//     (runner_detail.hpp, SessionMonitor: about every 10 ms of work, at most every 1024 steps);
//   - a step budget (absolute limits on Cursor::steps, fixed steps, or Cursor::attempts, adaptive) ends the run
//     exactly where it is reached, at no cost per step (the grid loop's bound is lowered to it);
//   - observe(t, y) takes the stepper's Internal (nullptr: the initial state, before any grid step — the
//     library's "no J⁻¹(Jx) round trip").
// The step loop does what the library's does: step, count, and now and then call the monitor.
#pragma once

#include "runner_checkpoint.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/integrators/adaptive.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>

namespace lgi::app::runner_detail {

// How a drive ended when it did not complete.
enum class Halt : std::uint8_t { none, failed, monitor, budget };

// The output events of a fixed-step run, by index (integrate_times and integrate_every of core/driver.hpp).
class GridEvents {
 public:
  // Rows at `times` (increasing, in [0, t_end], ending at t_end); t = 0 is observed before any event.
  GridEvents(std::span<const double> times, double h) : times_(times), h_(h) {
    if (!times_.empty() && times_[0] == 0.0) first_ = 1;
  }
  // Rows every `every` steps and at t_end.
  GridEvents(std::int64_t every, double t_end, double h)
      : h_(h), every_(every), t_end_(t_end), end_(lgi::detail::locate(0.0, h, t_end)) {}

  // True if a run can be at grid index n with `event` its next output event: the events before it are at or
  // before n, and it is not (a resumed run's cursor; every event's grid index is where drive_grid reaches it).
  bool accepts(std::int64_t n, std::int64_t event) const {
    lgi::detail::OutputEvent<double> e;
    if (event < 0 || n < 0) return false;
    if (event > 0 && (!get(event - 1, e) || e.at.m > n)) return false;
    return !get(event, e) || e.at.m >= n;
  }

  // The k-th event (k ≥ 0); false past the last.
  bool get(std::int64_t k, lgi::detail::OutputEvent<double>& e) const {
    if (every_ == 0) {
      const std::size_t i = first_ + static_cast<std::size_t>(k);
      if (i >= times_.size()) return false;
      e = {times_[i], lgi::detail::locate(0.0, h_, times_[i])};
      return true;
    }
    if (end_.m == 0 && end_.on_grid) return false;  // t_end = 0: no event
    if (k > end_.m / every_ + 1) return false;        // past t_end (and k·every below cannot overflow)
    const auto is_grid = [&](std::int64_t m) { return m < end_.m || (m == end_.m && !end_.on_grid); };
    if (k > 0 && !is_grid(k * every_)) return false;  // event k − 1 was t_end (k·every ≤ 1e13 beyond this line)
    const std::int64_t m = (k + 1) * every_;
    if (is_grid(m))
      e = {static_cast<double>(m) * h_, {m, true}};
    else
      e = {t_end_, end_};
    return true;
  }

 private:
  std::span<const double> times_;
  std::size_t first_ = 0;
  double h_;
  std::int64_t every_ = 0;
  double t_end_ = 0;
  lgi::detail::GridPoint end_{};
};

// Fixed steps from the cursor (n, event, steps) with y the state at t = n·h (a fresh run: n = 0, event = 0, and
// t = 0 already observed). step_limit: the run stops (Halt::budget) when c.steps would pass it. On return y is
// the last good state, summary.t its time, c where the run is (a checkpoint taken now continues it).
template <class S, class Observe, class Monitor>
Halt drive_grid(S& stepper, typename S::Internal& y, double h, const GridEvents& events, std::int64_t step_limit,
                Cursor& c, IntegrationSummary& summary, bool& moved, Observe& observe, Monitor& monitor) {
  using Internal = typename S::Internal;
  summary.steps = c.steps;
  summary.t = static_cast<double>(c.n) * h;
  moved = c.n > 0;
  lgi::detail::OutputEvent<double> event;
  if (!events.get(c.event, event)) return Halt::none;
  std::int64_t next_check = c.n + 1;  // the grid index of the next monitor call
  for (;;) {
    lgi::detail::OutputEvent<double> following;
    const bool more = events.get(c.event + 1, following);
    const std::int64_t m = event.at.m;
    const std::int64_t bound = step_limit - c.steps < m - c.n ? c.n + (step_limit - c.steps) : m;
    Halt halt = Halt::none;
    std::int64_t n = c.n;  // in registers: the stepper's stores into y could alias c
    while (n < bound) {
      const StepStatus status = stepper.step(y, static_cast<double>(n) * h, h);
      if (status != StepStatus::ok) [[unlikely]] {
        summary.status = RunStatus::step_failed;
        summary.step_status = status;
        halt = Halt::failed;
        break;
      }
      ++n;
      if (n == next_check) [[unlikely]] {
        c.steps += n - c.n;
        c.n = n;
        const std::int64_t stride = monitor(static_cast<const Cursor&>(c), static_cast<const Internal&>(y));
        if (stride <= 0) {
          summary.status = RunStatus::stopped;
          halt = Halt::monitor;
          break;
        }
        next_check = n + stride;
      }
    }
    c.steps += n - c.n;
    c.n = n;
    summary.steps = c.steps;
    summary.t = static_cast<double>(c.n) * h;
    moved = c.n > 0;
    if (halt != Halt::none) return halt;
    if (c.n < m) {
      summary.status = RunStatus::stopped;
      return Halt::budget;
    }
    if (event.at.on_grid) {
      summary.t = event.t;
      observe(event.t, moved ? &y : nullptr);
    } else {
      if (c.steps >= step_limit) {
        summary.status = RunStatus::stopped;
        return Halt::budget;
      }
      const double t_grid = static_cast<double>(c.n) * h;
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
        summary.t = event.t;
        moved = true;
      }
      observe(event.t, static_cast<const Internal*>(&z));
    }
    ++c.event;
    if (!more) return Halt::none;
    event = following;
  }
}

// A fresh adaptive cursor (integrate_adaptive's initial values): the first trial step h0 (≤ h_max).
inline Cursor adaptive_start(double h0, const AdaptiveOptions& options) {
  Cursor c;
  c.adaptive = true;
  c.h = std::min(h0, options.h_max);
  return c;
}

// Adaptive steps from the cursor, to times.back() (times increasing, > 0 from c.next on; a fresh run: t = 0
// observed and times equal to 0 skipped by the caller). attempt_limit: the run stops (Halt::budget) when
// c.attempts reaches it. On return y is the last accepted state, summary.t its time.
template <class S, class Observe, class Monitor>
Halt drive_adaptive(S& stepper, typename S::Internal& y, std::span<const double> times, const AdaptiveOptions& options,
                    std::int64_t attempt_limit, Cursor& c, IntegrationSummary& summary, bool& moved, Observe& observe,
                    Monitor& monitor) {
  using Internal = typename S::Internal;
  summary.steps = c.steps;
  summary.t = c.t;
  moved = c.steps > 0;
  const std::size_t count = times.size();
  if (static_cast<std::size_t>(c.next) >= count) return Halt::none;
  const double t_end = times.back();
  const double span = std::abs(t_end);
  const double alpha = 1.0 / S::control_order - 0.75 * options.beta;
  constexpr double eps = std::numeric_limits<double>::epsilon();
  Internal y1 = y;
  typename S::Dense dense{};
  std::int64_t next_check = c.attempts + 1;  // the attempt count at the next monitor call
  for (;;) {
    if (c.attempts >= attempt_limit) {
      summary.status = RunStatus::stopped;
      return Halt::budget;
    }
    if (c.attempts == next_check) [[unlikely]] {
      const std::int64_t stride = monitor(static_cast<const Cursor&>(c), static_cast<const Internal&>(y));
      if (stride <= 0) {
        summary.status = RunStatus::stopped;
        return Halt::monitor;
      }
      next_check = c.attempts + stride;
    }
    const double remaining = t_end - c.t;
    bool last = false;
    if (c.h * 1.01 >= remaining) {  // land on t_end (stretching a step by ≤ 1 %)
      c.h = remaining;
      last = true;
    }
    const double h_floor = std::max(options.h_min, 16 * eps * std::max(std::abs(c.t), span));
    if (!(c.h >= h_floor) && !(last && c.h > 0)) {
      summary.status = RunStatus::step_failed;
      summary.step_status = c.cause;
      return Halt::failed;
    }
    ++c.attempts;
    const double hT = last ? t_end - c.t : c.h;
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
      const double t_new = last ? t_end : c.t + hT;
      while (static_cast<std::size_t>(c.next) < count && times[static_cast<std::size_t>(c.next)] < t_new) {
        const double tk = times[static_cast<std::size_t>(c.next)];
        const double theta = (tk - c.t) / hT;
        const Internal z = stepper.dense_output(dense, theta);
        observe(tk, &z);
        ++c.next;
      }
      y = y1;
      c.t = t_new;
      moved = true;
      ++c.steps;
      summary.steps = c.steps;
      summary.t = c.t;
      bool observed = false;
      if (static_cast<std::size_t>(c.next) < count && times[static_cast<std::size_t>(c.next)] == c.t) {
        observe(times[static_cast<std::size_t>(c.next)], static_cast<const Internal*>(&y));
        ++c.next;
        observed = true;
      }
      if (options.every > 0 && c.steps % options.every == 0 && !observed) observe(c.t, static_cast<const Internal*>(&y));
      double h_new = std::min(c.h / lgi::detail::pi_accepted_divisor(err, c.err_old, alpha, options), options.h_max);
      if (c.rejected_last) h_new = std::min(h_new, c.h);
      c.err_old = std::max(err, 1e-4);
      c.rejected_last = false;
      c.cause = StepStatus::step_size_underflow;
      c.h = h_new;
      if (last || static_cast<std::size_t>(c.next) >= count) return Halt::none;
    } else {
      ++c.rejected;
      c.h /= lgi::detail::pi_rejected_divisor(err, alpha, options);
      c.rejected_last = true;
    }
  }
}

}  // namespace lgi::app::runner_detail
