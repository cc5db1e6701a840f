// lgi/integrators/rkmk.hpp — Runge–Kutta–Munthe-Kaas methods for any explicit Butcher tableau.
//
// With body angular velocity the flow is R(t) = R_n exp(u(t)), and u obeys the ODE in the Lie algebra
// (right trivialisation; Hairer–Lubich–Wanner, GNI 2nd ed., eq. (IV.8.9) and Algorithm IV.8.3, with the
// sign of ad flipped for right products):
//
//   u' = J_r⁻¹(u) Ω = Ω + ½ u × Ω + (1/12) u × (u × Ω) + …,     Ω' = J⁻¹((JΩ) × Ω + M(t, R_n exp(u))),
//
// u(0) = 0. One step applies the tableau (a, b, c) to this pair:
//
//   stage i:  u_i = h Σ_j a_ij U_j,   W_i = Ω_n + h Σ_j a_ij V_j,
//             U_i = J_r⁻¹(u_i) W_i (series truncated after ad^(p−2)),   V_i = Ω'(t_n + c_i h, R_n exp(u_i), W_i)
//   update:   R_{n+1} = R_n exp(h Σ b_i U_i),   Ω_{n+1} = Ω_n + h Σ b_i V_i.
//
// The truncation after the ad^(p−2) term keeps the order p of the tableau (HLW Theorem IV.8.5;
// Munthe-Kaas, Appl. Numer. Math. 29 (1999) 115) and makes the stage map a polynomial. Zero tableau
// entries are skipped at compile time; for a torque-free problem no stage attitude is formed at all, and
// for a torque that depends on R only through Γ = Rᵀa (ReducedAttitudeProblem: the heavy top) the stages
// rotate Γ_i = exp(u_i)ᵀ Γ_n instead of forming R_n exp(u_i).
//
// Order: that of the tableau. R stays on SO(3) to round-off (products of exponentials). Not symplectic,
// not symmetric; energy and momentum drift like those of the underlying Runge–Kutta method.
#pragma once

#include "../core/inertia.hpp"
#include "../core/integrator.hpp"
#include "../core/problem.hpp"
#include "../core/so3.hpp"
#include "../core/state.hpp"
#include "butcher_tableaus.hpp"

#include <array>
#include <utility>

namespace lgi {

template <const auto& Tableau, RigidBodyProblem P>
class Rkmk {
 public:
  using Problem = P;
  using Scalar = typename P::Scalar;
  using Internal = State<Scalar>;

  static constexpr MethodTraits traits{
      .name = Tableau.name,
      .title = Tableau.title,
      .order = Tableau.order,
      .symplectic = false,
      .symmetric = false,
      .explicit_method = true,
      .exact_on_group = true,
      .preserves_momentum = false,
      .reference = Tableau.reference,
  };

  explicit Rkmk(const P& problem, const StepperOptions& = {}) : problem_(problem), J_(problem.inertia) {}

  Internal to_internal(const State<Scalar>& x, const Scalar&) const { return x; }
  State<Scalar> to_state(const Internal& y) const { return y; }

  LGI_FLATTEN StepStatus step(Internal& x, const Scalar& t, const Scalar& h) {
    constexpr int S = Tableau.stages;
    std::array<Vec3<Scalar>, S> U, V;
    Vec3<Scalar> Gamma;  // Rᵀa at the start of the step (reduced-attitude problems)
    if constexpr (reduced) Gamma = x.R.transpose() * problem_.reduced_axis();
    [&]<int... I>(std::integer_sequence<int, I...>) {
      (stage<I>(x, Gamma, t, h, U, V), ...);
    }(std::make_integer_sequence<int, S>{});
    Vec3<Scalar> u = Vec3<Scalar>::Zero(), dOmega = Vec3<Scalar>::Zero();
    [&]<int... I>(std::integer_sequence<int, I...>) {
      ([&] {
        if constexpr (Tableau.b[I] != 0) {
          u += Scalar(Tableau.b[I]) * U[I];
          dOmega += Scalar(Tableau.b[I]) * V[I];
        }
      }(), ...);
    }(std::make_integer_sequence<int, S>{});
    // R exp(hu) as R + R (exp(hu) − I): see core/so3.hpp on the rounding of the increment.
    const Mat3<Scalar> R1 = x.R + x.R * so3::exp_increment(Vec3<Scalar>(h * u));
    return commit(x, R1, Vec3<Scalar>(x.Omega + h * dOmega));
  }

  const P& problem() const { return problem_; }

 private:
  static constexpr int series_degree = Tableau.order > 2 ? Tableau.order - 2 : 0;
  static constexpr bool reduced = P::has_torque && ReducedAttitudeProblem<P>;

  // Ω' = J⁻¹((JΩ) × Ω + M)
  Vec3<Scalar> acceleration(const Vec3<Scalar>& Omega, const Vec3<Scalar>& M) const {
    return J_.solve(Vec3<Scalar>(J_.apply(Omega).cross(Omega) + M));
  }
  Vec3<Scalar> acceleration(const Vec3<Scalar>& Omega) const {
    return J_.solve(Vec3<Scalar>(J_.apply(Omega).cross(Omega)));
  }

  template <int I>
  void stage(const State<Scalar>& x, const Vec3<Scalar>& Gamma, const Scalar& t, const Scalar& h,
             std::array<Vec3<Scalar>, Tableau.stages>& U, std::array<Vec3<Scalar>, Tableau.stages>& V) const {
    if constexpr (I == 0) {
      U[0] = x.Omega;
      if constexpr (reduced)
        V[0] = acceleration(x.Omega, problem_.reduced_torque(Gamma));
      else if constexpr (P::has_torque)
        V[0] = acceleration(x.Omega, body_torque(problem_, t, x.R));
      else
        V[0] = acceleration(x.Omega);
    } else {
      Vec3<Scalar> u = Vec3<Scalar>::Zero(), dW = Vec3<Scalar>::Zero();
      [&]<int... J>(std::integer_sequence<int, J...>) {
        ([&] {
          if constexpr (Tableau.a[I][J] != 0) {
            u += Scalar(Tableau.a[I][J]) * U[J];
            dW += Scalar(Tableau.a[I][J]) * V[J];
          }
        }(), ...);
      }(std::make_integer_sequence<int, I>{});
      u *= h;
      const Vec3<Scalar> W = x.Omega + h * dW;
      U[I] = so3::right_jacobian_inverse_series<series_degree>(u, W);
      if constexpr (reduced) {
        const so3::Coefficients<Scalar> k = so3::exp_coefficients(u);  // Γ_i = exp(u)ᵀ Γ = exp(−u) Γ
        V[I] = acceleration(W, problem_.reduced_torque(so3::rotate(u, Scalar(-k.A), k.B, Gamma)));
      } else if constexpr (P::has_torque) {
        const Mat3<Scalar> R = x.R * so3::exp(u);
        V[I] = acceleration(W, body_torque(problem_, t + Scalar(Tableau.c[I]) * h, R));
      } else {
        V[I] = acceleration(W);
      }
    }
  }

  P problem_;
  Inertia<Scalar> J_;
};

template <RigidBodyProblem P>
using LieEuler = Rkmk<tableaus::euler, P>;
template <RigidBodyProblem P>
using Rkmk4 = Rkmk<tableaus::classical_rk4, P>;

}  // namespace lgi
