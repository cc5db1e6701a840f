// lgi/integrators/lgvi.hpp — the Lie group variational integrator of Lee, Leok & McClamroch.
//
// Update (Lee, Leok, McClamroch, Proc. IEEE CCA 2005, 962–967; Comput. Methods Appl. Mech. Engrg. 196
// (2007) 2907, §3), with Π = JΩ, the body-frame torque M_k = M(t_k, R_k) and J_d = ½ tr(J) I − J:
//
//   h hat(Π_k + ½ h M_k) = F_k J_d − J_d F_kᵀ           solve for F_k ∈ SO(3)
//   R_{k+1} = R_k F_k
//   Π_{k+1} = F_kᵀ (Π_k + ½ h M_k) + ½ h M_{k+1}
//
// Implicit stage. Writing F through the unit quaternion (1, c)/√(1 + c·c), i.e. the Cayley map of 2c,
// F = I + 2/(1 + c·c) (hat(c) + hat(c)²), the identity F J_d − J_d Fᵀ = hat(2/(1 + c·c) (Jc + c × Jc))
// (valid for any symmetric J) turns the matrix equation into three scalar ones,
//
//   G(c) = J c + c × (J c) − ½ (1 + c·c) μ = 0,           μ = h (Π_k + ½ h M_k),
//
// which in principal axes is Hairer's fixed point c_i = α w_i + ((I_j − I_k)/I_i) c_j c_k (HLW, GNI 2nd
// ed., §VII.5.3, eq. (5.27)). We take the predictor c = J⁻¹(½αμ − c₀ × Jc₀) from c₀ = ½J⁻¹μ, then Newton,
// dG = J + hat(c) J − hat(Jc) − μ cᵀ, until the update is below `tolerance`·|c| (or, from the quadratic
// convergence bound |e⁺| ≤ K|Δ|², K = ‖J⁻¹‖(‖J‖ + |μ|), until K|Δ|² is), within `max_iterations` updates;
// otherwise the step reports StepStatus::not_converged and leaves the state untouched. With a Jet scalar
// one more Newton update follows convergence, so the derivative part is exact as well (implicit function
// theorem). R_{k+1} is a product of rotations: orthogonal to round-off, never re-orthonormalised.
//
// Order 2. Symplectic, symmetric (time-reversible), preserves the spatial momentum the torque leaves
// alone (m for the free body, m·k for the heavy top) to round-off for any F, and the Casimirs; energy
// error bounded (no drift) over exponentially long times. For the free body it is the discrete
// Moser–Veselov algorithm (RATTLE; HLW Remark VII.5.2): a steady rotation about a principal axis with
// rate ω advances by asin(hω) per step, not hω — DMV's error is a time reparametrisation (McLachlan &
// Zanna, FoCM 5 (2005) 87).
#pragma once

#include "../core/inertia.hpp"
#include "../core/integrator.hpp"
#include "../core/problem.hpp"
#include "../core/so3.hpp"
#include "../core/state.hpp"

#include <cstdint>

namespace lgi {

template <RigidBodyProblem P>
class Lgvi {
 public:
  using Problem = P;
  using Scalar = typename P::Scalar;
  using Internal = MomentumState<Scalar>;  // (R, Π): no J⁻¹ round trip inside the run

  static constexpr MethodTraits traits{
      .name = "lgvi",
      .title = "Lie group variational integrator (Lee-Leok-McClamroch)",
      .order = 2,
      .symplectic = true,
      .symmetric = true,
      .explicit_method = false,
      .exact_on_group = true,
      .preserves_momentum = true,
      .reference = "Lee, Leok, McClamroch, IEEE CCA 2005; CMAME 196 (2007) 2907",
  };

  explicit Lgvi(const P& problem, const StepperOptions& options = {})
      : problem_(problem), J_(problem.inertia), options_(options) {
    const auto inf_norm = [](const Mat3<Scalar>& M) {
      double n = 0;
      for (int r = 0; r < 3; ++r)
        n = std::max(n, static_cast<double>(value_of(abs_(M(r, 0)) + abs_(M(r, 1)) + abs_(M(r, 2)))));
      return n;
    };
    J_norm_ = inf_norm(J_.J);
    J_inv_norm_ = inf_norm(J_.J_inv);
  }

  Internal to_internal(const State<Scalar>& x) const { return {x.R, J_.apply(x.Omega)}; }
  State<Scalar> to_state(const Internal& y) const { return {y.R, J_.solve(y.Pi)}; }

  StepStatus step(Internal& x, const Scalar& t, const Scalar& h) {
    using T = Scalar;
    const T half_h = T(0.5) * h;
    Vec3<T> Pi = x.Pi;
    if constexpr (P::has_torque) Pi += half_h * body_torque(problem_, t, x.R);
    Vec3<T> c;
    if (const StepStatus s = solve_cayley(h * Pi, c); s != StepStatus::ok) return s;

    // F = I + s (hat(c) + hat(c)²), s = 2/(1 + c·c)
    const T s = T(2) / (T(1) + c.squaredNorm());
    const Mat3<T> C = so3::hat(c);
    Mat3<T> F = s * (C + C * C);
    F.diagonal().array() += T(1);
    const Mat3<T> R1 = x.R * F;
    Vec3<T> Pi1 = F.transpose() * Pi;
    if constexpr (P::has_torque) Pi1 += half_h * body_torque(problem_, t + h, R1);
    return commit(x, R1, Pi1);
  }

  // Newton updates taken over the stepper's lifetime (a diagnostic: iterations per step).
  std::int64_t newton_iterations() const { return iterations_; }
  const P& problem() const { return problem_; }

 private:
  template <class U>
  static U abs_(const U& u) {
    return value_of(u) < 0 ? U(-u) : u;
  }

  // Solves G(c) = Jc + c × Jc − ½(1 + c·c) μ = 0 (see the header).
  StepStatus solve_cayley(const Vec3<Scalar>& mu, Vec3<Scalar>& c) {
    using T = Scalar;
    const Vec3<T> half_mu = T(0.5) * mu;
    c = J_.solve(half_mu);
    c = J_.solve((T(1) + c.squaredNorm()) * half_mu - c.cross(J_.apply(c)));
    const double K = J_inv_norm_ * (J_norm_ + static_cast<double>(value_of(mu.cwiseAbs().maxCoeff())));
    double last = 0;
    bool converged = false;
    for (int it = 0; it < options_.max_iterations; ++it) {
      const Vec3<T> Jc = J_.apply(c);
      const Vec3<T> G = Jc + c.cross(Jc) - (T(1) + c.squaredNorm()) * half_mu;
      Mat3<T> dG = so3::hat(c) * J_.J - so3::hat(Jc) - mu * c.transpose();
      dG += J_.J;
      const Vec3<T> delta = dG.inverse() * G;
      c -= delta;
      ++iterations_;
      if (converged) return StepStatus::ok;  // the extra update for the derivative part (Jets)
      const double d = static_cast<double>(value_of(delta.cwiseAbs().maxCoeff()));
      const double scale = static_cast<double>(value_of(c.cwiseAbs().maxCoeff()));
      if (!std::isfinite(d)) return StepStatus::non_finite;
      converged = d <= options_.tolerance * scale ||                                   // update small
                  (d <= 1e-3 * scale && 4 * K * d * d <= options_.tolerance * scale) ||  // next one would be
                  (it > 0 && d > 0.5 * last && last <= 1e-8 * scale);                   // round-off floor
      if (converged && !is_dual_v<T>) return StepStatus::ok;
      last = d;
    }
    return StepStatus::not_converged;
  }

  P problem_;
  Inertia<Scalar> J_;
  StepperOptions options_;
  double J_norm_ = 0, J_inv_norm_ = 0;
  std::int64_t iterations_ = 0;
};

}  // namespace lgi
