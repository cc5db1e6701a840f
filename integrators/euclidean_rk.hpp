// lgi/integrators/euclidean_rk.hpp — explicit Runge–Kutta methods on R^n, for states that are not on
// SO(3) (the seed paper's Euler-angle top, problems/euler_angle_top.hpp), and their drivers.
//
// For y' = f(t, y) on R^n and an explicit tableau (a, b, c) of butcher_tableaus.hpp (Hairer, Nørsett,
// Wanner, Solving ODEs I, 2nd ed., §II.1, eq. (1.8)):
//
//   k_i = f(t + c_i h, y + h Σ_{j<i} a_ij k_j),   i = 1 … s,        y⁺ = y + h Σ_i b_i k_i.
//
// This is the RKMK method of the same tableau on the additive group R^n (exp is y ↦ y + v and the inverse
// Jacobian of the exponential is the identity, so Munthe-Kaas' stage equations reduce to these), which
// is why the scene names of the RKMK tableaus select these methods for Euclidean problems.
// Embedded pairs (EmbeddedTableau) run with fixed steps on their main weights b.
// Order: that of the tableau. Not symplectic, not symmetric; no geometric structure is kept except
// linear invariants (a component with zero derivative stays exactly constant). Zero tableau entries are
// skipped at compile time; the step allocates nothing; everything is templated on the scalar.
//
// A Euclidean system is a struct with `Scalar`, `Vector` (a fixed-size Eigen column vector) and
// `Vector derivative(const Scalar& t, const Vector& y) const`; optionally `bool admissible(const Vector&)
// const`, the domain of the coordinates (the drivers stop, keeping the last admissible state, once a step
// leaves it), and `void normalize(Vector&) const`, applied after every step (e.g. taking whole turns out
// of an angle, so that it does not grow and round at a growing ulp).
#pragma once

#include "../core/driver.hpp"
#include "../core/integrator.hpp"
#include "../core/scalar.hpp"
#include "butcher_tableaus.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <utility>

namespace lgi {

template <class S>
concept EuclideanSystem = requires(const S& s, const typename S::Vector& y, const typename S::Scalar& t) {
  typename S::Scalar;
  typename S::Vector;
  { s.derivative(t, y) } -> std::convertible_to<typename S::Vector>;
};

template <const auto& Tableau, EuclideanSystem Sys>
class EuclideanRk {
 public:
  using System = Sys;
  using Scalar = typename Sys::Scalar;
  using Vector = typename Sys::Vector;

  static constexpr MethodTraits traits{
      .name = Tableau.name,
      .title = "explicit Runge-Kutta on R^n with the tableau of this RKMK method",
      .order = Tableau.order,
      .symplectic = false,
      .symmetric = false,
      .explicit_method = true,
      .exact_on_group = false,
      .preserves_momentum = false,
      .reference = "Hairer-Norsett-Wanner, Solving ODEs I, sec. II.1, eq. (1.8)",
  };

  explicit EuclideanRk(const Sys& system) : system_(system) {}

  // Advances y from t to t + h; on a non-finite result y is left untouched.
  LGI_FLATTEN StepStatus step(Vector& y, const Scalar& t, const Scalar& h) const {
    constexpr int S = update_stages;
    std::array<Vector, S> k;
    [&]<int... I>(std::integer_sequence<int, I...>) {
      (stage<I>(y, t, h, k), ...);
    }(std::make_integer_sequence<int, S>{});
    Vector dy = Vector::Zero();
    [&]<int... I>(std::integer_sequence<int, I...>) {
      ([&] {
        if constexpr (Tableau.b[I] != 0) dy += Scalar(Tableau.b[I]) * k[I];
      }(), ...);
    }(std::make_integer_sequence<int, S>{});
    Vector y1 = y + h * dy;
    if constexpr (requires { system_.normalize(y1); }) system_.normalize(y1);
    if (!all_finite(y1)) return StepStatus::non_finite;
    y = y1;
    return StepStatus::ok;
  }

  bool admissible(const Vector& y) const {
    if constexpr (requires { system_.admissible(y); })
      return system_.admissible(y);
    else
      return true;
  }

  const Sys& system() const { return system_; }

 private:
  // Stages a step needs: up to the last with b_i ≠ 0 (an embedded pair's later stages feed only its
  // error estimate; these fixed steps make none).
  static constexpr int update_stages = [] {
    int n = 0;
    for (int i = 0; i < Tableau.stages; ++i)
      if (Tableau.b[static_cast<std::size_t>(i)] != 0) n = i + 1;
    return n;
  }();

  template <int I>
  void stage(const Vector& y, const Scalar& t, const Scalar& h, std::array<Vector, update_stages>& k) const {
    if constexpr (I == 0) {
      k[0] = system_.derivative(t, y);
    } else {
      Vector dy = Vector::Zero();
      [&]<int... J>(std::integer_sequence<int, J...>) {
        ([&] {
          if constexpr (Tableau.a[I][J] != 0) dy += Scalar(Tableau.a[I][J]) * k[J];
        }(), ...);
      }(std::make_integer_sequence<int, I>{});
      k[I] = system_.derivative(t + Scalar(Tableau.c[I]) * h, Vector(y + h * dy));
    }
  }

  Sys system_;
};

// What a Euclidean run ended with: IntegrationSummary (completed, step_failed, stopped by the monitor),
// plus `left_domain` when it stopped because a step left the system's admissible domain (then status is
// `stopped`, y the last admissible state and t its time, `t_outside` the time of the rejected state).
struct EuclideanSummary : IntegrationSummary {
  bool left_domain = false;
  double t_outside = 0;
};

// The do-nothing observer of Euclidean runs.
struct NoVectorObserver {
  template <class T, class V>
  constexpr void operator()(const T&, const V&) const {}
};

namespace detail {

// The Euclidean twin of detail::drive (core/driver.hpp), with the same grid: t_n = t0 + n h, output
// times between grid points reached by a side-step from a copy, the last one on the trajectory itself.
template <class Stepper, class Next, class Observer, class Monitor>
EuclideanSummary drive_euclidean(const Stepper& stepper, typename Stepper::Vector& y,
                                 const typename Stepper::Scalar& t0, const typename Stepper::Scalar& h, Next&& next,
                                 Observer& observe, Monitor& monitor) {
  using T = typename Stepper::Scalar;
  using V = typename Stepper::Vector;
  if (!(value_of(h) > 0)) throw std::invalid_argument("lgi::integrate: step h must be positive");
  EuclideanSummary summary;
  summary.t = static_cast<double>(value_of(t0));
  observe(t0, static_cast<const V&>(y));
  std::int64_t n = 0;
  const auto grid_time = [&] { return t0 + T(static_cast<double>(n)) * h; };
  // One step from time t by dt, checked; false ends the run with y untouched.
  const auto checked_step = [&](V& z, const T& t, const T& dt) {
    V trial = z;
    const StepStatus status = stepper.step(trial, t, dt);
    if (status != StepStatus::ok) [[unlikely]] {
      summary.status = RunStatus::step_failed;
      summary.step_status = status;
      return false;
    }
    if (!stepper.admissible(trial)) [[unlikely]] {
      summary.status = RunStatus::stopped;
      summary.left_domain = true;
      summary.t_outside = static_cast<double>(value_of(t + dt));
      return false;
    }
    z = trial;
    ++summary.steps;
    return true;
  };
  OutputEvent<T> event;
  bool more = next(event);
  while (more) {
    OutputEvent<T> following;
    more = next(following);
    bool ok = true;
    for (; n < event.at.m && ok; ++n) {
      ok = checked_step(y, grid_time(), h);
      if (ok && (n + 1) % monitor_stride == 0 && !monitor(summary.steps)) [[unlikely]] {
        ++n;
        summary.status = RunStatus::stopped;
        ok = false;
      }
      if (!ok) break;
    }
    summary.t = static_cast<double>(value_of(grid_time()));
    if (!ok) break;
    if (event.at.on_grid) {
      summary.t = static_cast<double>(value_of(event.t));
      observe(event.t, static_cast<const V&>(y));
    } else {
      V side = y;
      V& z = more ? side : y;
      if (!checked_step(z, grid_time(), event.t - grid_time())) break;
      if (!more) summary.t = static_cast<double>(value_of(event.t));
      observe(event.t, static_cast<const V&>(z));
    }
    event = following;
  }
  return summary;
}

}  // namespace detail

// Integrates from t0 with step h, observing t0 and each of `times` (increasing, ≥ t0); see
// integrate_times in core/driver.hpp. y ends at times.back() or at the last good state.
template <class Stepper, class Observer = NoVectorObserver, class Monitor = NoMonitor>
EuclideanSummary integrate_times_euclidean(const Stepper& stepper, typename Stepper::Vector& y,
                                           const typename Stepper::Scalar& t0, const typename Stepper::Scalar& h,
                                           std::span<const typename Stepper::Scalar> times, Observer&& observe = {},
                                           Monitor&& monitor = {}) {
  using T = typename Stepper::Scalar;
  for (std::size_t i = 0; i < times.size(); ++i)
    if (!(value_of(times[i]) >= value_of(t0)) || (i > 0 && !(value_of(times[i]) > value_of(times[i - 1]))))
      throw std::invalid_argument("lgi::integrate_times: output times must be increasing and >= t0");
  std::size_t i = 0;
  if (!times.empty() && value_of(times[0]) == value_of(t0)) i = 1;
  auto next = [&](detail::OutputEvent<T>& e) {
    if (i == times.size()) return false;
    e = {times[i], detail::locate(t0, h, times[i])};
    ++i;
    return true;
  };
  return detail::drive_euclidean(stepper, y, t0, h, next, observe, monitor);
}

// Integrates from t0 to t_end with step h, observing t0, every `every` steps, and t_end.
template <class Stepper, class Observer = NoVectorObserver, class Monitor = NoMonitor>
EuclideanSummary integrate_every_euclidean(const Stepper& stepper, typename Stepper::Vector& y,
                                           const typename Stepper::Scalar& t0, const typename Stepper::Scalar& h,
                                           const typename Stepper::Scalar& t_end, std::int64_t every,
                                           Observer&& observe = {}, Monitor&& monitor = {}) {
  using T = typename Stepper::Scalar;
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
  return detail::drive_euclidean(stepper, y, t0, h, next, observe, monitor);
}

}  // namespace lgi
