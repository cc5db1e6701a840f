#include "scene.hpp"

#include <lgi/core/so3.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <stdexcept>

namespace lgi::app {
namespace {

// How each integrator option is read from the scene into StepperOptions (a method lists the keys it
// takes in MethodTraits::options; any other key is an error naming the method).
struct OptionReader {
  std::string_view key;
  void (*read)(const Node& node, StepperOptions& options);
};

constexpr OptionReader option_readers[] = {
    {"tolerance",
     [](const Node& n, StepperOptions& o) {
       o.tolerance = n.positive();
       if (o.tolerance >= 1e-2) n.fail("must be < 0.01, got " + format_number(o.tolerance));
     }},
    {"max_iterations",
     [](const Node& n, StepperOptions& o) { o.max_iterations = static_cast<int>(n.integer(1, 1000)); }},
};

}  // namespace

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
  std::vector<std::string_view> keys = {"method", "dt"};
  for (const std::string_view key : scene.method->traits.options)
    if (!key.empty()) keys.push_back(key);
  integrator.allow_only(keys, "method " + method);
  scene.dt = integrator.at("dt").positive();
  for (const std::string_view key : scene.method->traits.options) {
    if (key.empty()) continue;
    const auto node = integrator.find(key);
    if (!node) continue;
    const auto reader = std::find_if(std::begin(option_readers), std::end(option_readers),
                                     [&](const OptionReader& r) { return r.key == key; });
    if (reader == std::end(option_readers)) throw std::logic_error("lgi: no reader for option " + std::string(key));
    reader->read(*node, scene.options);
  }

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
