/// \file
/// lgi/core/invariants.hpp — the quantities conserved by rigid-body motion, for any problem.
///
/// ~~~{.unparsed}
///   energy           E = ½ Ω·JΩ + V(R)                    (conserved for every autonomous problem)
///   spatial momentum m = R J Ω                            (free body: all of it; heavy top: m·k, the
///                                                          seed paper's m_φ, eq. (s13) and its footnote)
///   body momentum    |JΩ|                                 (free body: a Casimir)
///   orthogonality    ‖RᵀR − I‖_F                          (zero on SO(3))
/// ~~~
/// Problem-specific invariants (m·k, Kovalevskaya's integral, …) live with the problem's `invariants`.
#pragma once

#include "problem.hpp"
#include "so3.hpp"
#include "state.hpp"

#include <array>
#include <string_view>

namespace lgi {

/// ½ Ω·JΩ, J the inertia tensor (body frame) and Ω the body angular velocity; energy units of J·Ω².
template <class T>
T kinetic_energy(const Mat3<T>& J, const Vec3<T>& Omega) {
  return T(0.5) * Omega.dot(J * Omega);
}

/// E = ½ Ω·JΩ + V(R) with p's inertia and potential(R). For a time-dependent problem (problems/satellite.hpp)
/// potential(R) cannot know t: use energy_at.
template <RigidBodyProblem P>
typename P::Scalar energy(const P& p, const State<typename P::Scalar>& x) {
  return kinetic_energy(p.inertia, x.Omega) + p.potential(x.R);
}

/// Energy at time t: a time-dependent problem's potential(t, R) where it has one (core/problem.hpp potential_at).
template <RigidBodyProblem P>
typename P::Scalar energy_at(const P& p, const typename P::Scalar& t, const State<typename P::Scalar>& x) {
  return kinetic_energy(p.inertia, x.Omega) + potential_at(p, t, x.R);
}

/// m = R J Ω, the angular momentum in the laboratory frame (conserved by the free body; its component along k by
/// the heavy top).
template <class T>
Vec3<T> spatial_momentum(const Mat3<T>& J, const State<T>& x) {
  return x.R * (J * x.Omega);
}

/// |JΩ|, the norm of the body angular momentum (a Casimir of the free body: conserved by every torque-free motion).
template <class T>
T body_momentum_norm(const Mat3<T>& J, const State<T>& x) {
  return (J * x.Omega).norm();
}

/// The CSV columns of a body's momentum (the free body's invariants; the columns of the bodies under torques, where
/// they change): momentum_1 … momentum_3 = m = R J Ω, momentum_norm = |JΩ|.
inline constexpr std::array<std::string_view, 4> momentum_column_names{"momentum_1", "momentum_2", "momentum_3",
                                                                       "momentum_norm"};
/// (m1, m2, m3, |JΩ|) of x, in the order of momentum_column_names.
template <class T>
std::array<T, 4> momentum_columns(const Mat3<T>& J, const State<T>& x) {
  const Vec3<T> m = spatial_momentum(J, x);
  return {m.x(), m.y(), m.z(), body_momentum_norm(J, x)};
}

}  // namespace lgi
