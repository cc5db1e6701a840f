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
// {"R": ...} | {"quaternion": [w, x, y, z]} | {"axis_angle": {...}}, returned as its rotation.
Mat3<double> read_target_attitude(const Node& target);
// A table of samples in R^D from the CSV named by term's "file", joined as its "interpolation" says: columns `names`
// (t first, then the components; the rest of a sample is 0), "what" in messages (CsvError naming the file and line,
// or the JSON path). Defined for D = 3 (torque tables) and D = 6 (a gyrostat's motor table).
template <int D>
std::shared_ptr<const SampleTable<D>> read_sample_table(const Node& term, const std::vector<std::string>& names,
                                                        const std::string& what);

}  // namespace lgi::app
