/// \file
/// lgi/integrators/projection.hpp — invariant projection for non-symplectic methods: after every step,
/// restore the energy and a momentum invariant by moving Ω alone (R untouched).
///
/// The standard projection method (Hairer, Lubich, Wanner, Geometric Numerical Integration, 2nd ed. (2006),
/// §IV.4, Algorithm 4.2 "Standard Projection Method", with the projection step in the form (IV.4.5) — both
/// checked against the book's text; Hairer, BIT 41 (2001) 996, §2): after a step ỹ_{n+1} of the underlying
/// method, take
///
/// ~~~{.unparsed}
///   y_{n+1} = ỹ_{n+1} + G(ỹ_{n+1})ᵀ λ   with λ such that g(y_{n+1}) = g(y_0),
/// ~~~
///
/// G = g' the gradient of the invariants, λ from Newton's method (HLW use simplified Newton iterations from
/// λ = 0 and note that the first increment is of the size of the local error). Here y = Ω with R held fixed
/// (R is already on SO(3) to round-off for the RKMK methods; its invariants — the Casimir |Rᵀk| = 1 — need no
/// help), and
///
/// ~~~{.unparsed}
///   g₁(Ω) = ½ Ω·JΩ + V(R)                      energy; ∇g₁ = JΩ                   (every problem)
///   g₂(Ω) = a·(R JΩ) = (JΓ)·Ω,  Γ = Rᵀa        momentum about the axis a of a ReducedAttitudeProblem
///                                              (heavy top: m·k, the seed paper's m_φ); ∇g₂ = JΓ
///   g₂(Ω) = ½ |JΩ|²                             free body (no torque): the Casimir |JΩ|; ∇g₂ = J²Ω
/// ~~~
///
/// Newton solves the 2×2 system in λ (g₁ is quadratic, g₂ linear or quadratic along Ω̃ + Gᵀλ; its
/// Jacobian g'(Ω)Gᵀ is exact), starting from λ = 0; the first update is O(local error) and the iteration
/// stops once both residuals are at the round-off of evaluating them, 8 ε Σ|terms| (usually after one update;
/// at most 6; with Jets one update more so that the derivative part converges too). Where the two gradients are
/// parallel to within 1e-5 rad (a steady spin about a principal axis, a sleeping top) the 2×2 system is singular
/// and only the energy is restored. The targets g(y₀) travel in the internal state (no hidden state in the stepper).
///
/// What it does not do: the free body's spatial momentum m = RJΩ (three components) cannot be restored with
/// R fixed — with R given, m fixes Ω completely, and E and |JΩ| would then follow from the step's error —
/// so the free body keeps |m| = |JΩ| and E, not the direction of m. Time-dependent torques conserve no
/// energy: Projected does not accept them. Symplectic methods need no projection (their energy error is
/// bounded) and are not accepted either.
///
/// Cost: one Γ = Rᵀa (or none), one V(R), the gradients, and ≈ 40 flops per Newton update (usually one
/// update and two residuals) — ≈ 150 flops a step.
/// Effect (tests/integrators/test_projection.cpp): energy and m·k (free body: E and |JΩ|) within 1e-13 over 10⁶
/// steps where the unprojected runs drift; the state error at T = 10 at most twice the unprojected one (the
/// measured figures: docs/validation.md).
/// Order: that of the underlying method (the projection moves the state by O(local error)). R on SO(3): as
/// the underlying method.
/// Adaptive: an AdaptiveStepper stays one; its error estimate is the unprojected step's, the accepted state
/// and every dense output are projected.
#pragma once

#include "../core/state_io.hpp"
#include "../core/inertia.hpp"
#include "../core/integrator.hpp"
#include "../core/invariants.hpp"
#include "../core/problem.hpp"
#include "../core/state.hpp"

#include <cmath>
#include <concepts>
#include <limits>
#include <type_traits>

namespace lgi {

/// Problems whose energy is conserved: no time-dependent torque, no torque that reads Ω.
template <class P>
concept ProjectableProblem =
    AttitudeTorqueProblem<P> &&
    !requires(const P& p, const typename P::Scalar& t, const Mat3<typename P::Scalar>& R) { p.torque(t, R); };

/// Steppers whose result Projected can correct: not symplectic, with Ω in their internal coordinates, or
/// with a set_omega(y, Ω) that replaces the internal velocity (or momentum) and leaves the attitude alone
/// (the splittings, whose internal state is a quaternion and the principal-axis momentum).
template <class S>
concept ProjectableStepper =
    Stepper<S> && ProjectableProblem<typename S::Problem> && (!S::traits.symplectic) &&
    (requires(typename S::Internal& y) { { y.Omega } -> std::convertible_to<Vec3<typename S::Scalar>>; } ||
     requires(const S& s, typename S::Internal& y, const Vec3<typename S::Scalar>& w) { s.set_omega(y, w); });

/// The invariant values a projected run restores.
template <class T>
struct ProjectionTargets {
  T energy;  ///< g₁: the energy E
  T second;  ///< a·(RJΩ) or ½|JΩ|²
};

/// The projection itself, usable on its own: restores g(R, Ω) = targets by Ω ← Ω + Gᵀλ.
template <ProjectableProblem P>
class InvariantProjection {
 public:
  using T = typename P::Scalar;  ///< the problem's scalar
  static constexpr bool reduced = P::has_torque && ReducedAttitudeProblem<P>;  ///< g₂ = a·(RJΩ) (header)
  static constexpr bool free = !P::has_torque;                                ///< g₂ = ½|JΩ|² (header)
  static constexpr bool two_constraints = reduced || free;                    ///< else the energy alone

  /// Copies the problem (and J with its inverse).
  explicit InvariantProjection(const P& problem) : problem_(problem), J_(problem.inertia) {}

  /// g(x): the energy and, where the problem has one, the second invariant of the header.
  ProjectionTargets<T> targets(const State<T>& x) const {
    const Vec3<T> Pi = J_.apply(x.Omega);
    return {T(0.5) * x.Omega.dot(Pi) + problem_.potential(x.R), second(x.R, Pi)};
  }

  /// Ω restored for attitude R; false (Omega untouched) when the result is not finite.
  bool project(const Mat3<T>& R, Vec3<T>& Omega, const ProjectionTargets<T>& target) const {
    using std::abs;
    const T kinetic_target = target.energy - problem_.potential(R);  // ½ Ω·JΩ must equal this
    Vec3<T> a;                                                        // ∇g₂ for the linear case: JΓ
    if constexpr (reduced) a = J_.apply(Vec3<T>(R.transpose() * problem_.reduced_axis()));
    const Vec3<T> W0 = Omega;
    const Vec3<T> g1 = J_.apply(W0);                                  // ∇g₁(Ω̃) = JΩ̃
    Vec3<T> g2 = Vec3<T>::Zero();
    if constexpr (reduced) g2 = a;
    if constexpr (free) g2 = J_.apply(g1);                           // J²Ω̃
    bool both = two_constraints;
    if constexpr (two_constraints) {                                  // parallel gradients: energy only
      const double n1 = static_cast<double>(value_of(g1.squaredNorm()));
      const double n2 = static_cast<double>(value_of(g2.squaredNorm()));
      const double c = static_cast<double>(value_of(g1.cross(g2).squaredNorm()));
      both = c > 1e-10 * n1 * n2;
    }
    constexpr double eps = std::numeric_limits<double>::epsilon();
    const auto abs_dot = [](const Vec3<T>& x, const Vec3<T>& y) {  // Σ |x_k y_k|: the round-off scale of x·y
      double s = 0;
      for (int k = 0; k < 3; ++k)
        s += std::abs(static_cast<double>(value_of(x[k]))) * std::abs(static_cast<double>(value_of(y[k])));
      return s;
    };
    T l1 = T(0), l2 = T(0);
    Vec3<T> W = W0;
    int extra = is_dual_v<T> ? 1 : 0;
    for (int iteration = 0; iteration < 6 + extra; ++iteration) {
      const Vec3<T> PiW = J_.apply(W);
      const T r1 = T(0.5) * W.dot(PiW) - kinetic_target;
      T r2 = T(0);
      Vec3<T> dg2 = Vec3<T>::Zero();  // ∇g₂(W)
      double round2 = 0;              // round-off scale of g₂
      if (both) {
        if constexpr (reduced) {
          r2 = a.dot(W) - target.second;
          dg2 = a;
          round2 = abs_dot(a, W);
        } else {
          r2 = T(0.5) * PiW.squaredNorm() - target.second;
          dg2 = J_.apply(PiW);
          round2 = 0.5 * abs_dot(PiW, PiW);
        }
      }
      // Converged when the residuals are at the round-off of evaluating them (Newton converges quadratically:
      // from an O(local error) start the second residual is already there). Checking the residual instead of
      // the size of a further update saves that update (docs/performance.md, "Design measurements behind the code").
      if (std::abs(static_cast<double>(value_of(r1))) <= 8 * eps * 0.5 * abs_dot(W, PiW) &&
          std::abs(static_cast<double>(value_of(r2))) <= 8 * eps * round2) {
        if (extra == 0) break;
        --extra;  // Jets: one more update for the derivative part
      }
      T d1, d2 = T(0);
      if (both) {
        // Jacobian of λ ↦ g(Ω̃ + Gᵀλ): [∇g_i(W)·G_j]
        const T j11 = PiW.dot(g1), j12 = PiW.dot(g2), j21 = dg2.dot(g1), j22 = dg2.dot(g2);
        const T det = j11 * j22 - j12 * j21;
        d1 = -(j22 * r1 - j12 * r2) / det;
        d2 = -(-j21 * r1 + j11 * r2) / det;
      } else {
        d1 = -r1 / PiW.dot(g1);
      }
      l1 += d1;
      l2 += d2;
      W = W0 + l1 * g1 + l2 * g2;
    }
    if (!all_finite(W)) return false;
    Omega = W;
    return true;
  }

  /// The problem, as copied at construction.
  const P& problem() const { return problem_; }

 private:
  T second(const Mat3<T>& R, const Vec3<T>& Pi) const {
    if constexpr (reduced)
      return problem_.reduced_axis().dot(Vec3<T>(R * Pi));
    else if constexpr (free)
      return T(0.5) * Pi.squaredNorm();
    else
      return T(0);
  }

  P problem_;
  Inertia<T> J_;
};

namespace detail {
template <class S>
struct DenseOf {
  struct type {};
};
template <class S>
  requires requires { typename S::Dense; }
struct DenseOf<S> {
  using type = typename S::Dense;
};
}  // namespace detail

/// Any non-symplectic stepper S with the projection after every step (and after every dense output).
///
/// Switched off (the constructor's `enabled`; the engine behind `lgi` switches it by the scene's "projection"), it
/// is S itself: the same steps, bits and counters, the targets left zero and not counted by numbers_in_use — so
/// one compiled loop serves a method with and without projection.
template <ProjectableStepper S>
class Projected {
 public:
  using Problem = typename S::Problem;  ///< S's problem type
  using Scalar = typename S::Scalar;    ///< its scalar
  /// S's state and the invariant values to restore (set by to_internal from the run's initial state).
  struct Internal {
    typename S::Internal y;            ///< the inner method's state
    ProjectionTargets<Scalar> target;  ///< g at the start of the run (zero when switched off)
    LGI_NUMBERS(y, target.energy, target.second)
  };
  /// The inner method's traits: the projection changes what is conserved, not what the method is.
  static constexpr MethodTraits traits = S::traits;

  /// S built from (problem, options) (S's exceptions propagate); `enabled` false: S itself (above).
  explicit Projected(const Problem& problem, const StepperOptions& options = {}, bool enabled = true)
      : inner_(problem, options), projection_(problem), enabled_(enabled) {}

  /// Whether the projection runs.
  bool enabled() const { return enabled_; }
  /// The numbers of an Internal this stepper uses, leading in LGI_NUMBERS order: S's alone when switched off.
  std::size_t numbers_in_use() const {
    return enabled_ ? number_count<Internal>() : number_count<typename S::Internal>();
  }

  /// S's coordinates of x, and the targets g(x) when enabled.
  Internal to_internal(const State<Scalar>& x, const Scalar& t) const {
    if (!enabled_) return {inner_.to_internal(x, t), {Scalar(0), Scalar(0)}};
    return {inner_.to_internal(x, t), projection_.targets(x)};
  }
  /// S's state of y.
  State<Scalar> to_state(const Internal& y) const { return inner_.to_state(y.y); }

  /// S's step, then the projection: S's status, or non_finite when the projected state is not finite; y untouched
  /// unless ok. Cost: about 150 flops beyond S's step (header).
  /// Not LGI_FLATTEN: the inner step is flattened already; flattening it again here compiled every method's
  /// step twice in each runner part, for one call saved beside a projection's Newton solve.
  StepStatus step(Internal& y, const Scalar& t, const Scalar& h) {
    if (!enabled_) return inner_.step(y.y, t, h);
    typename S::Internal z = y.y;
    const StepStatus status = inner_.step(z, t, h);
    if (status != StepStatus::ok) return status;
    if (!project(z, y.target)) return StepStatus::non_finite;
    y.y = z;
    return StepStatus::ok;
  }

  // ---- adaptive, when S is ----
  /// S's control order (0 when S has no embedded pair).
  static constexpr int control_order = [] {
    if constexpr (requires { S::control_order; }) return S::control_order; else return 0;
  }();
  /// S's dense-output data and the targets.
  struct Dense {
    typename detail::DenseOf<S>::type inner;  ///< S's Dense (an empty struct when S has none)
    ProjectionTargets<Scalar> target;         ///< the targets the dense outputs are projected to
  };

  /// S's trial step with its error estimate (that of the unprojected step), then the projection of y1 (non_finite
  /// and an infinite error when the projection fails). Only when S is an AdaptiveStepper.
  StepStatus attempt(const Internal& y, const Scalar& t, const Scalar& h, Internal& y1, double& error, Dense& d) const
    requires(control_order > 0)
  {
    const StepStatus status = inner_.attempt(y.y, t, h, y1.y, error, d.inner);
    if (!enabled_ || status != StepStatus::ok) return status;
    d.target = y.target;
    y1.target = y.target;
    if (!project(y1.y, y.target)) {
      error = std::numeric_limits<double>::infinity();
      return StepStatus::non_finite;
    }
    return StepStatus::ok;
  }
  /// S's dense output at θ ∈ [0, 1], projected to the run's targets.
  Internal dense_output(Dense& d, const Scalar& theta) const
    requires(control_order > 0)
  {
    if (!enabled_) return {inner_.dense_output(d.inner, theta), {Scalar(0), Scalar(0)}};
    Internal z{inner_.dense_output(d.inner, theta), d.target};
    project(z.y, d.target);
    return z;
  }
  /// S's rtol.
  double rtol() const
    requires(control_order > 0)
  {
    return inner_.rtol();
  }
  /// S's atol.
  double atol() const
    requires(control_order > 0)
  {
    return inner_.atol();
  }

  /// The inner stepper.
  const S& inner() const { return inner_; }
  /// The projection.
  const InvariantProjection<Problem>& projection() const { return projection_; }
  /// S's Newton iterations, where S counts them (the projection's own are not counted).
  std::int64_t newton_iterations() const
    requires requires(const S& s) { s.newton_iterations(); }
  {
    return inner_.newton_iterations();
  }

 private:
  bool project(typename S::Internal& z, const ProjectionTargets<Scalar>& target) const {
    if constexpr (std::is_same_v<typename S::Internal, State<Scalar>>) {
      // RKMK with a non-diagonal J carries (R, Ω) in principal axes (rkmk.hpp): project in the body frame.
      if constexpr (requires { inner_.internal_is_body_frame(); }) {
        if (!inner_.internal_is_body_frame()) {
          State<Scalar> x = inner_.to_state(z);
          if (!projection_.project(x.R, x.Omega, target)) return false;
          inner_.set_omega(z, x.Omega);
          return true;
        }
      }
      return projection_.project(z.R, z.Omega, target);
    } else if constexpr (requires { z.Omega; }) {
      const State<Scalar> x = inner_.to_state(z);
      return projection_.project(x.R, z.Omega, target);
    } else {
      State<Scalar> x = inner_.to_state(z);
      if (!projection_.project(x.R, x.Omega, target)) return false;
      inner_.set_omega(z, x.Omega);
      return true;
    }
  }

  S inner_;
  InvariantProjection<Problem> projection_;
  bool enabled_;
};

}  // namespace lgi
