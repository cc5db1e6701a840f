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

}  // namespace lgi
