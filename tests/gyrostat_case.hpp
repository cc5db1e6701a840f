// The gyrostat of the rotor tests (tests/integrators/test_gyrostat.cpp, and in binary128
// tests/integrators/test_quad_order.cpp): an asymmetric body with three rotors on skew axes, and the power of its
// non-conservative torques for the energy balance.
#pragma once

#include "test_problems.hpp"

#include <lgi/core/so3.hpp>
#include <lgi/core/state.hpp>
#include <lgi/problems/gyrostat.hpp>

namespace lgi::test {

// Non-diagonal J, three rotors on skew axes (friction on all, a motor on one, each spinning), gravity on an off-axis
// centre of mass and a little damping.
inline Gyrostat<double> three_rotor_gyrostat() {
  Gyrostat<double> g;
  g.body.inertia << 3.0, 0.1, 0.05, 0.1, 2.0, 0.02, 0.05, 0.02, 1.5;
  g.body.b = 0.6;
  g.body.z0 = Vec3<double>(0.3, 0.2, 1.0).normalized();
  g.body.has_damping = true;
  g.body.damping = 0.02 * Mat3<double>::Identity();
  g.rotor_count = 3;
  g.rotors[0] = {Vec3<double>::UnitX(), 0.05, 0.02, 0.0, 30.0};
  g.rotors[1] = {Vec3<double>(0, 1, 1).normalized(), 0.08, 0.05, 0.01, -20.0};
  g.rotors[2] = {Vec3<double>(1, 1, 1).normalized(), 0.04, 0.01, 0.0, 10.0};
  return g;
}

inline State<double> gyrostat_initial_state() {
  return {test::fixture_rotation(Vec3<double>(0.3, -0.2, 0.5)), Vec3<double>(0.8, -0.5, 1.2)};
}

// P = Ω·M_nc + Σ g_i ω_s,i, the power of the non-conservative torques (problems/gyrostat.hpp): dE/dt = P with
// E = GyrostatDynamics::energy. M_nc is the external torque without gravity and without the controller's
// proportional term (both in E's potential); g_i the motor torque on rotor i, ω_s,i its rate relative to the body.
template <class T>
T gyrostat_power(const GyrostatDynamics<T>& dyn, const T& t, const GyrostatState<T>& y) {
  const Gyrostat<T>& g = dyn.problem();
  const Vec3<T> Omega = dyn.omega(y.R, y.m, y.h);
  Vec3<T> M = g.body.torque(t, y.R, Omega) - g.body.b * Vec3<T>(y.R.transpose() * g.body.k).cross(g.body.z0);
  if (g.body.has_control) M += g.body.k_R * g.body.attitude_error(y.R);
  const auto f = dyn.forcing(t, y.R, y.m, y.h);
  return Omega.dot(M) + f.template tail<Gyrostat<T>::max_rotors>().dot(dyn.rotor_rates(y.h, Omega));
}

}  // namespace lgi::test
