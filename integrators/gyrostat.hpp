/// \file
/// lgi/integrators/gyrostat.hpp — integrators for a rigid body with rotors (problems/gyrostat.hpp): the LGVI in the
/// gyrostat's Routh-reduced form, its compositions, and RKMK on SO(3) × R^{3+N}.
///
/// **GyrostatLgvi** (scene name `lgvi` on a gyrostat). The rotor angles are cyclic (the Lagrangian of body and rotors,
/// Hughes §3.5, reads only their rates), so their momenta h are the state and the body moves under the Routhian
/// K(H) = ½ (H − A h)·J_b⁻¹(H − A h) = ½ H·J_b⁻¹H − H·w + const, w = J_b⁻¹ A h, on the Lie–Poisson space of (R, H)
/// (H' = H × ∇K, R' = R hat(∇K)); the state keeps m = R H (problems/gyrostat.hpp). One step of size τ from t is the
/// symmetric composition
///
/// ~~~{.unparsed}
///   kick⁺(τ/2, t) ∘ gyro(τ/2) ∘ body(τ) ∘ gyro(τ/2) ∘ kick⁻(τ/2, t + τ)        (applied left to right)
///
///   gyro(s):  R ← R exp(−s ŵ)                                   the exact flow of −H·w (h, m fixed)
///   body(τ):  τ hat(Rᵀm) = F J_d − J_d Fᵀ,  R ← R F               the LGVI of ½ H·J_b⁻¹H, J_d = ½ tr(J_b) I − J_b
///                                                              (lgvi.hpp: the discrete Moser–Veselov step; m fixed)
///   kick⁺(s, t):  z ← z + s f(t, R, z)                            z = (m, h), explicit, at the start of the step
///   kick⁻(s, t):  z⁺ = z + s f(t, R, z⁺)                          implicit, at the end
/// ~~~
///
/// with f = (R M(t, R, Ω), g) the external torque and the rotor torques (problems/gyrostat.hpp). The two kicks are
/// each other's adjoints (the forced LGVI's discrete Lagrange–d'Alembert forcing split evenly between the ends of the
/// step: Marsden & West, Acta Numerica 10 (2001), §3.2), gyro and body are symmetric (gyro exact), so the step is
/// symmetric and of order 2 (Strang splitting; McLachlan & Quispel, Acta Numerica 11 (2002), §2.4, §3), and its
/// compositions (composition.hpp) keep their orders. f is affine in z at fixed (t, R), so kick⁻ is one linear solve:
/// (I − s D)(z⁺ − z) = s f(z), D = ∂f/∂z (GyrostatDynamics::forcing_jacobian).
///
/// Preserved: every sub-step moves R by a rotation (R orthogonal to round-off); m changes only by the external
/// torque's kicks — with internal torques only (friction, motors, the wheel PD law) it is the same number at every
/// step, and R H = R Rᵀ m equals it to R's orthogonality. Each h_i changes only by its kicks (constant without motor
/// torques). Conservative (no torque reads z, none depends on t): each sub-step is a Poisson map of (R, H), so the
/// step is symplectic on the symplectic leaves and its energy error bounded. Friction alone: kick⁻ is implicit Euler
/// on the gradient flow h' = −C ∇_h E, which lowers E; kick⁺ (explicit Euler) does for τ c_i/I_s,i small.
///
/// **GyrostatRkmk<Tableau>** (the RKMK tableaus' scene names on a gyrostat). The Runge–Kutta–Munthe-Kaas method of
/// the tableau (Munthe-Kaas, BIT 38 (1998) 92; Hairer, Lubich & Wanner, GNI 2nd ed., §IV.8.2, Algorithm 8.3) on
/// SO(3) × R^{3+N}, R acted on by exp from the right:
///
/// ~~~{.unparsed}
///   u_i = τ Σ_j a_ij k_j,  z_i = z + τ Σ_j a_ij ℓ_j,  R_i = R exp(u_i)
///   k_i = J_r⁻¹(u_i) Ω(R_i, z_i),  ℓ_i = f(t + c_i τ, R_i, z_i)
///   R⁺ = R exp(τ Σ b_i k_i),  z⁺ = z + τ Σ b_i ℓ_i
/// ~~~
///
/// with J_r⁻¹ in closed form (core/so3.hpp), so the order is the tableau's for every tableau. Explicit, fixed steps
/// (an embedded pair's main weights), R orthogonal to round-off; m is constant without external torque (a linear
/// invariant of z' = f), no other invariant is kept.
#pragma once

#include "../core/integrator.hpp"
#include "../core/so3.hpp"
#include "../problems/free_body.hpp"
#include "../problems/gyrostat.hpp"
#include "butcher_tableaus.hpp"
#include "lgvi.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <utility>

namespace lgi {

/// What the gyrostat's steppers share: the problem's precomputed dynamics and the maps between (R, Ω) and (R, m, h).
template <class P>
class GyrostatSteps {
 public:
  using Problem = P;                           ///< Gyrostat<T>
  using Scalar = typename P::Scalar;           ///< its scalar
  using Internal = GyrostatState<Scalar>;      ///< (R, m, h)
  using Dynamics = GyrostatDynamics<Scalar>;   ///< J_b⁻¹, A, A⁺ and the forcing

  /// Precomputes the problem's dynamics.
  explicit GyrostatSteps(const P& problem) : dyn_(problem) {}
  /// (R, m, h) of x, the rotors at the problem's initial relative rates.
  Internal to_internal(const State<Scalar>& x, const Scalar&) const { return dyn_.state(x.R, x.Omega); }
  /// (R, Ω) of y.
  State<Scalar> to_state(const Internal& y) const { return {y.R, dyn_.omega(y.R, y.m, y.h)}; }
  /// The problem's precomputed dynamics.
  const Dynamics& dynamics() const { return dyn_; }

 protected:
  Dynamics dyn_;  ///< the problem's dynamics
};

/// The gyrostat LGVI (this header) on P = Gyrostat<T>: order 2, symmetric, R H exact under internal torques.
template <class P>
class GyrostatLgvi : public GyrostatSteps<P> {
  using Base = GyrostatSteps<P>;
  using Base::dyn_;

 public:
  using typename Base::Dynamics;
  using typename Base::Internal;
  using typename Base::Scalar;

  /// The traits (scene name `lgvi`, as on the bodies without rotors; the summary says "forced" where a torque reads
  /// the state).
  static constexpr MethodTraits traits{
      .name = "lgvi",
      .title = "Lie group variational integrator, gyrostat (Routh-reduced: rotor momenta, LGVI of the body)",
      .order = 2,
      .symplectic = true,
      .symmetric = true,
      .explicit_method = false,
      .exact_on_group = true,
      .preserves_momentum = true,
      .reference = "Lee, Leok, McClamroch, CMAME 196 (2007) 2907; Hughes, Spacecraft Attitude Dynamics, sec. 3.5",
      .options = {"tolerance", "max_iterations"},
  };

  /// Copies the problem; options as the LGVI's (its Newton solve of the body part).
  explicit GyrostatLgvi(const P& problem, const StepperOptions& options = {})
      : Base(problem), body_(FreeBody<Scalar>{problem.body_inertia()}, options) {}

  /// One step from t to t + τ (either sign); y untouched unless ok (not_converged from the body part's Newton,
  /// non_finite). Cost: two forcing evaluations, the body's LGVI solve, two 3×3 exponentials, one 9×9 LU where a
  /// torque reads the state; no allocation.
  StepStatus step(Internal& y, const Scalar& t, const Scalar& tau) {
    using T = Scalar;
    const T s = T(0.5) * tau;
    Internal z = y;
    kick_explicit(z, t, s);
    gyro(z, s);
    typename Lgvi<FreeBody<T>>::Internal b{z.R, Vec3<T>(z.R.transpose() * z.m), Vec3<T>::Zero()};
    if (const StepStatus st = body_.step(b, t, tau); st != StepStatus::ok) return st;
    z.R = b.R;
    gyro(z, s);
    kick_implicit(z, t + tau, s);
    if (!all_finite(z.R) || !all_finite(z.m) || !all_finite(z.h)) return StepStatus::non_finite;
    y = z;
    return StepStatus::ok;
  }

  /// Newton updates of the body part over the stepper's lifetime.
  std::int64_t newton_iterations() const { return body_.newton_iterations(); }

 private:
  using VecZ = typename Dynamics::VecZ;
  static constexpr int N = Dynamics::N;

  void kick_explicit(Internal& z, const Scalar& t, const Scalar& s) const {
    const VecZ f = dyn_.forcing(t, z.R, z.m, z.h);
    z.m += s * f.template head<3>();
    z.h += s * f.template tail<N>();
  }
  void kick_implicit(Internal& z, const Scalar& t, const Scalar& s) const {
    VecZ dz = s * dyn_.forcing(t, z.R, z.m, z.h);
    if (dyn_.reads_state()) {
      typename Dynamics::MatZ A = -s * dyn_.forcing_jacobian(t, z.R);
      A.diagonal().array() += Scalar(1);
      solve_in_place(A, dz, 3 + dyn_.problem().rotor_count);
    }
    z.m += dz.template head<3>();
    z.h += dz.template tail<N>();
  }
  /// x ← A⁻¹ x on the leading n × n block (the rest of A is the identity, of x zero): Gaussian elimination with
  /// partial pivoting. A is I − sD with s D small at any step the body part converges for, so the pivots are ≈ 1.
  static void solve_in_place(typename Dynamics::MatZ& A, VecZ& x, int n) {
    using std::abs;
    for (int k = 0; k < n; ++k) {
      int p = k;
      for (int i = k + 1; i < n; ++i)
        if (abs(value_of(A(i, k))) > abs(value_of(A(p, k)))) p = i;
      if (p != k) {
        A.row(k).swap(A.row(p));
        std::swap(x(k), x(p));
      }
      for (int i = k + 1; i < n; ++i) {
        const Scalar f = A(i, k) / A(k, k);
        for (int j = k + 1; j < n; ++j) A(i, j) -= f * A(k, j);
        x(i) -= f * x(k);
      }
    }
    for (int k = n - 1; k >= 0; --k) {
      Scalar r = x(k);
      for (int j = k + 1; j < n; ++j) r -= A(k, j) * x(j);
      x(k) = r / A(k, k);
    }
  }

  void gyro(Internal& z, const Scalar& s) const {
    const Mat3<Scalar> dE = so3::exp_increment(Vec3<Scalar>(-s * dyn_.rotor_drift(z.h)));  // exp(−s ŵ) − I
    z.R += z.R * dE;  // without rounding the 1s of exp(−s ŵ)'s diagonal (lgvi.hpp)
  }

  Lgvi<FreeBody<Scalar>> body_;
};

/// RKMK with the explicit tableau Tableau on P = Gyrostat<T> (this header): the tableau's order, fixed steps.
template <const auto& Tableau, class P>
class GyrostatRkmk : public GyrostatSteps<P> {
  using Base = GyrostatSteps<P>;
  using Base::dyn_;

 public:
  using typename Base::Dynamics;
  using typename Base::Internal;
  using typename Base::Scalar;

  /// The traits: the tableau's name and order.
  static constexpr MethodTraits traits{
      .name = Tableau.name,
      .title = "Runge-Kutta-Munthe-Kaas on SO(3) x R^(3+N), gyrostat",
      .order = Tableau.order,
      .symplectic = false,
      .symmetric = false,
      .explicit_method = true,
      .exact_on_group = true,
      .preserves_momentum = false,
      .reference = "Munthe-Kaas, BIT 38 (1998) 92; Hairer-Lubich-Wanner, GNI, sec. IV.8.2",
  };

  /// Copies the problem.
  explicit GyrostatRkmk(const P& problem, const StepperOptions& = {}) : Base(problem) {}

  /// One step from t to t + τ; y untouched unless the result is finite. Cost: one forcing and one J_r⁻¹ per stage.
  StepStatus step(Internal& y, const Scalar& t, const Scalar& tau) const {
    std::array<V, S> K;
    [&]<int... I>(std::integer_sequence<int, I...>) { (stage<I>(y, t, tau, K), ...); }(std::make_integer_sequence<int, S>{});
    const V d = tau * tableaus::weighted_sum<Tableau, tableaus::Weights::b, S>(K);
    Internal z = y;
    z.R = y.R * so3::exp(Vec3<Scalar>(d.template head<3>()));
    z.m += d.template segment<3>(3);
    z.h += d.template tail<N>();
    if (!all_finite(z.R) || !all_finite(z.m) || !all_finite(z.h)) return StepStatus::non_finite;
    y = z;
    return StepStatus::ok;
  }

 private:
  static constexpr int N = Dynamics::N;
  static constexpr int S = tableaus::update_stages(Tableau);
  using V = Eigen::Matrix<Scalar, 6 + N, 1>;  ///< (k, ℓ): the so(3) and (m, h) parts of a stage

  /// Stage I: K_I = (k_I, ℓ_I), combined as the two parts they are written as (rkmk.hpp's stage: a packet of K that
  /// straddles two separate stores of the stage just written is not forwarded from the store buffer). The same
  /// operations element by element as on the whole vector, so the same bits.
  template <int I>
  void stage(const Internal& y, const Scalar& t, const Scalar& tau, std::array<V, S>& K) const {
    using T = Scalar;
    Vec3<T> u = Vec3<T>::Zero();
    Eigen::Matrix<T, 3 + N, 1> mh = Eigen::Matrix<T, 3 + N, 1>::Zero();
    [&]<int... J>(std::integer_sequence<int, J...>) {
      ([&] {
        if constexpr (Tableau.a[I][J] != 0) {
          u += T(Tableau.a[I][J]) * K[J].template head<3>();
          mh += T(Tableau.a[I][J]) * K[J].template tail<3 + N>();
        }
      }(), ...);
    }(std::make_integer_sequence<int, I>{});
    u *= tau;
    mh *= tau;
    const Mat3<T> R = I == 0 ? y.R : Mat3<T>(y.R * so3::exp(u));
    const Vec3<T> m = y.m + mh.template head<3>();
    const typename Dynamics::VecN h = y.h + mh.template tail<N>();
    const Vec3<T> Omega = dyn_.omega(R, m, h);
    K[I].template head<3>() = I == 0 ? Omega : Vec3<T>(so3::right_jacobian_inverse(u) * Omega);
    K[I].template tail<3 + N>() = dyn_.forcing(t + T(Tableau.c[I]) * tau, R, m, h);
  }
};

}  // namespace lgi
