/// \file
/// lgi/problems/kovalevskaya_top.hpp — the Kovalevskaya top.
///
/// A heavy top (seed paper eqs. (s4)–(s5)) with principal moments about the fixed point I1 = I2 = 2 I3
/// (body frame: principal axes, J = diag(2c, 2c, c), c = I3 > 0) and its centre of mass in the equatorial
/// plane: z0 = (cos α, sin α, 0). k: unit laboratory vector opposite to gravity; b = a·L·μ ≥ 0.
/// ~~~{.unparsed}
///   J Ω' = (JΩ) × Ω + b Γ × z0,    R' = R hat(Ω),    Γ = Rᵀk,  Γ' = Γ × Ω.
/// ~~~
/// Potential V(R) = b k·(R z0) = b Γ·z0; torque M = b Γ × z0.
///
/// Kovalevskaya's integral in this project's conventions (derived here; S. Kowalevski, Acta Math. 12
/// (1889) 177 states it in normalised units, J = diag(2, 2, 1) and the centre of mass on the first axis;
/// equation numbers there not checked). Write ξ = Ω1 + iΩ2, η = Γ1 + iΓ2, ζ0 = z0_1 + i z0_2 = e^{iα},
/// s = b/I3. For α = 0 the equations above read
/// ~~~{.unparsed}
///   2Ω1' = Ω2Ω3,   2Ω2' = −Ω1Ω3 + s Γ3,   Ω3' = −s Γ2,
/// ~~~
/// so ξ' = −(i/2)Ω3 ξ + (i/2) s Γ3 and η' = Γ × Ω in complex form = −iΩ3 η + iΓ3 ξ; then
/// ~~~{.unparsed}
///   (ξ² − s η)' = 2ξξ' − s η' = −iΩ3 ξ² + i s Γ3 ξ + i s Ω3 η − i s Γ3 ξ = −iΩ3 (ξ² − s η),
/// ~~~
/// a pure phase rotation, hence
/// ~~~{.unparsed}
///   K = |(Ω1 + iΩ2)² − (b/I3) ζ0 (Γ1 + iΓ2)|²          (for any α: rotate the body frame by α about e3;
///                                                       ξ² picks up e^{−2iα}, η e^{−iα})
/// ~~~
/// is conserved. Units: 1/time⁴. The sign of the Γ term follows from k pointing against gravity
/// (V = +b k·R z0); with Γ along gravity it flips. The tests check by measurement that K is
/// conserved to the reference's accuracy by a high-accuracy integration and that a wrong constant (2b/I3)
/// or a wrong inertia ratio is not.
/// Invariants: energy E = ½ Ω·JΩ + b Γ·z0; m·k = k·(R J Ω) (the paper's m_φ, eq. (s13) footnote);
/// K above; the Casimir |Γ| = 1.
/// Default data: c = 1 (J = diag(2, 2, 1)), b = 1, z0 = e1, k = e3 — Kowalevski's normalisation.
#pragma once

#include "../core/invariants.hpp"
#include "../core/problem.hpp"
#include "heavy_top.hpp"

#include <array>
#include <string_view>

namespace lgi {

/// The Kovalevskaya top as a RigidBodyProblem (this header). Build it with make(); the data are not checked here
/// (k and z0 unit vectors, z0 in the equatorial plane, b ≥ 0).
template <class T = double>
struct KovalevskayaTop {
  using Scalar = T;                                             ///< the scalar type
  static constexpr std::string_view name = "kovalevskaya_top";  ///< the scene's problem.type
  static constexpr bool has_torque = true;                      ///< gravity's torque

  Mat3<T> inertia = Vec3<T>(T(2), T(2), T(1)).asDiagonal();  ///< diag(2 I3, 2 I3, I3): construct with make()
  T b = T(1);                     ///< a·L·μ ≥ 0: gravity × distance to the centre of mass × mass
  Vec3<T> k = Vec3<T>::UnitZ();   ///< unit laboratory vector opposite to gravity
  Vec3<T> z0 = Vec3<T>::UnitX();  ///< equatorial: z0_3 = 0
  /// k (UniformGravityProblem, core/problem.hpp).
  Vec3<T> gravity_axis() const { return k; }
  /// z0 (UniformGravityProblem).
  Vec3<T> mass_axis() const { return z0; }

  /// The top with J = diag(2 I3, 2 I3, I3), b, k and z0 (I3 > 0, b ≥ 0, unit k and z0 with z0_3 = 0: not checked).
  static KovalevskayaTop make(const T& I3, const T& b, const Vec3<T>& k = Vec3<T>::UnitZ(),
                              const Vec3<T>& z0 = Vec3<T>::UnitX()) {
    return {Vec3<T>(T(2) * I3, T(2) * I3, I3).asDiagonal(), b, k, z0};
  }

  /// V(R) = b k·(R z0).
  T potential(const Mat3<T>& R) const { return b * k.dot(R * z0); }
  /// M(R) = b (Rᵀk) × z0, body frame.
  Vec3<T> torque(const Mat3<T>& R) const { return reduced_torque(Vec3<T>(R.transpose() * k)); }
  /// k: the torque depends on R only through Γ = Rᵀk (ReducedAttitudeProblem).
  const Vec3<T>& reduced_axis() const { return k; }
  /// M = b Γ × z0 as a function of Γ = Rᵀk.
  Vec3<T> reduced_torque(const Vec3<T>& Gamma) const { return b * Gamma.cross(z0); }
  /// b z0: reduced_torque(Γ) = Γ × (b z0) (LeverTorqueProblem).
  Vec3<T> reduced_torque_lever() const { return b * z0; }

  /// The same top as a HeavyTop: the same equations of motion, operation for operation (the integrators give the same
  /// bits for both).
  HeavyTop<T> as_heavy_top() const { return {inertia, b, k, z0}; }

  /// K = |(Ω1 + iΩ2)² − (b/I3)(z0_1 + i z0_2)(Γ1 + iΓ2)|².
  T kovalevskaya_integral(const State<T>& x) const {
    const Vec3<T> G = x.R.transpose() * k;
    const Vec3<T>& W = x.Omega;
    const T s = b / inertia(2, 2);
    const T re = W.x() * W.x() - W.y() * W.y() - s * (z0.x() * G.x() - z0.y() * G.y());
    const T im = T(2) * W.x() * W.y() - s * (z0.x() * G.y() + z0.y() * G.x());
    return re * re + im * im;
  }

  /// The extra output columns: m·k and Kovalevskaya's integral K.
  static constexpr std::array<std::string_view, 2> invariant_names{"momentum_k", "kovalevskaya"};
  /// {k·(R J Ω), K} of x.
  std::array<T, 2> invariants(const State<T>& x) const {
    return {k.dot(spatial_momentum(inertia, x)), kovalevskaya_integral(x)};
  }

  /// The same top in scalar S (e.g. double → ceres::Jet).
  template <class S>
  KovalevskayaTop<S> cast() const {
    return {inertia.template cast<S>(), S(b), k.template cast<S>(), z0.template cast<S>()};
  }
};

}  // namespace lgi
