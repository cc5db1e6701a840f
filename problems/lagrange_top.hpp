/// \file
/// lgi/problems/lagrange_top.hpp — the Lagrange top: a symmetric heavy top, centre of mass on the axis.
///
/// Body frame: principal axes, J = diag(I1, I1, I3) about the fixed point, symmetry axis e3, centre of
/// mass on it (z0 = e3). k: unit laboratory vector opposite to gravity, any direction — the seed paper's
/// choice k = (0, k2, k3) (Deriglazov, Sect. II, Fig. 1(b)) among them. b = a·L·μ ≥ 0.
/// Equations (seed paper eqs. (s4)–(s5) with z0 = e3):
/// ~~~{.unparsed}
///   J Ω' = (JΩ) × Ω + b Γ × e3,    R' = R hat(Ω),    Γ = Rᵀk,
/// ~~~
/// i.e. I1 Ω1' = (I1 − I3) Ω2 Ω3 + b Γ2,  I1 Ω2' = (I3 − I1) Ω3 Ω1 − b Γ1,  I3 Ω3' = 0.
/// Potential V(R) = b k·(R e3) = b Γ3 (the paper's b(k2 R23 + k3 R33) for k = (0, k2, k3)); torque
/// M = b Γ × e3 = b (Γ2, −Γ1, 0): its third component is exactly zero, which is what makes
/// m_ψ = I3 Ω3 an integral (paper eq. (s6.1): m_ψ = I3(ψ' + φ' cos θ) = I3 Ω3 in Euler angles (6.3)).
/// Invariants: energy E = ½ Ω·JΩ + b Γ3 (paper eq. (s12) in Euler angles); m·k = k·(R J Ω), the
/// paper's m_φ (eq. (s13) and its footnote); m_ψ = I3 Ω3 (eq. (s6.1)); the Casimir |Γ| = 1.
/// The struct declares `axisymmetric`: J = diag(I1, I1, I3) and M3 ≡ 0, which the splitting of
/// integrators/lagrange_split.hpp (gravity kicks around the exact symmetric free flow) relies on.
///
/// Default data: fast_top() is the fast Lagrange top of Brüls, Cardona & Arnold, Mech. Mach. Theory 48
/// (2012) 121, as listed in shared/NUMERICS.md (J = diag(15.234375, 0.46875, 15.234375) about the fixed
/// point, b = 147.15, z0 = e2, k = e3, Ω0 = (0, 150, −4.61538), R0 = I, T = 2), with the body axes
/// relabelled cyclically (e1', e2', e3') = (e3, e1, e2) so that the symmetry axis is e3: J' = diag(
/// 15.234375, 15.234375, 0.46875), Ω0' = (−4.61538, 0, 150), R0' = [e3 e1 e2] (laboratory frame and k
/// unchanged, so z0 = R0' e3 = e2 in the laboratory at t = 0, as in the original). The relabelling is a
/// constant change of body frame: the laboratory motion is the same (tests compare it with HeavyTop on
/// the original data).
#pragma once

#include "../core/invariants.hpp"
#include "../core/problem.hpp"
#include "heavy_top.hpp"

#include <array>
#include <string_view>

namespace lgi {

/// The Lagrange top as a RigidBodyProblem (this header). Build it with make() so that J = diag(I1, I1, I3); the
/// data are not checked here (k must be a unit vector, b ≥ 0).
template <class T = double>
struct LagrangeTop {
  using Scalar = T;                                         ///< the scalar type
  static constexpr std::string_view name = "lagrange_top";  ///< the scene's problem.type
  static constexpr bool has_torque = true;                  ///< gravity's torque
  static constexpr bool axisymmetric = true;  ///< J = diag(I1, I1, I3), M3 ≡ 0 (see the header)

  Mat3<T> inertia = Mat3<T>::Identity();  ///< diag(I1, I1, I3): construct with make()
  T b = T(0);                             ///< a·L·μ ≥ 0: gravity × distance to the centre of mass × mass
  Vec3<T> k = Vec3<T>::UnitZ();           ///< unit laboratory vector opposite to gravity
  /// k (UniformGravityProblem, core/problem.hpp).
  Vec3<T> gravity_axis() const { return k; }
  /// e3: the centre of mass on the symmetry axis (UniformGravityProblem).
  Vec3<T> mass_axis() const { return Vec3<T>::UnitZ(); }

  /// The top with J = diag(I1, I1, I3), b and k (I1, I3 > 0 with I3 ≤ 2 I1, b ≥ 0, |k| = 1: not checked).
  static LagrangeTop make(const T& I1, const T& I3, const T& b, const Vec3<T>& k = Vec3<T>::UnitZ()) {
    return {Vec3<T>(I1, I1, I3).asDiagonal(), b, k};
  }

  /// V(R) = b k·(R e3).
  T potential(const Mat3<T>& R) const { return b * k.dot(R.col(2)); }
  /// M(R) = b Γ × e3 with Γ = Rᵀk, body frame.
  Vec3<T> torque(const Mat3<T>& R) const { return reduced_torque(Vec3<T>(R.transpose() * k)); }
  /// The torque depends on R only through Γ = Rᵀk (core/problem.hpp, ReducedAttitudeProblem).
  const Vec3<T>& reduced_axis() const { return k; }
  /// M = b (Γ2, −Γ1, 0), its third component an exact zero.
  Vec3<T> reduced_torque(const Vec3<T>& Gamma) const { return Vec3<T>(b * Gamma.y(), -(b * Gamma.x()), T(0)); }
  /// b e3: reduced_torque(Γ) = Γ × (b e3) (LeverTorqueProblem).
  Vec3<T> reduced_torque_lever() const { return Vec3<T>(T(0), T(0), b); }

  /// The same top as a HeavyTop (z0 = e3): its torque b Γ × e3 and potential b k·(R e3) are this one's, term for term,
  /// with exact zeros where this one writes 0 (the sign of a zero may differ).
  HeavyTop<T> as_heavy_top() const { return {inertia, b, k, Vec3<T>::UnitZ()}; }

  /// The extra output columns: m·k (the seed paper's m_φ) and m_ψ = I3 Ω3.
  static constexpr std::array<std::string_view, 2> invariant_names{"momentum_k", "momentum_psi"};
  /// {k·(R J Ω), I3 Ω3} of x.
  std::array<T, 2> invariants(const State<T>& x) const {
    return {k.dot(spatial_momentum(inertia, x)), inertia(2, 2) * x.Omega.z()};
  }

  /// The same top in scalar S (e.g. double → ceres::Jet).
  template <class S>
  LagrangeTop<S> cast() const {
    return {inertia.template cast<S>(), S(b), k.template cast<S>()};
  }

  /// The fast Lagrange top of Brüls, Cardona & Arnold (2012), body axes relabelled (see the header).
  static LagrangeTop fast_top() { return make(T(15.234375), T(0.46875), T(147.15), Vec3<T>::UnitZ()); }
  /// Its initial state, relabelled likewise: R0 = [e3 e1 e2], Ω0 = (−4.61538, 0, 150) (the source integrates to
  /// T = 2).
  static State<T> fast_top_state() {
    Mat3<T> R0;
    R0 << T(0), T(1), T(0),  //
        T(0), T(0), T(1),    //
        T(1), T(0), T(0);
    return {R0, Vec3<T>(T(-4.61538), T(0), T(150))};
  }
};

}  // namespace lgi
