// lgi/apps/problems/torqued_body_reader.hpp — the readers of rigid_body.cpp that the gyrostat's parser shares
// (apps/problems/gyrostat.cpp): a body's inertia, gravity and torque terms, and a target attitude.
#pragma once

#include "../json_reader.hpp"

#include <lgi/problems/torqued_body.hpp>

namespace lgi::app {

// The body of a "problem" object: "inertia", optional "gravity" and "torques" (docs/scenes.md, "rigid_body"); other
// keys are the caller's to allow.
TorquedBody<double> read_torqued_body(const Node& problem);
// {"R": ...} | {"quaternion": [w, x, y, z]} | {"axis_angle": {...}}, returned as its rotation.
Mat3<double> read_target_attitude(const Node& target);

}  // namespace lgi::app
