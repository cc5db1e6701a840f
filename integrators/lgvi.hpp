/// \file
/// lgi/integrators/lgvi.hpp — the Lie group variational integrator of Lee, Leok & McClamroch.
///
/// Update (Lee, Leok, McClamroch, Proc. IEEE CCA 2005, 962–967; Comput. Methods Appl. Mech. Engrg. 196
/// (2007) 2907, §3), with Π = JΩ, the body-frame torque M_k = M(t_k, R_k) and J_d = ½ tr(J) I − J:
///
/// ~~~{.unparsed}
///   h hat(Π_k + ½ h M_k) = F_k J_d − J_d F_kᵀ           solve for F_k ∈ SO(3)
///   R_{k+1} = R_k F_k
///   Π_{k+1} = F_kᵀ (Π_k + ½ h M_k) + ½ h M_{k+1}
/// ~~~
///
/// Implicit stage. Writing F through the unit quaternion (1, c)/√(1 + c·c), i.e. the Cayley map of 2c,
/// F = I + 2/(1 + c·c) (hat(c) + hat(c)²), the identity F J_d − J_d Fᵀ = hat(2/(1 + c·c) (Jc + c × Jc))
/// (valid for any symmetric J) turns the matrix equation into three scalar ones,
///
/// ~~~{.unparsed}
///   G(c) = J c + c × (J c) − ½ (1 + c·c) μ = 0,           μ = h (Π_k + ½ h M_k),
/// ~~~
///
/// which in principal axes is Hairer's fixed point c_i = α w_i + ((I_j − I_k)/I_i) c_j c_k (HLW, GNI 2nd
/// ed., §VII.5.3, eq. (5.27)). From c₀ = ½J⁻¹μ two sweeps of that fixed point, c ← J⁻¹(½αμ − c × Jc),
/// give the predictor (error O(|c|⁵)); then Newton, dG = J + hat(c) J − hat(Jc) − μ cᵀ (written out for a
/// diagonal J), until the update is below `tolerance`·|c| or, by the quadratic convergence bound
/// |e⁺| ≤ K|Δ|², K = ‖J⁻¹‖(‖J‖ + |μ|), the next one would be — one update at ordinary step sizes — within
/// `max_iterations` updates;
/// otherwise the step reports StepStatus::not_converged and leaves the state untouched. Updates below
/// 16 cond(J) ε |c| count as converged: round-off allows no better. With a Jet scalar one more Newton
/// update follows convergence (not counted against the limit), so the derivative part is exact as well
/// (implicit function theorem). R_{k+1} is a product of rotations: orthogonal to round-off, never re-orthonormalised.
/// The method steps (R, Π) and keeps M_{k+1} for the next step's first kick: one torque per step, and
/// no J⁻¹ round trip (core/state.hpp).
///
/// Order 2. Symplectic, symmetric (time-reversible), preserves the spatial momentum the torque leaves
/// alone (m for the free body, m·k for the heavy top) to round-off for any F, and the Casimirs; energy
/// error bounded (no drift) over exponentially long times. For the free body it is the discrete
/// Moser–Veselov algorithm (RATTLE; HLW Remark VII.5.2): a steady rotation about a principal axis with
/// rate ω advances by asin(hω) per step, not hω — DMV's error is a time reparametrisation (McLachlan &
/// Zanna, FoCM 5 (2005) 87).
///
/// Forced (a StateTorqueProblem, core/problem.hpp: damping, feedback control). The discrete Lagrange–d'Alembert
/// principle (Marsden & West, Acta Numerica 10 (2001), §3.2; NUMERICS.md) with the forcing split evenly between the
/// ends of the step, f_d^∓ = ½ h M_nc (for the LGVI with control moments see also Lee, Leok & McClamroch, J. Dyn.
/// Control Syst. 14 (2008)), keeps the update above with
/// M_k = M(t_k, R_k, Ω_k) — the first kick stays explicit — and makes the last one implicit in Π_{k+1}:
///
/// ~~~{.unparsed}
///   Π_{k+1} = Fᵀ (Π_k + ½ h M_k) + ½ h M(t_{k+1}, R_{k+1}, J⁻¹Π_{k+1}),
/// ~~~
///
/// solved by Newton on r(Π) = Π − Fᵀ(Π_k + ½hM_k) − ½hM(…, J⁻¹Π), dr = I − ½h D J⁻¹ with D = ∂M/∂Ω taken from the
/// problem's torque_omega_jacobian (exact) or by forward differences at the predictor (a chord method: the
/// solution is the same, the convergence linear with a small ratio), until |r| ≤ tolerance · (|Π| + |½hM|) — one
/// update for a torque linear in Ω with an exact D. A Jet scalar takes one more update after convergence (two with
/// forward differences), so that its derivative parts converge as well.
/// Order 2 and symmetric (the explicit first and implicit last half kick are each other's adjoints). Not
/// symplectic: the forcing does work. R_{k+1} stays a product of rotations. A problem whose torque does not read Ω
/// takes the conservative step above (the same code).
#pragma once

#include "../core/state_io.hpp"
#include "../core/inertia.hpp"
#include "../core/integrator.hpp"
#include "../core/problem.hpp"
#include "../core/so3.hpp"
#include "../core/state.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace lgi {

/// The LGVI (this header) as a Stepper on problem P: implicit, order 2, symplectic (unforced), symmetric; it steps
/// (R, Π) and keeps the torque for the next step's first kick.
template <RigidBodyProblem P>
class Lgvi {
 public:
  using Problem = P;                    ///< the problem type
  using Scalar = typename P::Scalar;    ///< its scalar
  /// (R, Π) and the torque M(t, R) at the current attitude, the first kick of the next step.
  struct Internal {
    Mat3<Scalar> R;   ///< attitude, body → laboratory
    Vec3<Scalar> Pi;  ///< body angular momentum Π = JΩ
    Vec3<Scalar> M;   ///< body-frame torque at (t, R), zero for a torque-free problem
    LGI_NUMBERS(R, Pi, M)
  };

  /// The method's traits (`lgi list`, the README's method table).

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
      .options = {"tolerance", "max_iterations"},
  };

  /// Copies the problem; options: the Newton tolerance and max_iterations (std::invalid_argument from
  /// StepperOptions::check when they are out of range).
  explicit Lgvi(const P& problem, const StepperOptions& options = {})
      : problem_(problem), J_(problem.inertia), options_(options) {
    options.check();
    const auto inf_norm = [](const Mat3<Scalar>& M) {
      double n = 0;
      for (int r = 0; r < 3; ++r) {
        double row = 0;
        for (int c = 0; c < 3; ++c) row += std::abs(static_cast<double>(value_of(M(r, c))));
        n = std::max(n, row);
      }
      return n;
    };
    J_norm_ = inf_norm(J_.J);
    J_inv_norm_ = inf_norm(J_.J_inv);
    const Vec3<Scalar> I = J_.J.diagonal();
    d_ = Vec3<Scalar>(I(2) - I(1), I(0) - I(2), I(1) - I(0));
    inv_I_ = J_.J_inv.diagonal();
  }

  /// (R, JΩ, M(t, R, Ω)) of x at time t: one torque evaluation.
  Internal to_internal(const State<Scalar>& x, const Scalar& t) const {
    if constexpr (StateTorqueProblem<P>)
      return {x.R, J_.apply(x.Omega), body_torque(problem_, t, x.R, x.Omega)};
    else
      return {x.R, J_.apply(x.Omega), torque(t, x.R)};
  }
  /// (R, J⁻¹Π) of y.
  State<Scalar> to_state(const Internal& y) const { return {y.R, J_.solve(y.Pi)}; }

  /// One step from t to t + h (h of either sign). not_converged when Newton does not converge within
  /// max_iterations, non_finite when an update or the new state is not finite; y is untouched unless ok. Cost: one
  /// torque, two fixed-point sweeps and the Newton updates (each a 3×3 solve by Cramer's rule); no allocation.
  /// Forced: the last kick's Newton adds one torque per update (and three for a forward-difference D).
  LGI_FLATTEN StepStatus step(Internal& y, const Scalar& t, const Scalar& h) {
    using T = Scalar;
    const T half_h = T(0.5) * h;
    Vec3<T> Pi = y.Pi;
    if constexpr (P::has_torque) Pi += half_h * y.M;
    Vec3<T> c;
    if (const StepStatus s = solve_cayley(Vec3<T>(h * Pi), c); s != StepStatus::ok) return s;
    const T s = T(2) / (T(1) + c.squaredNorm());
    const Mat3<T> dF = so3::rodrigues_increment(c, s, s);  // F − I = s (hat(c) + hat(c)²)
    const Mat3<T> R1 = y.R + y.R * dF;                      // R F, without rounding F's diagonal
    Vec3<T> Pi1 = Pi + dF.transpose() * Pi;                 // Fᵀ Π
    Vec3<T> M1;
    if constexpr (StateTorqueProblem<P>) {
      if (const StepStatus st = last_kick(t + h, R1, half_h, Pi1, y.M, M1); st != StepStatus::ok) return st;
    } else {
      M1 = torque(t + h, R1);
      if constexpr (P::has_torque) Pi1 += half_h * M1;
    }
    if (!all_finite(R1) || !all_finite(Pi1)) return StepStatus::non_finite;
    y = {R1, Pi1, M1};
    return StepStatus::ok;
  }

  /// Newton updates taken over the stepper's lifetime (a diagnostic: iterations per step).
  std::int64_t newton_iterations() const { return iterations_; }
  /// The problem, as copied at construction.
  const P& problem() const { return problem_; }

 private:
  Vec3<Scalar> torque(const Scalar& t, const Mat3<Scalar>& R) const
    requires AttitudeTorqueProblem<P>
  {
    if constexpr (P::has_torque)
      return body_torque(problem_, t, R);
    else
      return Vec3<Scalar>::Zero();
  }

  /// The forced last kick (the header): on entry Pi holds Fᵀ(Π_k + ½hM_k); on exit Π_{k+1}, and M1 = M(t1, R1, Ω_{k+1}).
  /// The predictor adds ½h M_k (M at the start of the step, O(h) from M1).
  StepStatus last_kick(const Scalar& t1, const Mat3<Scalar>& R1, const Scalar& half_h, Vec3<Scalar>& Pi,
                       const Vec3<Scalar>& M0, Vec3<Scalar>& M1)
    requires StateTorqueProblem<P>
  {
    using T = Scalar;
    const Vec3<T> base = Pi;
    Pi = base + half_h * M0;
    const auto M_at = [&](const Vec3<T>& P1) { return Vec3<T>(body_torque(problem_, t1, R1, J_.solve(P1))); };
    M1 = M_at(Pi);
    // D = ∂M/∂Ω: the problem's, or forward differences at the predictor.
    Mat3<T> D;
    constexpr bool exact_D = requires { problem_.torque_omega_jacobian(t1, R1, Pi); };
    if constexpr (exact_D) {
      D = problem_.torque_omega_jacobian(t1, R1, J_.solve(Pi));
    } else {
      const Vec3<T> Omega = J_.solve(Pi);
      for (int j = 0; j < 3; ++j) {
        const double w = static_cast<double>(value_of(Omega(j)));
        const double delta = std::sqrt(static_cast<double>(epsilon_v<T>)) * std::max(1.0, std::abs(w));
        Vec3<T> Od = Omega;
        Od(j) += T(delta);
        D.col(j) = (Vec3<T>(body_torque(problem_, t1, R1, Od)) - M1) / T(delta);
      }
    }
    const Mat3<T> A = Mat3<T>::Identity() - half_h * D * J_.J_inv;
    const Vec3<T> r0 = A.row(0), r1 = A.row(1), r2 = A.row(2);
    const Vec3<T> c12 = r1.cross(r2), c20 = r2.cross(r0), c01 = r0.cross(r1);
    const T det = r0.dot(c12);
    const double tol = std::max(options_.tolerance, static_cast<double>(16 * epsilon_v<T>));
    // Jets: updates after convergence make the derivative parts converge too — one with the exact D (Newton),
    // two with forward differences (each contracts by the chord's ratio, O(√ε)).
    int polish = is_dual_v<T> ? (exact_D ? 1 : 2) : 0;
    for (int it = 0;; ++it) {
      const Vec3<T> r = Pi - base - half_h * M1;
      const double res = static_cast<double>(value_of(r.cwiseAbs().maxCoeff()));
      const double scale = static_cast<double>(value_of(Pi.cwiseAbs().maxCoeff())) +
                           std::abs(static_cast<double>(value_of(half_h))) *
                               static_cast<double>(value_of(M1.cwiseAbs().maxCoeff()));
      if (!std::isfinite(res)) return StepStatus::non_finite;
      const bool converged = res <= tol * scale;
      if (!converged && it >= options_.max_iterations) return StepStatus::not_converged;
      if (converged && polish-- == 0) return StepStatus::ok;
      Pi -= (r(0) * c12 + r(1) * c20 + r(2) * c01) / det;  // A⁻¹ r by Cramer's rule
      ++iterations_;
      M1 = M_at(Pi);
    }
  }

  /// One sweep of the fixed point c ← J⁻¹(½αμ − c × Jc), α = 1 + c·c.
  Vec3<Scalar> sweep(const Vec3<Scalar>& c, const Vec3<Scalar>& half_mu) const {
    using T = Scalar;
    if (J_.diagonal) {  // Hairer's c_i = α w_i + r_i c_j c_k, w = J⁻¹ ½μ, r_i = −d_i/I_i
      const T a = T(1) + c.squaredNorm();
      return Vec3<T>((a * half_mu(0) - d_(0) * c(1) * c(2)) * inv_I_(0), (a * half_mu(1) - d_(1) * c(2) * c(0)) * inv_I_(1),
                     (a * half_mu(2) - d_(2) * c(0) * c(1)) * inv_I_(2));
    }
    return J_.solve(Vec3<T>((T(1) + c.squaredNorm()) * half_mu - c.cross(J_.apply(c))));
  }

  /// The Newton update Δ = dG⁻¹ G for G(c) = Jc + c × Jc − ½(1 + c·c) μ, dG = J + hat(c) J − hat(Jc) − μ cᵀ,
  /// solved by Cramer's rule. For diagonal J = diag(I), G_i = I_i c_i + d_i c_j c_k − ½αμ_i and dG is
  /// diag(I) plus off-diagonal entries d_i c_k ({i, j, k} = {0, 1, 2}), minus μ cᵀ, written out in scalars.
  Vec3<Scalar> newton_update(const Vec3<Scalar>& c, const Vec3<Scalar>& half_mu) const {
    using T = Scalar;
    const T a = T(1) + c.squaredNorm();
    const Vec3<T> mu = T(2) * half_mu;
    Vec3<T> G;
    Mat3<T> dG;
    if (J_.diagonal) {
      const T &c0 = c(0), &c1 = c(1), &c2 = c(2);
      G << J_.J(0, 0) * c0 + d_(0) * c1 * c2 - a * half_mu(0),  //
          J_.J(1, 1) * c1 + d_(1) * c2 * c0 - a * half_mu(1),    //
          J_.J(2, 2) * c2 + d_(2) * c0 * c1 - a * half_mu(2);
      dG << J_.J(0, 0) - mu(0) * c0, d_(0) * c2 - mu(0) * c1, d_(0) * c1 - mu(0) * c2,  //
          d_(1) * c2 - mu(1) * c0, J_.J(1, 1) - mu(1) * c1, d_(1) * c0 - mu(1) * c2,    //
          d_(2) * c1 - mu(2) * c0, d_(2) * c0 - mu(2) * c1, J_.J(2, 2) - mu(2) * c2;
    } else {
      const Vec3<T> Jc = J_.apply(c);
      G = Jc + c.cross(Jc) - a * half_mu;
      dG = J_.J + so3::hat(c) * J_.J - so3::hat(Jc) - mu * c.transpose();
    }
    const Vec3<T> r0 = dG.row(0), r1 = dG.row(1), r2 = dG.row(2);
    const Vec3<T> c12 = r1.cross(r2), c20 = r2.cross(r0), c01 = r0.cross(r1);
    return (G(0) * c12 + G(1) * c20 + G(2) * c01) / r0.dot(c12);
  }

  /// Solves G(c) = 0 (see the header): two sweeps of the fixed point, then Newton.
  StepStatus solve_cayley(const Vec3<Scalar>& mu, Vec3<Scalar>& c) {
    using T = Scalar;
    const Vec3<T> half_mu = T(0.5) * mu;
    c = J_.solve(half_mu);
    c = sweep(c, half_mu);
    c = sweep(c, half_mu);
    const double K = J_inv_norm_ * (J_norm_ + static_cast<double>(value_of(mu.cwiseAbs().maxCoeff())));
    // Below this the update is round-off: the solve cannot resolve c better than cond(J)·ε.
    const double floor = std::max(options_.tolerance, static_cast<double>(16 * epsilon_v<T>) * J_norm_ * J_inv_norm_);
    for (int it = 0; it < options_.max_iterations; ++it) {
      const Vec3<T> delta = newton_update(c, half_mu);
      c -= delta;
      ++iterations_;
      const double d = static_cast<double>(value_of(delta.cwiseAbs().maxCoeff()));
      const double scale = static_cast<double>(value_of(c.cwiseAbs().maxCoeff()));
      if (!std::isfinite(d)) return StepStatus::non_finite;
      const bool converged = d <= floor * scale ||                                            // update small
                             (d <= 1e-3 * scale && 4 * K * d * d <= options_.tolerance * scale);  // next one would be
      if (converged) {
        if constexpr (is_dual_v<T>) {  // one more update makes the derivative part exact (IFT)
          c -= newton_update(c, half_mu);
          ++iterations_;
        }
        return StepStatus::ok;
      }
    }
    return StepStatus::not_converged;
  }

  P problem_;
  Inertia<Scalar> J_;
  StepperOptions options_;
  double J_norm_ = 0, J_inv_norm_ = 0;
  Vec3<Scalar> d_;      ///< (I3 − I2, I1 − I3, I2 − I1) from J's diagonal
  Vec3<Scalar> inv_I_;  ///< diagonal of J⁻¹ (used when J is diagonal)
  std::int64_t iterations_ = 0;
};

}  // namespace lgi
