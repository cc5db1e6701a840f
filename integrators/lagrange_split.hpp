// lgi/integrators/lagrange_split.hpp — Strang splitting of an axisymmetric top: gravity kicks around the
// exact free flow of the symmetric body.
//
// For J = diag(I1, I1, I3) the kinetic energy splits into two commuting parts whose flows are
// rotations, H_T = |Π|²/(2 I1) + ½ (1/I3 − 1/I1) Π3² (|Π|² is a Casimir, so both Poisson-commute), and
// the free flow over a time h is exact and elementary (derived here; it is the classical regular
// precession of a free symmetric body, e.g. Landau & Lifshitz, Mechanics, §33):
//
//   Euler's equations:  Ω3' = 0,  (Ω1 + iΩ2)' = i λ (Ω1 + iΩ2),   λ = (I3 − I1) Ω3 / I1,
//   so Ω(t) = exp(λt ê3) Ω(0): Ω precesses about the body axis e3 at the rate λ; and
//   R(t) = R(0) exp(t Π/I1) exp(−λt ê3),   Π = JΩ(0)      [check: R'= R hat(exp(λt ê3)Ω(0)) = R hat(Ω(t)),
//                                                          since exp(tΠ/I1)ᵀ fixes Π/I1 = Ω(0) + λ e3]
//   i.e. a rotation about the fixed spatial momentum m = RΠ at the rate |Π|/I1, then a spin about the
//   symmetry axis by φ = −λh = h Π3 (I1 − I3)/(I1 I3). In momentum form Π(h) = exp(−φ ê3) Π(0).
//
// One step (R, Π) → (R', Π'), with the body torque M(R) = b Γ × z0 of a top whose M3 ≡ 0:
//
//   kick     Π⁺ = Π + ½h M(R)                      (only Π1, Π2 change)
//   drift    R' = R exp(h Π⁺/I1) exp(φ ê3),  φ = h Π⁺3 (I1 − I3)/(I1 I3);   Π⁻ = exp(−φ ê3) Π⁺
//   kick     Π' = Π⁻ + ½h M(R')
//
// written as R' = R + R(E − I) with E − I = (A − I) + (B − I) + (A − I)(B − I), A = exp(hΠ⁺/I1),
// B = exp(φ ê3), the increments formed without the 1 (core/so3.hpp). M(R') is kept for the next step's
// first kick: one torque per step. Explicit, no solve, no step-size restriction from the spin rate.
//
// Order 2 (Strang splitting φ^[V]_{h/2} ∘ φ^[T]_h ∘ φ^[V]_{h/2}: Strang, SIAM J. Numer. Anal. 5 (1968)
// 506; Hairer, Lubich & Wanner, Geometric Numerical Integration, 2nd ed., §II.5 — no equation number
// given: not checked against the book; the order is measured, 2.000). Symplectic and symmetric
// (composition of exact Hamiltonian flows, symmetric arrangement). Preserves exactly: R on SO(3) to
// round-off (products of rotations); m_ψ = Π3 = I3 Ω3 bit for bit in the stepped state (no operation
// touches Π3; m_ψ is a linear invariant, Ω3' ≡ 0, so RKMK4 and the LGVI keep it to round-off as well —
// measured: unchanged); m·k to round-off (the kick adds a vector ⊥ Γ = Rᵀk, the drift preserves m = RΠ); energy
// bounded (no drift). Exact (to round-off) when b = 0: it is then the free symmetric body's flow, so it
// integrates the fast spin of a gyroscope exactly and only the gravity kicks carry the O(h²) error —
// the regime of the fast Lagrange top (Brüls, Cardona, Arnold 2012; shared/NUMERICS.md: "integrate the
// spin about the symmetry axis exactly"). Using the exact symmetric free flow inside splittings:
// Celledoni, Fassò, Säfström, Zanna, SIAM J. Sci. Comput. 30 (2008) 2084, §1 (no equation number there
// for this flow; the formulas above are derived in this header and verified by the tests).
//
// Applies to problems that declare `static constexpr bool axisymmetric = true` (LagrangeTop): their
// inertia is diag(I1, I1, I3) — checked by the constructor, which throws std::invalid_argument
// otherwise — and their torque has M3 ≡ 0 (the step does not read M3).
#pragma once

#include "../core/integrator.hpp"
#include "../core/problem.hpp"
#include "../core/so3.hpp"
#include "../core/state.hpp"

#include <cmath>
#include <stdexcept>

namespace lgi {

template <class P>
concept AxisymmetricProblem = RigidBodyProblem<P> && requires {
  { P::axisymmetric } -> std::convertible_to<bool>;
  requires P::axisymmetric;
};

template <RigidBodyProblem P>
class LagrangeSplit {
 public:
  using Problem = P;
  using Scalar = typename P::Scalar;
  // (R, Π) and the torque at R, the next step's first kick.
  struct Internal {
    Mat3<Scalar> R;
    Vec3<Scalar> Pi;
    Vec3<Scalar> M;
  };

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
  }

  Internal to_internal(const State<Scalar>& x, const Scalar& t) const
    requires AxisymmetricProblem<P>
  {
    return {x.R, Vec3<Scalar>(I1_ * x.Omega.x(), I1_ * x.Omega.y(), I3_ * x.Omega.z()), torque(t, x.R)};
  }
  State<Scalar> to_state(const Internal& y) const
    requires AxisymmetricProblem<P>
  {
    return {y.R, Vec3<Scalar>(y.Pi.x() * inv_I1_, y.Pi.y() * inv_I1_, y.Pi.z() / I3_)};
  }

  LGI_FLATTEN StepStatus step(Internal& y, const Scalar& t, const Scalar& h)
    requires AxisymmetricProblem<P>
  {
    using T = Scalar;
    using std::cos;
    using std::sin;
    const T half_h = T(0.5) * h;
    // kick (Π3 untouched: M3 ≡ 0)
    Vec3<T> Pi = y.Pi;
    Pi.x() += half_h * y.M.x();
    Pi.y() += half_h * y.M.y();
    // drift: R exp(hΠ/I1) exp(φ ê3), Π ← exp(−φ ê3) Π
    const Mat3<T> dA = so3::exp_increment(Vec3<T>((h * inv_I1_) * Pi));
    const T phi = h * Pi.z() * spin_;
    const T s = sin(phi);
    const T half_s = sin(T(0.5) * phi);
    const T cm1 = T(-2) * half_s * half_s;  // cos φ − 1 without cancellation
    // E − I = dA + dB + dA dB, with dB = B − I nonzero only in its upper-left 2×2 block [[c−1, −s], [s, c−1]].
    Mat3<T> dE = dA;
    for (int r = 0; r < 3; ++r) {
      const T a0 = dA(r, 0), a1 = dA(r, 1);
      dE(r, 0) += a0 * cm1 + a1 * s;
      dE(r, 1) += a1 * cm1 - a0 * s;
    }
    dE(0, 0) += cm1;
    dE(1, 1) += cm1;
    dE(0, 1) -= s;
    dE(1, 0) += s;
    const Mat3<T> R1 = y.R + y.R * dE;
    // Π + (B − I)ᵀ Π: as an increment, since fl(1 + (cos φ − 1)) would round the same way every step
    // (φ is constant while Π3 is) and bias |Π| linearly in the number of steps (core/so3.hpp).
    Vec3<T> Pi1(Pi.x() + (cm1 * Pi.x() + s * Pi.y()), Pi.y() + (cm1 * Pi.y() - s * Pi.x()), Pi.z());
    // kick
    const Vec3<T> M1 = torque(t + h, R1);
    Pi1.x() += half_h * M1.x();
    Pi1.y() += half_h * M1.y();
    if (!all_finite(R1) || !all_finite(Pi1) || !all_finite(M1)) return StepStatus::non_finite;
    y = {R1, Pi1, M1};
    return StepStatus::ok;
  }

  const P& problem() const { return problem_; }

 private:
  Vec3<Scalar> torque(const Scalar& t, const Mat3<Scalar>& R) const { return body_torque(problem_, t, R); }

  P problem_;
  Scalar I1_{}, I3_{}, inv_I1_{}, spin_{};
};

}  // namespace lgi
