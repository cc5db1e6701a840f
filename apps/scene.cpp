#include "scene.hpp"

#include <lgi/core/so3.hpp>

#include <cmath>

namespace lgi::app {

Scene parse_scene(const json& document, const std::string& file) {
  Scene scene;
  scene.file = file;
  const Node root(document, "", file);
  root.allow_only({"description", "problem", "initial", "integrator", "t_end", "output"});
  if (auto d = root.find("description")) (void)d->string();

  // problem
  const Node problem = root.at("problem");
  const std::string type = problem.at("type").string();
  const ProblemInfo* info = find_problem(type);
  if (!info) problem.at("type").fail("unknown problem type \"" + type + "\" (known: " + known_problems() + ")");
  problem.allow_only(info->keys, type);
  scene.problem = info->parse(problem);

  // initial
  const Node initial = root.at("initial");
  initial.allow_only({"R", "omega"});
  if (auto R = initial.find("R")) scene.initial.R = read_rotation(*R);
  scene.initial.Omega = initial.at("omega").vec3();

  // integrator
  const Node integrator = root.at("integrator");
  const std::string method = integrator.at("method").string();
  scene.method = find_method(method);
  if (!scene.method)
    integrator.at("method").fail("unknown method \"" + method + "\" (known: " + known_methods() + ")");
  if (!method_applies(method, type))
    integrator.at("method").fail("method \"" + method + "\" does not apply to problem " + type +
                                 " (methods that do: " + known_methods(type) + ")");
  if (scene.method->traits.explicit_method)
    integrator.allow_only({"method", "dt"}, "explicit method " + method);
  else
    integrator.allow_only({"method", "dt", "tolerance", "max_iterations"}, "method " + method);
  scene.dt = integrator.at("dt").positive();
  if (auto tol = integrator.find("tolerance")) {
    scene.options.tolerance = tol->positive();
    if (scene.options.tolerance >= 1e-2) tol->fail("must be < 0.01, got " + format_number(scene.options.tolerance));
  }
  if (auto it = integrator.find("max_iterations")) scene.options.max_iterations = static_cast<int>(it->integer(1, 1000));

  // t_end and the number of steps it implies
  const Node t_end = root.at("t_end");
  scene.t_end = t_end.non_negative();
  if (scene.t_end / scene.dt > max_scene_steps)
    integrator.at("dt").fail("t_end/dt = " + format_number(scene.t_end / scene.dt) + " steps, more than the " +
                             format_number(max_scene_steps) + " a scene may take");

  // output
  if (auto output = root.find("output")) {
    output->allow_only({"times", "every"});
    const auto times = output->find("times");
    const auto every = output->find("every");
    if (times && every) output->fail("give either \"times\" or \"every\", not both");
    if (times) {
      const std::size_t n = times->size();
      for (std::size_t i = 0; i < n; ++i) {
        const Node ti = times->at(i);
        const double t = ti.number();
        if (t < 0 || t > scene.t_end)
          ti.fail("output time " + format_number(t) + " is outside [0, t_end = " + format_number(scene.t_end) + "]");
        if (!scene.output_times.empty() && !(t > scene.output_times.back()))
          ti.fail("output times must increase: " + format_number(t) + " follows " +
                  format_number(scene.output_times.back()));
        scene.output_times.push_back(t);
      }
    }
    if (every) scene.output_every = every->integer(1, std::int64_t{1} << 53);
  }
  return scene;
}

Scene load_scene(const std::string& file) { return parse_scene(read_json_file(file), file); }

}  // namespace lgi::app
