/// \file
/// lgi/core/problem.hpp — what a rigid-body problem is.
///
/// A problem is a plain struct of parameters (templated on the scalar) with a few physics functions:
///
/// ~~~{.unparsed}
///   using Scalar = T;
///   static constexpr std::string_view name;       // the scene's problem.type
///   static constexpr bool has_torque;             // false: integrators skip the torque entirely
///   Mat3<T> inertia;                              // body frame, symmetric positive definite
///   T       potential(const Mat3<T>& R) const;    // V(R)
///   Vec3<T> torque(const Mat3<T>& R) const;       // body-frame M(R) = −(∂V/∂η) for R → R·exp(η̂)
///                                                 //   (or torque(t, R) for a time-dependent one,
///                                                 //   or torque(t, R, Omega) for one that reads Ω too)
///   static constexpr std::array<std::string_view, N> invariant_names;   // extra output columns
///   std::array<T, N> invariants(const State<T>& x) const;             // their values
///   template <class S> Problem<S> cast() const;   // the same problem in another scalar (Jets)
/// ~~~
///
/// The equations of motion are those of the seed paper, eqs. (s4)–(s5), with the torque in its most general form:
/// ~~~{.unparsed}
///   J Ω' = (JΩ) × Ω + M(t, R, Ω),    R' = R hat(Ω),
/// ~~~
/// with energy E = ½ Ω·JΩ + V(R) (invariants.hpp computes it for every problem). Where M = −∂V/∂η + M_nc(t, R, Ω)
/// (a conservative part and the rest), dE/dt = ∂V/∂t + Ω·M_nc: the work of M_nc is the only change of E. A torque
/// that reads Ω (damping, feedback control: StateTorqueProblem below) has no potential in general: the explicit
/// methods (RKMK, commutator-free, the baselines) evaluate it at each stage's (t, R, Ω), the variational integrator
/// and its compositions take it as a forcing (discrete Lagrange–d'Alembert, integrators/lgvi.hpp), and the methods
/// whose kicks hold Ω out of the torque — the splittings, their compositions — and the projection onto energy levels
/// do not take it (AttitudeTorqueProblem). Optional for such a problem:
/// ~~~{.unparsed}
///   Mat3<T> torque_omega_jacobian(const T& t, const Mat3<T>& R, const Vec3<T>& Omega) const;   // ∂M/∂Ω
/// ~~~
/// which spares the forced LGVI's Newton its forward differences.
#pragma once

#include "scalar.hpp"
#include "state.hpp"

#include <array>
#include <cmath>
#include <concepts>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>

namespace lgi {

/// A rigid-body problem: the members of this header's list (Scalar, name, has_torque, inertia, potential(R),
/// torque(R) or torque(t, R), invariant_names, invariants(x)). Checked at compile time only: that the inertia is
/// physical and the torque the derivative of the potential is the problem's own contract.
template <class P>
concept RigidBodyProblem =
    requires(const P& p, const Mat3<typename P::Scalar>& R, const State<typename P::Scalar>& x,
             const typename P::Scalar& t) {
      typename P::Scalar;
      { P::name } -> std::convertible_to<std::string_view>;
      { P::has_torque } -> std::convertible_to<bool>;
      { p.inertia } -> std::convertible_to<Mat3<typename P::Scalar>>;
      { p.potential(R) } -> std::convertible_to<typename P::Scalar>;
      requires(requires { { p.torque(R) } -> std::convertible_to<Vec3<typename P::Scalar>>; } ||
               requires { { p.torque(t, R) } -> std::convertible_to<Vec3<typename P::Scalar>>; } ||
               requires { { p.torque(t, R, x.Omega) } -> std::convertible_to<Vec3<typename P::Scalar>>; });
      P::invariant_names.size();
      { p.invariants(x) } -> std::convertible_to<std::array<typename P::Scalar, P::invariant_names.size()>>;
    };

/// A problem whose torque reads the angular velocity: torque(t, R, Omega) (damping, control; time too).
template <class P>
concept StateTorqueProblem =
    RigidBodyProblem<P> && requires(const P& p, const typename P::Scalar& t, const Mat3<typename P::Scalar>& R,
                                    const Vec3<typename P::Scalar>& Omega) { p.torque(t, R, Omega); };

/// A problem whose torque is a function of time and attitude only, M(t, R): what the splittings need (their kicks
/// hold the attitude fixed and change Ω by the torque of that attitude).
template <class P>
concept AttitudeTorqueProblem = RigidBodyProblem<P> && !StateTorqueProblem<P>;

/// Optional: a torque that depends on the attitude only through Γ = Rᵀa, the image in the body frame of
/// one fixed laboratory axis a (gravity: a = k, the heavy top). Methods that move the attitude by
/// R·exp(u) inside a step then rotate Γ by exp(−u) (≈ 30 flops) instead of forming R·exp(u) (≈ 90):
/// ~~~{.unparsed}
///   Vec3<T> reduced_axis() const;                        // a (laboratory frame)
///   Vec3<T> reduced_torque(const Vec3<T>& Gamma) const;  // M, as a function of Γ = Rᵀa
/// ~~~
/// torque(R) must equal reduced_torque(Rᵀ reduced_axis()). A problem with a torque(t, R) or torque(t, R, Omega)
/// is never treated as reduced (reduced_torque has neither time nor Ω), even if it inherits the two functions.
/// Optional on top of that, where the torque is a cross product with a constant body vector v (gravity on a
/// rigid body: v = b z0):
/// ~~~{.unparsed}
///   Vec3<T> reduced_torque_lever() const;               // v, with reduced_torque(Γ) = Γ × v
/// ~~~
/// The splittings and RKMK with a non-diagonal inertia tensor then compute the torque as one cross product
/// with v turned to principal axes once (integrators/splitting.hpp, rkmk.hpp) and check at construction that
/// it agrees with reduced_torque on e1, e2, e3 (check_reduced_torque_lever below); a derived problem that
/// changes reduced_torque must change or remove the lever too.
template <class P>
concept ReducedAttitudeProblem =
    RigidBodyProblem<P> &&
    requires(const P& p, const Vec3<typename P::Scalar>& g) {
      { p.reduced_axis() } -> std::convertible_to<Vec3<typename P::Scalar>>;
      { p.reduced_torque(g) } -> std::convertible_to<Vec3<typename P::Scalar>>;
    } &&
    !requires(const P& p, const typename P::Scalar& t, const Mat3<typename P::Scalar>& R) { p.torque(t, R); } &&
    !StateTorqueProblem<P>;

/// A reduced-attitude problem with a torque Γ × v of constant lever v (the splittings and RKMK read it).
template <class P>
concept LeverTorqueProblem =
    ReducedAttitudeProblem<P> && P::has_torque && requires(const P& p) { p.reduced_torque_lever(); };

/// A problem's reduced_torque_lever() must describe its reduced_torque(): Γ × v against reduced_torque(Γ) on
/// e1, e2, e3, to 1e-12 of |v| (a derived problem that changes reduced_torque but inherits the lever would
/// otherwise be integrated with the wrong torque). `who` names the integrator in the message.
template <LeverTorqueProblem P>
void check_reduced_torque_lever(const P& problem, std::string_view who) {
  using S = typename P::Scalar;
  using V = value_type_t<S>;
  const Vec3<S> v(problem.reduced_torque_lever());
  const V scale = static_cast<V>(value_of(v.cwiseAbs().maxCoeff()));
  for (int i = 0; i < 3; ++i) {
    const Vec3<S> e = Vec3<S>::Unit(i);
    const Vec3<S> M(problem.reduced_torque(e)), L = e.cross(v);
    for (int j = 0; j < 3; ++j) {
      const V m = static_cast<V>(value_of(M(j))), l = static_cast<V>(value_of(L(j)));
      if (!(std::abs(m - l) <= V(1e-12) * scale))
        throw std::invalid_argument(std::string(who) +
                                    ": the problem's reduced_torque_lever() does not match reduced_torque()");
    }
  }
}

/// Body-frame torque at time t and attitude R: the one place integrators get a torque from, so that every method
/// sees the same function — torque(t, R) for time-dependent problems, reduced_torque(Rᵀa) for reduced-attitude
/// ones (a derived problem that changes the torque must override reduced_torque), torque(R) otherwise. Not for a
/// StateTorqueProblem (its torque needs Ω: the overload below).
template <AttitudeTorqueProblem P>
Vec3<typename P::Scalar> body_torque(const P& p, const typename P::Scalar& t, const Mat3<typename P::Scalar>& R) {
  if constexpr (requires { p.torque(t, R); })
    return p.torque(t, R);
  else if constexpr (ReducedAttitudeProblem<P>)
    return p.reduced_torque(Vec3<typename P::Scalar>(R.transpose() * p.reduced_axis()));
  else
    return p.torque(R);
}

/// Body-frame torque at (t, R, Ω): torque(t, R, Omega) for a StateTorqueProblem; otherwise the overload above, Ω
/// unused (the explicit methods call this one at every stage: a torque that does not read Ω is never given one).
template <RigidBodyProblem P>
Vec3<typename P::Scalar> body_torque(const P& p, const typename P::Scalar& t, const Mat3<typename P::Scalar>& R,
                                     const Vec3<typename P::Scalar>& Omega) {
  if constexpr (StateTorqueProblem<P>)
    return p.torque(t, R, Omega);
  else
    return body_torque(p, t, R);
}

/// Potential and invariants at time t. A time-dependent problem (torque(t, R), e.g. problems/satellite.hpp)
/// may also define potential(t, R) and invariants(t, x), which these prefer; its potential(R) and
/// invariants(x) cannot know the time (the satellite's return NaN). Outputs that know t should use these.
template <RigidBodyProblem P>
typename P::Scalar potential_at(const P& p, const typename P::Scalar& t, const Mat3<typename P::Scalar>& R) {
  if constexpr (requires { p.potential(t, R); })
    return p.potential(t, R);
  else
    return p.potential(R);
}
/// The problem's extra invariants at time t: invariants(t, x) where the problem defines it, else invariants(x)
/// (a `std::array<Scalar, N>` in the order of invariant_names).
template <RigidBodyProblem P>
auto invariants_at(const P& p, const typename P::Scalar& t, const State<typename P::Scalar>& x) {
  if constexpr (requires { p.invariants(t, x); })
    return p.invariants(t, x);
  else
    return p.invariants(x);
}

/// Optional: uniform gravity, the potential b k·(R z0) of a heavy top: the unit laboratory axis k opposite to gravity
/// and the unit body axis z0 from the fixed point to the centre of mass. What reads it: the state functions of
/// sweeps (γ = Rᵀk, the tilt of z0, its height), apps/sweep_observe.cpp.
/// ~~~{.unparsed}
///   Vec3<T> gravity_axis() const;   // k
///   Vec3<T> mass_axis() const;      // z0
/// ~~~
template <class P>
concept UniformGravityProblem = requires(const P& p) {
  { p.gravity_axis() } -> std::convertible_to<Vec3<typename P::Scalar>>;
  { p.mass_axis() } -> std::convertible_to<Vec3<typename P::Scalar>>;
};

/// A problem stated in coordinates other than SO(3)×R³ (the seed paper's Euler-angle top,
/// problems/euler_angle_top.hpp) that names the same body on SO(3):
/// ~~~{.unparsed}
///   auto heavy_top() const;   // the RigidBodyProblem with the same motion
/// ~~~
template <class P>
concept CoordinateProblem = !RigidBodyProblem<P> && requires(const P& p) { p.heavy_top(); };

/// The problem type P re-instantiated on scalar S (such as `HeavyTop<double>` → `HeavyTop<Jet>`).
template <class P, class S>
using rebind_problem_t = decltype(std::declval<const P&>().template cast<S>());

}  // namespace lgi
