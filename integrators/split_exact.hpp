/// \file
/// lgi/integrators/split_exact.hpp — Strang splitting of a torqued rigid body with the exact free-body
/// flow: kick(h/2) ∘ exact free body(h) ∘ kick(h/2).
///
/// Update (body frame, Π = JΩ, M(t, R) the body-frame torque):
///
/// ~~~{.unparsed}
///   Π⁺ = Π_n + ½ h M(t_n, R_n)
///   (R_{n+1}, Π⁻) = φ_h(R_n, Π⁺)              the exact Euler–Poinsot flow (problems/free_body_exact.hpp:
///                                              Jacobi elliptic functions and Π(n; φ, κ), Celledoni, Fassò,
///                                              Säfström & Zanna, SIAM J. Sci. Comput. 30 (2008) 2084, with
///                                              Leroy's corrections)
///   Π_{n+1} = Π⁻ + ½ h M(t_n + h, R_{n+1})
/// ~~~
///
/// Splitting with the exact free-body flow: CFSZ §5 (the splitting of H = T + V into the exact flows of T
/// and of V). Order 2 with a torque (symmetric, so compositions raise it: composition.hpp); exact (to
/// round-off) on the free body. Symplectic (a composition of exact Hamiltonian flows), explicit, m·k and
/// |Γ| kept to round-off, R on SO(3) to round-off (the exact flow's increments). Scalars: double and long
/// double only (no ceres::Jet). Cost: one exact flow (≈ µs: a Carlson duplication for R_F and R_J and a
/// Landen descent per call), so this is a reference-quality method, not a fast one.
#pragma once

#include "../core/state_io.hpp"
#include "../core/integrator.hpp"
#include "../core/problem.hpp"
#include "../core/state.hpp"
#include "../problems/free_body_exact.hpp"

#include <type_traits>

namespace lgi {

/// kick(h/2) ∘ exact free body(h) ∘ kick(h/2) (this header) as a Stepper on problem P: explicit, symmetric,
/// symplectic, order 2 (exact on the free body). Floating-point scalars only.
template <AttitudeTorqueProblem P>
  requires std::is_floating_point_v<typename P::Scalar>
class SplitExact {
 public:
  using Problem = P;                  ///< the problem type
  using Scalar = typename P::Scalar;  ///< its scalar (floating point: no Jets)
  /// (R, Π) and the torque at R, the next step's first kick.
  struct Internal {
    Mat3<Scalar> R;   ///< attitude, body → laboratory
    Vec3<Scalar> Pi;  ///< body angular momentum Π = JΩ
    Vec3<Scalar> M;   ///< body-frame torque at R
    LGI_NUMBERS(R, Pi, M)
  };

  /// The method's traits.
  static constexpr MethodTraits traits{
      .name = "split_exact",
      .title = "Strang splitting: gravity kicks + exact free-body flow (elliptic functions)",
      .order = 2,
      .symplectic = true,
      .symmetric = true,
      .explicit_method = true,
      .exact_on_group = true,
      .preserves_momentum = true,
      .reference = "Celledoni, Fasso, Safstrom, Zanna, SIAM J. Sci. Comput. 30 (2008) 2084, Sect. 5",
  };

  /// Copies the problem and diagonalises J (FreeBodyExact: std::invalid_argument unless J is symmetric positive
  /// definite); std::invalid_argument from StepperOptions::check.
  explicit SplitExact(const P& problem, const StepperOptions& options = {})
      : problem_(problem), exact_(problem.inertia) {
    options.check();
  }

  /// (R, JΩ, M(t, R)) of x at time t: one torque evaluation.
  Internal to_internal(const State<Scalar>& x, const Scalar& t) const {
    return {x.R, Vec3<Scalar>(problem_.inertia * x.Omega), torque(t, x.R)};
  }
  /// (R, J⁻¹Π) of y.
  State<Scalar> to_state(const Internal& y) const {
    return {y.R, Vec3<Scalar>(problem_.inertia.ldlt().solve(y.Pi))};
  }

  /// One step from t to t + h (the header's update): ok or non_finite, y untouched unless ok. Cost: one torque and
  /// one exact flow (a few elliptic functions and integrals in long double).
  // Not LGI_FLATTEN: flattening would inline all of the exact flow's special functions into the step (GCC then
  // compiles one translation unit for tens of minutes); the exact flow dominates the cost anyway.
  StepStatus step(Internal& y, const Scalar& t, const Scalar& h) {
    using T = Scalar;
    const T half_h = T(0.5) * h;
    MomentumState<T> z{y.R, y.Pi};
    if constexpr (P::has_torque) z.Pi += half_h * y.M;
    z = exact_.flow(z, h);
    const Vec3<T> M1 = torque(t + h, z.R);
    if constexpr (P::has_torque) z.Pi += half_h * M1;
    if (!all_finite(z.R) || !all_finite(z.Pi)) return StepStatus::non_finite;
    y = {z.R, z.Pi, M1};
    return StepStatus::ok;
  }

  /// The problem, as copied at construction.
  const P& problem() const { return problem_; }

 private:
  Vec3<Scalar> torque(const Scalar& t, const Mat3<Scalar>& R) const {
    if constexpr (P::has_torque)
      return body_torque(problem_, t, R);
    else
      return Vec3<Scalar>::Zero();
  }

  P problem_;
  FreeBodyExact<Scalar> exact_;
};

}  // namespace lgi
