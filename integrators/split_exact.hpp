// lgi/integrators/split_exact.hpp — Strang splitting of a torqued rigid body with the exact free-body
// flow: kick(h/2) ∘ exact free body(h) ∘ kick(h/2).
//
// Update (body frame, Π = JΩ, M(t, R) the body-frame torque):
//
//   Π⁺ = Π_n + ½ h M(t_n, R_n)
//   (R_{n+1}, Π⁻) = φ_h(R_n, Π⁺)              the exact Euler–Poinsot flow (problems/free_body_exact.hpp:
//                                              Jacobi elliptic functions and Π(n; φ, κ), Celledoni, Fassò,
//                                              Säfström & Zanna, SIAM J. Sci. Comput. 30 (2008) 2084, with
//                                              Leroy's corrections)
//   Π_{n+1} = Π⁻ + ½ h M(t_n + h, R_{n+1})
//
// Splitting with the exact free-body flow: CFSZ §5 (the splitting of H = T + V into the exact flows of T
// and of V). Order 2 with a torque (symmetric, so compositions raise it: composition.hpp); exact (to
// round-off) on the free body. Symplectic (a composition of exact Hamiltonian flows), explicit, m·k and
// |Γ| kept to round-off, R on SO(3) to round-off (the exact flow's increments). Scalars: double and long
// double only (Boost's elliptic integrals; no ceres::Jet). Cost: one exact flow (≈ µs: two Carlson
// integrals and an AGM per call), so this is a reference-quality method, not a fast one.
#pragma once

#include "../core/state_io.hpp"
#include "../core/integrator.hpp"
#include "../core/problem.hpp"
#include "../core/state.hpp"
#include "../problems/free_body_exact.hpp"

#include <type_traits>

namespace lgi {

template <RigidBodyProblem P>
  requires std::is_floating_point_v<typename P::Scalar>
class SplitExact {
 public:
  using Problem = P;
  using Scalar = typename P::Scalar;
  // (R, Π) and the torque at R, the next step's first kick.
  struct Internal {
    Mat3<Scalar> R;
    Vec3<Scalar> Pi;
    Vec3<Scalar> M;
    LGI_NUMBERS(R, Pi, M)
  };

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

  explicit SplitExact(const P& problem, const StepperOptions& options = {})
      : problem_(problem), exact_(problem.inertia) {
    options.check();
  }

  Internal to_internal(const State<Scalar>& x, const Scalar& t) const {
    return {x.R, Vec3<Scalar>(problem_.inertia * x.Omega), torque(t, x.R)};
  }
  State<Scalar> to_state(const Internal& y) const {
    return {y.R, Vec3<Scalar>(problem_.inertia.ldlt().solve(y.Pi))};
  }

  // Not LGI_FLATTEN: flattening would inline all of Boost's elliptic integrals into the step (GCC then
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
