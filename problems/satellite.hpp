/// \file
/// lgi/problems/satellite.hpp — a rigid satellite on a circular orbit under the gravity-gradient torque.
///
/// The centre of mass moves on a circular Keplerian orbit of rate n = √(μ/r³) (prescribed: the attitude
/// does not act back on the orbit). Laboratory frame: inertial, origin at the centre of mass, axes fixed.
/// Orbit: unit radial vector r̂(t) = cos(nt) r̂0 + sin(nt) (ν × r̂0), ν the unit orbit normal (ν ⊥ r̂0).
/// R: attitude body → inertial; Ω: body angular velocity relative to inertial space; J: inertia about
/// the centre of mass. With ρ = Rᵀ r̂(t), the radial direction seen from the body:
/// ~~~{.unparsed}
///   J Ω' = (JΩ) × Ω + M,    M(t, R) = 3 n² ρ × (J ρ),    R' = R hat(Ω)
/// ~~~
/// (the Newtonian potential of the body expanded to second order in its size, MacCullagh's formula
/// −μm/r − (μ/2r³)(tr J − 3 r̂·(R J Rᵀ r̂)); textbook result, e.g. Hughes, Spacecraft Attitude Dynamics
/// (1986) — chapter and equation numbers not checked). Potential (dropping the constant terms):
/// ~~~{.unparsed}
///   V(t, R) = (3n²/2) ρ·(J ρ);   check: R → R exp(η̂) gives ρ → ρ + ρ × η, δV = 3n² (Jρ)·(ρ × η)
///   = η·(3n² (Jρ) × ρ), so −∂V/∂η = 3n² ρ × Jρ = M.
/// ~~~
/// The torque depends on time explicitly: torque(t, R) (core/problem.hpp), never a reduced-attitude problem.
///
/// What is conserved. In the inertial frame V depends on t, so neither the energy ½ Ω·JΩ + V nor any
/// component of m = RJΩ is: dE/dt = ∂V/∂t, dm/dt = R M. In the frame rotating with the orbit (rate n
/// about ν) the problem is autonomous, and its Hamiltonian, the Jacobi integral
/// ~~~{.unparsed}
///   C = ½ Ω·JΩ + V(t, R) − n ν·(R J Ω)
/// ~~~
/// is conserved: dC/dt = ∂V/∂t − n ν·(R M), and ∂V/∂t = 3n² (ṙ̂)ᵀ R J ρ = 3n³ (ν × r̂)·(R J ρ) =
/// n ν·(r̂ × R J ρ) = n ν·(R M). Output: the energy column is the inertial energy ½ Ω·JΩ + V(t, R) (not
/// conserved; potential(t, R)), the invariant column "jacobi" is C. Both need the time: potential(R) and
/// invariants(x) without it return NaN (nothing else would be right), potential_at/invariants_at
/// (core/problem.hpp) call the timed versions.
/// Relative equilibrium (used by the tests): principal axes aligned with the orbit frame (r̂, ν × r̂, ν)
/// and Ω = n Rᵀν: R(t) = exp(nt ν̂) R0 exactly. Small pitch oscillations about it (rotation about ν, J
/// principal with moments A along r̂, B along ν × r̂, C along ν) obey θ'' = −3n² ((B − A)/C) sin θ cos θ:
/// a pendulum in 2θ of small-amplitude frequency n √(3 (B − A)/C).
/// Default data: J = diag(1, 2, 3) (A < B: pitch-stable), n = 1, r̂0 = e1, ν = e3.
#pragma once

#include "../core/invariants.hpp"
#include "../core/problem.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <string_view>

namespace lgi {

/// The gravity-gradient satellite as a time-dependent RigidBodyProblem (this header). The data are not checked
/// here: radial0 and normal unit and orthogonal, n ≥ 0.
template <class T = double>
struct Satellite {
  using Scalar = T;                                      ///< the scalar type
  static constexpr std::string_view name = "satellite";  ///< the scene's problem.type
  static constexpr bool has_torque = true;               ///< the gravity-gradient torque

  Mat3<T> inertia = Vec3<T>(T(1), T(2), T(3)).asDiagonal();  ///< J about the centre of mass, body frame
  T n = T(1);                                ///< orbital rate
  Vec3<T> radial0 = Vec3<T>::UnitX();        ///< r̂(0), unit, inertial frame
  Vec3<T> normal = Vec3<T>::UnitZ();         ///< ν, unit, ⊥ r̂(0)

  /// r̂(t) = cos(nt) r̂0 + sin(nt) ν × r̂0.
  Vec3<T> radial(const T& t) const {
    using std::cos;
    using std::sin;
    const T phase = n * t;
    return cos(phase) * radial0 + sin(phase) * Vec3<T>(normal.cross(radial0));
  }

  /// V(t, R) = (3n²/2) ρ·(J ρ), ρ = Rᵀ r̂(t).
  T potential(const T& t, const Mat3<T>& R) const {
    const Vec3<T> rho = R.transpose() * radial(t);
    return T(1.5) * n * n * rho.dot(inertia * rho);
  }
  /// M(t, R) = 3 n² ρ × (J ρ), body frame, ρ = Rᵀ r̂(t).
  Vec3<T> torque(const T& t, const Mat3<T>& R) const {
    const Vec3<T> rho = R.transpose() * radial(t);
    return (T(3) * n * n) * Vec3<T>(rho.cross(inertia * rho));
  }
  /// Without the time the potential is undefined (see the header): NaN, never a plausible wrong number.
  T potential(const Mat3<T>&) const { return T(std::numeric_limits<double>::quiet_NaN()); }

  /// The Jacobi integral C = ½ Ω·JΩ + V(t, R) − n ν·(R J Ω).
  T jacobi_integral(const T& t, const State<T>& x) const {
    return kinetic_energy(inertia, x.Omega) + potential(t, x.R) - n * normal.dot(spatial_momentum(inertia, x));
  }

  /// The extra output column: the Jacobi integral C.
  static constexpr std::array<std::string_view, 1> invariant_names{"jacobi"};
  /// {C} of x at time t.
  std::array<T, 1> invariants(const T& t, const State<T>& x) const { return {jacobi_integral(t, x)}; }
  /// Without the time C is undefined: {NaN} (use invariants_at, core/problem.hpp).
  std::array<T, 1> invariants(const State<T>&) const { return {T(std::numeric_limits<double>::quiet_NaN())}; }

  /// The same satellite in scalar S (e.g. double → ceres::Jet).
  template <class S>
  Satellite<S> cast() const {
    return {inertia.template cast<S>(), S(n), radial0.template cast<S>(), normal.template cast<S>()};
  }
};

}  // namespace lgi
