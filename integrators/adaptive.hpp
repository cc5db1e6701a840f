// lgi/integrators/adaptive.hpp — adaptive steps for embedded pairs: error control on the group, a PI
// step-size controller with rejection, output times by dense output on the group.
//
// An AdaptiveStepper (RKMK with an EmbeddedTableau, integrators/rkmk.hpp; the embedding baselines with
// DOP853, integrators/embedding.hpp; either wrapped in Projected, integrators/projection.hpp) offers
//
//   StepStatus attempt(y, t, h, y1, err, dense)   one trial step: y1 and the scaled error norm err (≤ 1: accept)
//   Internal   dense_output(dense, θ)             the state at t + θh of that step, θ ∈ [0, 1]
//   control_order                                 k: the error estimate behaves like h^k
//
// integrate_adaptive drives it (Hairer, Nørsett, Wanner, Solving ODEs I, 2nd ed., §II.4, and the step-size
// logic of Hairer & Wanner's codes DOPRI5 and DOP853, whose parameter names are kept here):
//
//   PI controller (Gustafsson, ACM TOMS 17 (1991) 533; Gustafsson, Lundh, Söderlind, BIT 28 (1988) 270;
//   Hairer & Wanner, Solving ODEs II, 2nd ed., §IV.2, "A PI Step Size Control": the controller is their
//   (IV.2.43c), h_{n+1} = h_n (Tol/err_n)^α (err_{n−1}/Tol)^β, with Gustafsson's (1991) choice α ≈ 0.7/p,
//   β ≈ 0.4/p and the remark that β = 0.04 suits DOP853 — checked against the book's text, where the number
//   of the α, β display is not legible in the copy read. The parametrisation below, α = 1/k − 0.75 β with
//   β = 0.04, err_{n−1} ≥ 1e-4, the rejection rule and the no-growth-after-rejection rule are those of
//   Hairer's dopri5.f (subroutine DOPCOR, read)):
//     h_new = h · clamp(safety · err_n^(−α) · err_{n−1}^β, fac_min, fac_max),   α = 1/k − 0.75 β,
//   with err_{n−1} the error of the last accepted step (≥ 1e-4), β = 0.04 by default (β = 0: the classical
//   controller h·safety·err^(−1/k)). A step with err > 1 is rejected and retried with
//   h / min(1/fac_min, err^α / safety); after a rejection the next accepted step may not grow.
//   Steps are clipped to h_max and to the final time (a step within 1 % of it is stretched to land on it,
//   as DOPRI5 does); output times in between are never stepped to: they are read from the dense output of
//   the step that covers them (on the group: R_n exp(u(θh)), integrators/rkmk.hpp), accurate to the
//   method's dense order.
//
//   Failure is a status, never a NaN: a trial step that is not finite counts as rejected and shrinks h ten
//   times; a step below max(h_min, 16 ε max(|t|, |t_end − t0|)) ends the run with RunStatus::step_failed
//   and StepStatus::step_size_underflow (or non_finite when non-finite trials drove h down); max_steps
//   attempted steps (accepted + rejected) or the monitor end it with RunStatus::stopped. x then holds the
//   last accepted state and the summary its time.
//
// Measured (tests/test_adaptive.cpp, skew heavy top, rtol = atol = tol, error = max over the output times of
// |log(R_refᵀR)| + |Ω − Ω_ref| against a long-double reference): over T = 2 the global error is 2.0 … 2.7 tol
// (DP5) and 0.04 … 1.7 tol (DOP853) for tol = 1e-4 … 1e-12; over T = 10 it is 33 … 46 tol (DP5) and 2 … 7 tol
// (DOP853) — the controller bounds the local error, and on this top local errors add up and grow — while
// staying proportional to tol (ratio spread 1.14 and 2.5 over 1e-6 … 1e-12). Accepted steps ∝ tol^−0.196 (DP5;
// 1/k = 0.2) and tol^−0.109 (DOP853; 1/k = 0.125, and 1/8.72 = 0.115 from the fixed-step order at the same
// step sizes, h = 0.11 … 0.5, where DOP853 is not yet in its asymptotic range).
//
// The error norm is computed on the value parts (ceres::Jet: derivatives do not steer the step sizes; a
// trajectory's derivative is that of the fixed step sequence the values chose). Nothing is allocated.
#pragma once

#include "../core/driver.hpp"
#include "../core/integrator.hpp"
#include "../core/state.hpp"

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <type_traits>

namespace lgi {

// The smallest relative tolerance accepted: 10 ε, as in DOPRI5 and DOP853. Below it the error estimate (a
// difference of two solutions) no longer sees the round-off of the solution itself and would "meet" any
// tolerance with steps too small to mean anything.
inline constexpr double min_rtol = 10 * std::numeric_limits<double>::epsilon();

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

// Step-size control (the defaults are DOPRI5's).
struct AdaptiveOptions {
  double safety = 0.9;     // h_new = h · safety · (1/err)^α …
  double fac_min = 0.2;    // … at least fac_min · h
  double fac_max = 10.0;   // … at most fac_max · h
  double beta = 0.04;      // PI controller: exponent of the previous error (0: I controller)
  double h_max = std::numeric_limits<double>::infinity();
  double h_min = 0;        // a step below max(h_min, 16 ε max(|t|, |t_end − t0|)) fails (step_size_underflow)
  std::int64_t max_steps = 1'000'000'000;  // attempted steps (accepted + rejected) before the run stops
  std::int64_t every = 0;  // also observe every `every` accepted steps (0: only at the requested times)

  // Throws std::invalid_argument unless the values make sense.
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

struct AdaptiveSummary {
  RunStatus status = RunStatus::completed;
  StepStatus step_status = StepStatus::ok;
  std::int64_t accepted = 0;
  std::int64_t rejected = 0;  // error test failed (non-finite trials included)
  double t = 0;               // time of the state left in x
  double h = 0;               // the step size the controller proposes next
};

// A fresh adaptive cursor at t0: the first trial step h0 (≤ h_max), the integrate_adaptive's initial values.
template <class T>
Cursor<T> adaptive_start(const T& t0, double h0, const AdaptiveOptions& options) {
  Cursor<T> c;
  c.adaptive = true;
  c.t = t0;
  c.h = std::min(h0, options.h_max);
  return c;
}

// The adaptive loop (the fixed-step one is drive_grid, core/driver.hpp): from the cursor to times.back(), times
// increasing and, from c.next on, > c.t (a fresh run: t0 observed by the caller and times equal to t0 skipped,
// adaptive_start). observe(t, y) at each requested time inside an accepted step (y its dense output), at its end,
// and every options.every accepted steps; the monitor as in drive_grid, counted in attempted steps; attempt_limit:
// the run stops (Halt::budget) when c.attempts reaches it. span: |t_end − t0| of the whole run (the step-size
// floor's scale). On return y is the last accepted state, summary.t its time, c where the run is.
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

// Integrates from t0 with initial step h0 to times.back(), calling observe(t, x) at t0, at each of `times`
// (strictly increasing, ≥ t0) and, with options.every = N > 0, after every N-th accepted step. On return x
// is the state at times.back() (or the last accepted state, see the summary). The loop is drive_adaptive's.
template <AdaptiveStepper S, class Observer = NoObserver, class Monitor = NoMonitor>
AdaptiveSummary integrate_adaptive(S& stepper, State<typename S::Scalar>& x, const typename S::Scalar& t0,
                                   const typename S::Scalar& h0, std::span<const typename S::Scalar> times,
                                   Observer&& observe = {}, const AdaptiveOptions& options = {},
                                   Monitor&& monitor = {}) {
  using T = typename S::Scalar;
  using Internal = typename S::Internal;
  options.check();
  if (!(stepper.rtol() >= min_rtol && stepper.atol() > 0 && std::isfinite(stepper.rtol()) &&
        std::isfinite(stepper.atol())))
    throw std::invalid_argument(
        "lgi::integrate_adaptive: the stepper's rtol must be >= 10 machine epsilons (2.2e-15) and atol > 0, both "
        "finite");
  if (!(value_of(h0) > 0)) throw std::invalid_argument("lgi::integrate_adaptive: initial step h0 must be positive");
  for (std::size_t i = 0; i < times.size(); ++i)
    if (!(value_of(times[i]) >= value_of(t0)) || (i > 0 && !(value_of(times[i]) > value_of(times[i - 1]))))
      throw std::invalid_argument("lgi::integrate_adaptive: output times must be increasing and >= t0");

  AdaptiveSummary summary;
  summary.t = static_cast<double>(value_of(t0));
  observe(t0, static_cast<const State<T>&>(x));
  Cursor<T> c = adaptive_start(t0, static_cast<double>(value_of(h0)), options);
  while (static_cast<std::size_t>(c.next) < times.size() && value_of(times[static_cast<std::size_t>(c.next)]) == value_of(t0))
    ++c.next;
  if (static_cast<std::size_t>(c.next) == times.size()) return summary;

  Internal y = stepper.to_internal(x, t0);
  IntegrationSummary run;
  bool moved = false;
  const auto on_event = [&](const T& t, const Internal* z) { observe(t, stepper.to_state(*z)); };
  const double span = std::abs(static_cast<double>(value_of(times.back() - t0)));
  if constexpr (std::is_same_v<std::remove_cvref_t<Monitor>, NoMonitor>) {
    NoMonitor none;
    drive_adaptive(stepper, y, times, span, options, options.max_steps, c, run, moved, on_event, none);
  } else {
    detail::StrideMonitor<std::remove_reference_t<Monitor>> every{monitor};
    drive_adaptive(stepper, y, times, span, options, options.max_steps, c, run, moved, on_event, every);
  }
  summary.status = run.status;
  summary.step_status = run.step_status;
  summary.accepted = c.steps;
  summary.rejected = c.rejected;
  summary.t = run.t;
  summary.h = c.h;
  if (moved) x = stepper.to_state(y);
  return summary;
}

}  // namespace lgi
