/// \file
/// lgi/problems/free_body.hpp — the free rigid body (Euler–Poinsot).
///
/// Equations (seed paper, eq. (s0)–(s1)):   J Ω' = (JΩ) × Ω,    R' = R hat(Ω).
/// Invariants: energy E = ½ Ω·JΩ; the spatial angular momentum m = R J Ω (all three components); the
/// Casimir |JΩ| (the body momentum's length). J is any symmetric positive-definite tensor about the
/// centre of mass.
/// Default data: J = diag(0.6, 0.8, 1.0), m0 = JΩ0 = (1.8, 0.4, −0.9), R0 = I — the free body of Hairer &
/// Vilmart, J. Phys. A 39 (2006) 13225 (their numerical experiments), as listed in shared/NUMERICS.md.
#pragma once

#include "../core/invariants.hpp"
#include "../core/problem.hpp"

#include <array>
#include <string_view>

namespace lgi {

/// The free rigid body as a RigidBodyProblem (this header): no torque, only the inertia tensor.
template <class T = double>
struct FreeBody {
  using Scalar = T;                                      ///< the scalar type
  static constexpr std::string_view name = "free_body";  ///< the scene's problem.type
  static constexpr bool has_torque = false;              ///< integrators skip the torque

  /// J about the centre of mass, body frame; symmetric positive definite (not checked here: inertia_defect).
  Mat3<T> inertia = Mat3<T>::Identity();

  /// V = 0.
  T potential(const Mat3<T>&) const { return T(0); }
  /// M = 0.
  Vec3<T> torque(const Mat3<T>&) const { return Vec3<T>::Zero(); }

  /// The extra output columns: the spatial momentum m = R J Ω and the Casimir |JΩ|.
  static constexpr std::array<std::string_view, 4> invariant_names = momentum_column_names;
  /// (m1, m2, m3, |JΩ|) of x, in the order of invariant_names.
  std::array<T, 4> invariants(const State<T>& x) const { return momentum_columns(inertia, x); }

  /// The same body in scalar S (e.g. double → ceres::Jet).
  template <class S>
  FreeBody<S> cast() const {
    return {inertia.template cast<S>()};
  }

  /// The Hairer–Vilmart body: J = diag(0.6, 0.8, 1.0).
  static FreeBody hairer_vilmart() { return {Vec3<T>(T(0.6), T(0.8), T(1.0)).asDiagonal()}; }
};

}  // namespace lgi
