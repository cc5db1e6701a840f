/// \file
/// lgi/core/state.hpp — the state of a rigid body on SO(3) × R³.
///
/// ~~~{.unparsed}
///   R      attitude, body → laboratory (columns: body axes in the laboratory frame); kept orthogonal to
///          round-off by every integrator, never re-orthonormalised (see so3.hpp for the drift bound).
///   Omega  angular velocity in the body frame; kinematics R' = R·hat(Ω).
/// ~~~
/// Time is not part of the state: drivers compute t = t0 + n·h from the step index.
#pragma once

#include "state_io.hpp"
#include "scalar.hpp"

namespace lgi {

/// A rigid body's state (R, Ω), in this header's conventions; by default R = I, Ω = 0.
template <class T>
struct State {
  Mat3<T> R = Mat3<T>::Identity();  ///< attitude, body → laboratory: a rotation (orthogonal to round-off)
  Vec3<T> Omega = Vec3<T>::Zero();  ///< angular velocity in the body frame, rad per unit time
  LGI_NUMBERS(R, Omega)

  /// The same state in another scalar type (double → ceres::Jet for differentiation, or back).
  template <class S>
  State<S> cast() const {
    return {R.template cast<S>(), Omega.template cast<S>()};
  }
};

/// The same point of T*SO(3) ≅ SO(3) × R³ in canonical coordinates: attitude R and body angular
/// momentum Π = JΩ. Symplectic methods step (R, Π) and convert to and from (R, Ω) only at the edges
/// of a run: a round trip Π → J⁻¹Π → J(J⁻¹Π) every step carries a rounding bias in the momentum, which
/// adds up to a linear drift (docs/findings.md); stepping Π itself avoids it.
template <class T>
struct MomentumState {
  Mat3<T> R = Mat3<T>::Identity();  ///< attitude, body → laboratory, as in State
  Vec3<T> Pi = Vec3<T>::Zero();     ///< body angular momentum Π = JΩ (J about the problem's reference point)
  LGI_NUMBERS(R, Pi)
};

/// True when every entry is finite (derivative parts of Jets included).
template <class T>
bool is_finite(const State<T>& x) {
  return all_finite(x.R) && all_finite(x.Omega);
}
/// True when every entry of (R, Π) is finite (derivative parts of Jets included).
template <class T>
bool is_finite(const MomentumState<T>& x) {
  return all_finite(x.R) && all_finite(x.Pi);
}

}  // namespace lgi
