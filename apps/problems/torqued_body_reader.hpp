// lgi/apps/problems/torqued_body_reader.hpp — the readers of rigid_body.cpp that the gyrostat's parser shares
// (apps/problems/gyrostat.cpp): a body's inertia, gravity and torque terms, and a target attitude.
#pragma once

#include "../json_reader.hpp"

#include <lgi/problems/torqued_body.hpp>

#include <memory>
#include <string>
#include <vector>

namespace lgi::app {

// The body of a "problem" object: "inertia", optional "gravity" and "torques" (docs/scenes.md, "rigid_body"); other
// keys are the caller's to allow.
TorquedBody<double> read_torqued_body(const Node& problem);
// A circular orbit: rate n > 0, unit normal ν, unit radial direction r̂0 ⊥ ν at t = 0 (problems/satellite.hpp).
struct CircularOrbit {
  double n = 0;
  Vec3<double> radial = Vec3<double>::UnitX();
  Vec3<double> normal = Vec3<double>::UnitZ();
};
// "n" (required), "normal" (default e3), "radial" (default e1; perpendicular to the normal to 1e-9, then made exactly
// so) of p: the satellite's problem keys and the gravity_gradient term's.
CircularOrbit read_circular_orbit(const Node& p);
// {"R": ...} | {"quaternion": [w, x, y, z]} | {"axis_angle": {...}}, returned as its rotation.
Mat3<double> read_target_attitude(const Node& target);
// A table of samples in R^D from the CSV named by term's "file", joined as its "interpolation" says: columns `names`
// (t first, then the components; the rest of a sample is 0), "what" in messages (CsvError naming the file and line,
// or the JSON path). Defined for D = 3 (torque tables) and D = 6 (a gyrostat's motor table).
template <int D>
std::shared_ptr<const SampleTable<D>> read_sample_table(const Node& term, const std::vector<std::string>& names,
                                                        const std::string& what);

}  // namespace lgi::app
