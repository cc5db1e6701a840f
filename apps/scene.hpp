// lgi/apps/scene.hpp — a scene file (shared/DESIGN.md §3), parsed and validated.
//
// load_scene checks everything before anything runs: every malformed scene ends in one InputError that
// names the file, the JSON path and what is wrong. A Scene that loads is runnable.
//
// Decisions where DESIGN.md is silent (documented in README "Scene files"):
//   - "description": an optional top-level string, ignored.
//   - heavy_top: `inertia` and `b` are required; `k` and `z0` default to e3.
//   - initial.R, k and z0 must be within 1e-9 of a rotation / unit vector; they are then projected
//     exactly onto SO(3) / the unit sphere, so the run starts on the group to round-off.
//   - Rows are written at t = 0, at each output time (or every N steps), and at t_end.
//   - integrator.tolerance and integrator.max_iterations are accepted by implicit methods only; with "method":
//     "auto" (auto_method.hpp), "tolerance" is the run's accuracy and the only other key.
#pragma once

#include "json_reader.hpp"
#include "output_columns.hpp"
#include "registry.hpp"

#include <lgi/core/integrator.hpp>
#include <lgi/core/state.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace lgi::app {

// "method": "auto" (auto_method.hpp): the tolerance asked for and what was chosen.
struct AutoChoice {
  double tolerance = 0;          // > 0: the scene asked for "auto" (scene.method, dt, options are its choice)
  std::string reason;            // why that method and those settings (the summary's line)
  std::int64_t probe_steps = 0;  // steps taken by the probes that set a fixed step
  double seconds = 0;            // the probes' wall time (0 without probes)
};

struct Scene {
  std::string file;
  std::shared_ptr<const ProblemModel> problem;  // the problem type and its parameters
  State<double> initial;
  const MethodInfo* method = nullptr;
  double dt = 0;
  StepperOptions options;
  double t_end = 0;
  std::vector<double> output_times;  // when non-empty: write at these times (and 0, t_end)
  std::int64_t output_every = 0;     // when > 0: write every N steps (and 0, t_end)
  std::vector<ColumnGroup> columns;  // "output.columns" (output_columns.hpp); empty: the standard row
  // "limits": the run stops (RunStatus::stopped, `lgi` exit 6) after max_steps steps (adaptive runs: attempted
  // steps) or max_wall_seconds of wall time, both counted from the start of this invocation (a resumed run
  // starts counting again); 0: no limit.
  std::int64_t max_steps = 0;
  double max_wall_seconds = 0;
  // What the readers changed to make the input exact (a rotation projected, a unit vector normalised), each
  // above input_note_defect (registry.hpp).
  std::vector<InputAdjustment> adjustments;
  AutoChoice auto_choice;
};

// The largest number of steps a scene may ask for (t_end / dt).
inline constexpr double max_scene_steps = 1e13;
// The most rows "output": {"interval"} may ask for (t_end / interval; each an output time held in memory).
inline constexpr double max_interval_rows = 1e7;

Scene load_scene(const std::string& file);
// Why `output` may not be written: it is a file the scene reads (a torque table), which lgi does not replace; "" if
// it is not (or is streamed).
std::string output_replaces_input(const Scene& scene, const std::string& output);
// `file` names the scene in messages; `directory` (empty: the file's) is where file names in it are resolved.
Scene parse_scene(const json& document, const std::string& file, const std::string& directory = {});

}  // namespace lgi::app
