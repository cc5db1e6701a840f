/// \file
/// lgi/problems/heavy_top.hpp — the heavy top: a rigid body with a fixed point in uniform gravity.
///
/// Equations (seed paper, Deriglazov, eqs. (s4)–(s5)):
/// ~~~{.unparsed}
///   J Ω' = (JΩ) × Ω + b (Rᵀk) × z0,    R' = R hat(Ω),
/// ~~~
/// with J the inertia tensor about the fixed point (symmetric positive definite, any orientation: the
/// paper's point is that it is diagonal only in principal axes, eqs. (s0.02)–(s0.03)), k the unit
/// laboratory vector opposite to gravity, z0 the unit body vector from the fixed point to the centre of
/// mass, b = a·L·μ ≥ 0 (gravity × distance × mass). b = 0 is the free body.
/// Potential V(R) = b k·(R z0) = b Γ·z0 with Γ = Rᵀk (k seen from the body); torque M = b Γ × z0.
/// Invariants: energy E = ½ Ω·JΩ + b k·(R z0); the projection of the spatial momentum on k,
/// m·k = k·(R J Ω) — the paper's m_φ, eq. (s13) and its footnote; the Casimir |Γ| = 1 (exact while R is
/// orthogonal). For the Lagrange top (J = diag(I2, I2, I3), z0 = e3) also m_ψ = I3 Ω3 (eq. (s6.1)).
/// Default data: the Hairer–Vilmart heavy top, J = diag(0.6, 0.8, 1.0), b = 1, k = z0 = e3 (NUMERICS.md).
#pragma once

#include "../core/invariants.hpp"
#include "../core/problem.hpp"

#include <array>
#include <string_view>

namespace lgi {

/// The heavy top as a RigidBodyProblem (this header's equations). The data are not checked here (the scene loader
/// checks them): k and z0 must be unit vectors and b ≥ 0 for the conventions above to hold.
template <class T = double>
struct HeavyTop {
  using Scalar = T;                                      ///< the scalar type
  static constexpr std::string_view name = "heavy_top";  ///< the scene's problem.type
  static constexpr bool has_torque = true;               ///< gravity's torque

  Mat3<T> inertia = Mat3<T>::Identity();  ///< J about the fixed point, body frame, symmetric positive definite
  T b = T(0);                             ///< a·L·μ ≥ 0: gravity × distance to the centre of mass × mass
  Vec3<T> k = Vec3<T>::UnitZ();           ///< unit laboratory vector opposite to gravity
  Vec3<T> z0 = Vec3<T>::UnitZ();          ///< unit body vector from the fixed point to the centre of mass
  /// k (UniformGravityProblem, core/problem.hpp).
  Vec3<T> gravity_axis() const { return k; }
  /// z0 (UniformGravityProblem).
  Vec3<T> mass_axis() const { return z0; }

  /// V(R) = b k·(R z0).
  T potential(const Mat3<T>& R) const { return b * k.dot(R * z0); }
  /// M(R) = b (Rᵀk) × z0, body frame.
  Vec3<T> torque(const Mat3<T>& R) const { return reduced_torque(Vec3<T>(R.transpose() * k)); }
  /// The torque depends on R only through Γ = Rᵀk (core/problem.hpp, ReducedAttitudeProblem).
  const Vec3<T>& reduced_axis() const { return k; }
  /// M = b Γ × z0 as a function of Γ = Rᵀk.
  Vec3<T> reduced_torque(const Vec3<T>& Gamma) const { return b * Gamma.cross(z0); }
  /// b z0: reduced_torque(Γ) = Γ × (b z0) (LeverTorqueProblem).
  Vec3<T> reduced_torque_lever() const { return b * z0; }

  /// The extra output column: m·k, the spatial momentum's component along k (the seed paper's m_φ).
  static constexpr std::array<std::string_view, 1> invariant_names{"momentum_k"};
  /// {k·(R J Ω)} of x.
  std::array<T, 1> invariants(const State<T>& x) const { return {k.dot(spatial_momentum(inertia, x))}; }

  /// The same top in scalar S (e.g. double → ceres::Jet).
  template <class S>
  HeavyTop<S> cast() const {
    return {inertia.template cast<S>(), S(b), k.template cast<S>(), z0.template cast<S>()};
  }

  /// The Hairer–Vilmart heavy top: J = diag(0.6, 0.8, 1.0), b = 1, k = z0 = e3.
  static HeavyTop hairer_vilmart() {
    return {Vec3<T>(T(0.6), T(0.8), T(1.0)).asDiagonal(), T(1), Vec3<T>::UnitZ(), Vec3<T>::UnitZ()};
  }
};

}  // namespace lgi
