/// \file
/// lgi/integrators/lagrange_split.hpp — Strang splitting of an axisymmetric top: gravity kicks around the
/// exact free flow of the symmetric body.
///
/// For J = diag(I1, I1, I3) the kinetic energy splits into two commuting parts whose flows are
/// rotations, H_T = |Π|²/(2 I1) + ½ (1/I3 − 1/I1) Π3² (|Π|² is a Casimir, so both Poisson-commute), and
/// the free flow over a time h is exact and elementary (derived here; it is the classical regular
/// precession of a free symmetric body, e.g. Landau & Lifshitz, Mechanics, §33):
///
/// ~~~{.unparsed}
///   Euler's equations:  Ω3' = 0,  (Ω1 + iΩ2)' = i λ (Ω1 + iΩ2),   λ = (I3 − I1) Ω3 / I1,
///   so Ω(t) = exp(λt ê3) Ω(0): Ω precesses about the body axis e3 at the rate λ; and
///   R(t) = R(0) exp(t Π/I1) exp(−λt ê3),   Π = JΩ(0)      [check: R'= R hat(exp(λt ê3)Ω(0)) = R hat(Ω(t)),
///                                                          since exp(tΠ/I1)ᵀ fixes Π/I1 = Ω(0) + λ e3]
///   i.e. a rotation about the fixed spatial momentum m = RΠ at the rate |Π|/I1, then a spin about the
///   symmetry axis by φ = −λh = h Π3 (I1 − I3)/(I1 I3). In momentum form Π(h) = exp(−φ ê3) Π(0).
/// ~~~
///
/// One step (R, Π) → (R', Π'), with the body torque M(R) = b Γ × z0 of a top whose M3 ≡ 0:
///
/// ~~~{.unparsed}
///   kick     Π⁺ = Π + ½h M(R)                      (only Π1, Π2 change)
///   drift    R' = R exp(h Π⁺/I1) exp(φ ê3),  φ = h Π⁺3 (I1 − I3)/(I1 I3);   Π⁻ = exp(−φ ê3) Π⁺
///   kick     Π' = Π⁻ + ½h M(R')
/// ~~~
///
/// Carried in the frame that turns with the spin. Since Π3 is constant, the spin angle ψ of the symmetric
/// free flow grows by the same φ every step; any rotation by φ rounded to doubles has the same small defect
/// every step — (cos φ)² + (sin φ)² − 1 ≈ 4εφ², and an angle error, both fixed — and applied to R (a 3×3
/// product) it makes ‖RᵀR − I‖ and m·k drift linearly (docs/findings.md). So the state is (q̃, Π̃, ψ) with
/// ~~~{.unparsed}
///   R = R(q̃) exp(ψ ê3),   Π = exp(−ψ ê3) Π̃:
/// ~~~
/// in these variables the drift is R(q̃) ← R(q̃) exp(hΠ̃/I1) with Π̃ unchanged and ψ ← ψ + φ (a scalar sum,
/// kept in [−π, π) with 2π split in two doubles), and the kicks are Π̃ += ½h M(R(q̃)ᵀk) — the torque of an
/// axisymmetric top commutes with turns about e3, M(R exp(α ê3)) = exp(−α ê3) M(R) (its potential does not see
/// them: that is what M3 ≡ 0 means; the constructor checks it). No fixed rotation is applied to anything:
/// the rotation exp(hΠ̃/I1) changes with the kicks, q̃ is a unit quaternion renormalised by one Newton step each
/// step, and ψ enters only at the output, R = R(q̃) exp(ψ ê3). Checked by tests/problems/test_problem_library.cpp,
/// LagrangeSplit.LongRunAtLargeSteps: ‖RᵀR − I‖ and m·k stay below 1e-12 over 4·10⁶ steps at h = 0.3, growing no
/// faster than a random walk (growth exponent < 0.75). M is kept for the next step's first kick: one torque per
/// step; Γ̃ = R(q̃)ᵀk is read off q̃ without forming a matrix. Explicit, no solve, no step-size restriction from the
/// spin rate.
///
/// Order 2 (Strang splitting φ^[V]_{h/2} ∘ φ^[T]_h ∘ φ^[V]_{h/2}: Strang, SIAM J. Numer. Anal. 5 (1968) 506; Hairer,
/// Lubich & Wanner, Geometric Numerical Integration, 2nd ed., §II.5, eq. (II.5.3), which they call the Strang
/// splitting (Strang 1968) and show to be symmetric and of order 2 — checked against the book's text; the observed
/// order is 2 ± 0.2 in tests/problems/test_problem_library.cpp). Symplectic and symmetric (composition of exact
/// Hamiltonian flows, symmetric arrangement; HLW Example II.5.1 makes the same argument for Störmer–Verlet).
/// Preserves exactly: R on SO(3) to round-off (products of rotations); m_ψ = Π3 = I3 Ω3 bit for bit in the stepped
/// state (no operation touches Π3; m_ψ is a linear invariant, Ω3' ≡ 0, so RKMK4 and the LGVI keep it to round-off as
/// well: tests/problems/test_problem_library.cpp); m·k to round-off (the kick adds a vector ⊥ Γ = Rᵀk, the drift
/// preserves m = RΠ); energy bounded (no drift). Exact (to round-off) when b = 0: it is then the free symmetric
/// body's flow, so it integrates the fast spin of a gyroscope exactly and only the gravity kicks carry the O(h²)
/// error — the regime of the fast Lagrange top (Brüls, Cardona, Arnold 2012; shared/NUMERICS.md: "integrate the spin
/// about the symmetry axis exactly"). Using the exact symmetric free flow inside splittings: Celledoni, Fassò,
/// Säfström, Zanna, SIAM J. Sci. Comput. 30 (2008) 2084, §1 (no equation number there for this flow; the formulas
/// above are derived in this header and verified by the tests).
///
/// Applies to problems that declare `static constexpr bool axisymmetric = true` (LagrangeTop): their
/// inertia is diag(I1, I1, I3) — checked by the constructor, which throws std::invalid_argument
/// otherwise — and their torque has M3 ≡ 0 (the step does not read M3).
#pragma once

#include "../core/state_io.hpp"
#include "../core/integrator.hpp"
#include "../core/problem.hpp"
#include "../core/so3.hpp"
#include "../core/state.hpp"
#include "free_body_flows.hpp"  // Quaternion, quat::

#include <cmath>
#include <stdexcept>

namespace lgi {

/// A problem that declares `static constexpr bool axisymmetric = true`: J = diag(I1, I1, I3) and a torque that
/// commutes with turns about e3 (M3 ≡ 0), as LagrangeTop does.
template <class P>
concept AxisymmetricProblem = AttitudeTorqueProblem<P> && requires {
  { P::axisymmetric } -> std::convertible_to<bool>;
  requires P::axisymmetric;
};

/// The splitting of an axisymmetric top around the exact symmetric free flow (this header) as a Stepper on problem
/// P: explicit, symmetric, symplectic, order 2, m_ψ kept exactly. Only an AxisymmetricProblem can construct one.
template <AttitudeTorqueProblem P>
class LagrangeSplit {
 public:
  using Problem = P;                  ///< the problem type
  using Scalar = typename P::Scalar;  ///< its scalar
  /// In the frame turning with the spin (see the header): R = R(q) exp(ψ ê3), Π = JΩ = exp(−ψ ê3) Pi, and M
  /// the torque in that frame at q (the next step's first kick).
  struct Internal {
    Quaternion<Scalar> q;  ///< the attitude of the turning frame, R(q)
    Vec3<Scalar> Pi;       ///< the body momentum in that frame
    Vec3<Scalar> M;        ///< the torque in that frame at q
    Scalar psi;            ///< the spin angle ψ, in [−π, π)
    LGI_NUMBERS(q, Pi, M, psi)
  };

  /// The method's traits.
  static constexpr MethodTraits traits{
      .name = "lagrange_split",
      .title = "Strang splitting: gravity kicks around the exact symmetric free flow (axisymmetric tops)",
      .order = 2,
      .symplectic = true,
      .symmetric = true,
      .explicit_method = true,
      .exact_on_group = true,
      .preserves_momentum = true,
      .reference = "Strang, SIAM J. Numer. Anal. 5 (1968) 506; free symmetric flow: Celledoni et al., SIAM J. Sci. "
                   "Comput. 30 (2008) 2084, Sect. 1",
  };

  /// Copies the problem; explicit: the options are not read. std::invalid_argument unless the inertia is
  /// diag(I1, I1, I3) with I1, I3 > 0 and the torque commutes with turns about e3 (checked at one attitude).
  explicit LagrangeSplit(const P& problem, const StepperOptions& = {})
    requires AxisymmetricProblem<P>
      : problem_(problem) {
    const Mat3<Scalar>& J = problem.inertia;
    const bool diagonal = value_of(J(0, 1)) == 0 && value_of(J(0, 2)) == 0 && value_of(J(1, 2)) == 0 &&
                          value_of(J(1, 0)) == 0 && value_of(J(2, 0)) == 0 && value_of(J(2, 1)) == 0;
    if (!diagonal || !(value_of(J(0, 0)) == value_of(J(1, 1))) || !(value_of(J(0, 0)) > 0) || !(value_of(J(2, 2)) > 0))
      throw std::invalid_argument("lgi::LagrangeSplit: the inertia must be diag(I1, I1, I3) with I1, I3 > 0");
    I1_ = J(0, 0);
    I3_ = J(2, 2);
    inv_I1_ = Scalar(1) / I1_;
    spin_ = (I1_ - I3_) / (I1_ * I3_);
    // The torque must commute with turns about e3 (the header): checked at one attitude and turn.
    const Mat3<Scalar> R0 = so3::exp(Vec3<Scalar>(Scalar(0.4), Scalar(-0.7), Scalar(0.3)));
    const Scalar alpha(0.9);
    const Vec3<Scalar> M0 = body_torque(problem_, Scalar(0), R0);
    const Vec3<Scalar> M1 = turn(body_torque(problem_, Scalar(0), Mat3<Scalar>(R0 * so3::exp(Vec3<Scalar>(Scalar(0), Scalar(0), alpha)))), alpha);
    if (!(value_of((M1 - M0).norm()) <= 1e-12 * (1 + value_of(M0.norm()))))
      throw std::invalid_argument("lgi::LagrangeSplit: the torque must commute with turns about the symmetry axis e3");
  }

  /// x at time t in the turning frame and its torque: one evaluation.
  Internal to_internal(const State<Scalar>& x, const Scalar& t) const
    requires AxisymmetricProblem<P>
  {
    const Quaternion<Scalar> q = quat::from_matrix(x.R);
    return {q, Vec3<Scalar>(I1_ * x.Omega.x(), I1_ * x.Omega.y(), I3_ * x.Omega.z()), torque(t, q), Scalar(0)};
  }
  /// (R(q) exp(ψ ê3), J⁻¹ exp(−ψ ê3) Π) of y.
  State<Scalar> to_state(const Internal& y) const
    requires AxisymmetricProblem<P>
  {
    using std::cos;
    using std::sin;
    const Scalar c = cos(y.psi), s = sin(y.psi);
    Mat3<Scalar> R = quat::to_matrix(y.q);  // R(q) exp(ψ ê3): columns 0 and 1 turned by ψ
    for (int r = 0; r < 3; ++r) {
      const Scalar r0 = R(r, 0), r1 = R(r, 1);
      R(r, 0) = c * r0 + s * r1;
      R(r, 1) = c * r1 - s * r0;
    }
    const Vec3<Scalar> Pi = turn(y.Pi, Scalar(-y.psi));
    return {R, Vec3<Scalar>(Pi.x() * inv_I1_, Pi.y() * inv_I1_, Pi.z() / I3_)};
  }

  /// One step from t to t + h: kick, exact symmetric drift, kick (header). ok or non_finite, y untouched unless ok;
  /// one torque evaluation, no matrix formed for a reduced-attitude torque, no allocation.
  LGI_FLATTEN StepStatus step(Internal& y, const Scalar& t, const Scalar& h)
    requires AxisymmetricProblem<P>
  {
    using T = Scalar;
    const T half_h = T(0.5) * h;
    // kick (Π3 untouched: M3 ≡ 0)
    Vec3<T> Pi = y.Pi;
    Pi.x() += half_h * y.M.x();
    Pi.y() += half_h * y.M.y();
    // drift in the turning frame: q ⊗ a, a = exp(hΠ/I1) = (cos x, sin x n), x n = ½h Π/I1; ψ += φ
    const T ha = T(0.5) * h * inv_I1_;
    T da, sa;  // cos x − 1, sin x / x
    half_angle(T(ha * ha * Pi.squaredNorm()), da, sa);
    const Vec3<T> ua = (sa * ha) * Pi;
    // q ⊗ a = q + (w δ − v·u, w u + δ v + v × u), then |q| → 1
    Quaternion<T> q = y.q;
    const T w = q.w;
    const Vec3<T> v = q.v;
    q.w = w + (w * da - v.dot(ua));
    q.v = v + (w * ua + da * v + v.cross(ua));
    quat::renormalise(q);
    T psi = y.psi + h * Pi.z() * spin_;
    if (value_of(psi) >= pi_ || value_of(psi) < -pi_) psi = wrap(psi);
    // kick
    const Vec3<T> M1 = torque(t + h, q);
    Pi.x() += half_h * M1.x();
    Pi.y() += half_h * M1.y();
    if (!all_finite(q.w) || !all_finite(q.v) || !all_finite(Pi) || !all_finite(M1) || !all_finite(psi))
      return StepStatus::non_finite;
    y = {q, Pi, M1, psi};
    return StepStatus::ok;
  }

  /// The problem, as copied at construction.
  const P& problem() const { return problem_; }

 private:
  static constexpr double pi_ = 3.141592653589793;
  /// ψ reduced to [−π, π): ψ − 2π (or + 2π) with 2π = two_pi_hi + two_pi_lo; the first difference is exact.
  static Scalar wrap(const Scalar& psi) {
    constexpr double two_pi_hi = 6.283185307179586, two_pi_lo = 2.4492935982947064e-16;
    if (value_of(psi) >= pi_) return (psi - Scalar(two_pi_hi)) - Scalar(two_pi_lo);
    return (psi + Scalar(two_pi_hi)) + Scalar(two_pi_lo);
  }
  /// exp(α ê3) v
  static Vec3<Scalar> turn(const Vec3<Scalar>& v, const Scalar& alpha) {
    using std::cos;
    using std::sin;
    const Scalar c = cos(alpha), s = sin(alpha);
    return {c * v.x() - s * v.y(), s * v.x() + c * v.y(), v.z()};
  }
  /// cos x − 1 and sin x / x from x² (Taylor polynomials below x² = 0.01, exact there to < 3e-19; no square
  /// root on that path).
  static void half_angle(const Scalar& x2, Scalar& cm1, Scalar& sinc) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    if (value_of(x2) < 0.01) {
      static constexpr double sc[] = {1.0, -1.0 / 6, 1.0 / 120, -1.0 / 5040, 1.0 / 362880};
      static constexpr double cc[] = {-0.5, 1.0 / 24, -1.0 / 720, 1.0 / 40320, -1.0 / 3628800};
      sinc = so3::detail::horner(x2, sc);
      cm1 = x2 * so3::detail::horner(x2, cc);
    } else {
      const Scalar x = sqrt(x2);
      const Scalar s = sin(x);
      sinc = s / x;
      cm1 = -(s * s) / (Scalar(1) + cos(x));
    }
  }
  /// The torque in the turning frame at q: M(R(q)) = exp(ψ ê3) M(R(q) exp(ψ ê3)) for an axisymmetric top (the
  /// header); through Γ̃ = R(q)ᵀk for a reduced-attitude problem (no matrix), else at R(q).
  Vec3<Scalar> torque(const Scalar& t, const Quaternion<Scalar>& q) const {
    if constexpr (ReducedAttitudeProblem<P>) {
      // R(q)ᵀk = k − 2w (v × k) + 2 v × (v × k) for a unit q
      const Vec3<Scalar>& k = problem_.reduced_axis();
      const Vec3<Scalar> vk = q.v.cross(k);
      const Vec3<Scalar> Gamma = k + Scalar(2) * (q.v.cross(vk) - q.w * vk);
      return problem_.reduced_torque(Gamma);
    } else {
      return body_torque(problem_, t, quat::to_matrix(q));
    }
  }

  P problem_;
  Scalar I1_{}, I3_{}, inv_I1_{}, spin_{};
};

}  // namespace lgi
