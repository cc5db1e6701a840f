/// \file
/// lgi/integrators/euclidean_rk.hpp — explicit Runge–Kutta methods on R^n, for states that are not on
/// SO(3) (the seed paper's Euler-angle top, problems/euler_angle_top.hpp), and their drivers.
///
/// For y' = f(t, y) on R^n and an explicit tableau (a, b, c) of butcher_tableaus.hpp (Hairer, Nørsett,
/// Wanner, Solving ODEs I, 2nd ed., §II.1, eq. (1.8)):
///
/// ~~~{.unparsed}
///   k_i = f(t + c_i h, y + h Σ_{j<i} a_ij k_j),   i = 1 … s,        y⁺ = y + h Σ_i b_i k_i.
/// ~~~
///
/// This is the RKMK method of the same tableau on the additive group R^n (exp is y ↦ y + v and the inverse
/// Jacobian of the exponential is the identity, so Munthe-Kaas' stage equations reduce to these), which
/// is why the scene names of the RKMK tableaus select these methods for Euclidean problems.
/// Embedded pairs (EmbeddedTableau) run with fixed steps on their main weights b.
/// Order: that of the tableau. Not symplectic, not symmetric; no geometric structure is kept except
/// linear invariants (a component with zero derivative stays exactly constant). Zero tableau entries are
/// skipped at compile time; the step allocates nothing; everything is templated on the scalar.
///
/// A Euclidean system is a struct with `Scalar`, `Vector` (a fixed-size Eigen column vector) and
/// `Vector derivative(const Scalar& t, const Vector& y) const`; optionally `bool admissible(const Vector&)
/// const`, the domain of the coordinates (the drivers stop, keeping the last admissible state, once a step
/// leaves it), and `void normalize(Vector&) const`, applied after every step (e.g. taking whole turns out
/// of an angle, so that it does not grow and round at a growing ulp).
#pragma once

#include "../core/driver.hpp"
#include "../core/integrator.hpp"
#include "../core/scalar.hpp"
#include "butcher_tableaus.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <utility>

namespace lgi {

/// A Euclidean system (this header): Scalar, Vector and derivative(t, y).
template <class S>
concept EuclideanSystem = requires(const S& s, const typename S::Vector& y, const typename S::Scalar& t) {
  typename S::Scalar;
  typename S::Vector;
  { s.derivative(t, y) } -> std::convertible_to<typename S::Vector>;
};

/// The explicit Runge–Kutta method of Tableau on the Euclidean system Sys (this header).
template <const auto& Tableau, EuclideanSystem Sys>
class EuclideanRk {
 public:
  using System = Sys;                   ///< the system type
  using Scalar = typename Sys::Scalar;  ///< its scalar
  using Vector = typename Sys::Vector;  ///< its state vector

  /// The traits: the tableau's name and order, no geometric property.
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

  /// Copies the system.
  explicit EuclideanRk(const Sys& system) : system_(system) {}

  /// Advances y from t to t + h; on a non-finite result y is left untouched.
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

  /// The system's admissible(y), or true for a system without a domain.
  bool admissible(const Vector& y) const {
    if constexpr (requires { system_.admissible(y); })
      return system_.admissible(y);
    else
      return true;
  }

  /// The system, as copied at construction.
  const Sys& system() const { return system_; }

 private:
  /// Stages a step needs (these fixed steps make no error estimate).
  static constexpr int update_stages = tableaus::update_stages(Tableau);

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

/// What a Euclidean run ended with: IntegrationSummary (completed, step_failed, stopped by the monitor),
/// plus `left_domain` when it stopped because a step left the system's admissible domain (then status is
/// `stopped`, y the last admissible state and t its time, `t_outside` the time of the rejected state).
struct EuclideanSummary : IntegrationSummary {
  bool left_domain = false;  ///< the run stopped because a step left the admissible domain
  double t_outside = 0;      ///< then: the time of the rejected state
};

/// The do-nothing observer of Euclidean runs.
struct NoVectorObserver {
  /// Does nothing.
  template <class T, class V>
  constexpr void operator()(const T&, const V&) const {}
};

/// A Euclidean stepper with its domain checked, as the drivers step it (drive_grid, core/driver.hpp): a step whose
/// result is not admissible fails, the state untouched, and records where (left, t_outside). Internal is the
/// system's Vector.
template <class Rk>
class CheckedEuclideanStep {
 public:
  using Scalar = typename Rk::Scalar;    ///< the stepper's scalar
  using Internal = typename Rk::Vector;  ///< the system's vector
  /// Refers to rk, which must outlive this object.
  explicit CheckedEuclideanStep(const Rk& rk) : rk_(rk) {}
  /// rk's step; a result that is not admissible fails with non_finite (y untouched), recording left() and
  /// t_outside().
  StepStatus step(Internal& y, const Scalar& t, const Scalar& h) {
    Internal trial = y;
    const StepStatus status = rk_.step(trial, t, h);
    if (status != StepStatus::ok) return status;
    if (!rk_.admissible(trial)) [[unlikely]] {
      left_ = true;
      t_outside_ = static_cast<double>(value_of(t + h));
      return StepStatus::non_finite;  // the run's status: left_domain (see left())
    }
    y = trial;
    return StepStatus::ok;
  }
  /// The last failed step left the domain.
  bool left() const { return left_; }
  /// The time of that rejected state.
  double t_outside() const { return t_outside_; }
  /// The wrapped stepper.
  const Rk& rk() const { return rk_; }

 private:
  const Rk& rk_;
  bool left_ = false;
  double t_outside_ = 0;
};

namespace detail {

// The Euclidean drivers over drive_grid: observe(t, y) with the vector itself.
template <class Rk, class Observer, class Monitor>
EuclideanSummary drive_euclidean(const Rk& rk, typename Rk::Vector& y, const typename Rk::Scalar& t0,
                                 const typename Rk::Scalar& h, const GridEvents<typename Rk::Scalar>& events,
                                 Observer& observe, Monitor& monitor) {
  using T = typename Rk::Scalar;
  using V = typename Rk::Vector;
  if (!(value_of(h) > 0)) throw std::invalid_argument("lgi::integrate: step h must be positive");
  EuclideanSummary summary;
  summary.t = static_cast<double>(value_of(t0));
  observe(t0, static_cast<const V&>(y));
  CheckedEuclideanStep<Rk> stepper(rk);
  Cursor<T> c;
  bool moved = false;
  const auto on_event = [&](const T& t, const V* z) { observe(t, z ? *z : static_cast<const V&>(y)); };
  const std::int64_t no_limit = std::numeric_limits<std::int64_t>::max();
  IntegrationSummary& s = summary;
  if constexpr (std::is_same_v<std::remove_cvref_t<Monitor>, NoMonitor>) {
    NoMonitor none;
    drive_grid(stepper, y, t0, h, events, no_limit, c, s, moved, on_event, none);
  } else {
    StrideMonitor<std::remove_reference_t<Monitor>> every{monitor};
    drive_grid(stepper, y, t0, h, events, no_limit, c, s, moved, on_event, every);
  }
  if (summary.status == RunStatus::step_failed && stepper.left()) {
    summary.status = RunStatus::stopped;
    summary.step_status = StepStatus::ok;
    summary.left_domain = true;
    summary.t_outside = stepper.t_outside();
  }
  return summary;
}

}  // namespace detail

/// Integrates from t0 with step h, observing t0 and each of `times` (increasing, ≥ t0); see
/// integrate_times in core/driver.hpp. y ends at times.back() or at the last good state.
template <class Stepper, class Observer = NoVectorObserver, class Monitor = NoMonitor>
EuclideanSummary integrate_times_euclidean(const Stepper& stepper, typename Stepper::Vector& y,
                                           const typename Stepper::Scalar& t0, const typename Stepper::Scalar& h,
                                           std::span<const typename Stepper::Scalar> times, Observer&& observe = {},
                                           Monitor&& monitor = {}) {
  detail::check_output_times(times, t0, "lgi::integrate_times_euclidean");
  const GridEvents<typename Stepper::Scalar> events(times, t0, h);
  return detail::drive_euclidean(stepper, y, t0, h, events, observe, monitor);
}

/// Integrates from t0 to t_end with step h, observing t0, every `every` steps, and t_end.
template <class Stepper, class Observer = NoVectorObserver, class Monitor = NoMonitor>
EuclideanSummary integrate_every_euclidean(const Stepper& stepper, typename Stepper::Vector& y,
                                           const typename Stepper::Scalar& t0, const typename Stepper::Scalar& h,
                                           const typename Stepper::Scalar& t_end, std::int64_t every,
                                           Observer&& observe = {}, Monitor&& monitor = {}) {
  if (every < 1) throw std::invalid_argument("lgi::integrate_every: every must be >= 1");
  if (!(value_of(t_end) >= value_of(t0))) throw std::invalid_argument("lgi::integrate_every: t_end < t0");
  const GridEvents<typename Stepper::Scalar> events(every, t0, t_end, h);
  return detail::drive_euclidean(stepper, y, t0, h, events, observe, monitor);
}

}  // namespace lgi
