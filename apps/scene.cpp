#include "scene.hpp"

#include "auto_method.hpp"
#include "output_file.hpp"

#include <lgi/core/attitude.hpp>
#include <lgi/core/so3.hpp>
#include <lgi/integrators/adaptive.hpp>
#include <lgi/integrators/projection.hpp>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <numbers>
#include <optional>
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
    // [outer, middle, inner]: the principal axes 1, 2, 3 of an axis-rotation splitting, in any order.
    {"axis_order",
     [](const Node& n, StepperOptions& o) {
       if (!n.is_array() || n.size() != 3) n.fail("must be an array of three axes, a permutation of [1, 2, 3]");
       for (std::size_t i = 0; i < 3; ++i) o.axis_order[i] = static_cast<int>(n.at(i).integer(1, 3));
       if (o.axis_order[0] == o.axis_order[1] || o.axis_order[0] == o.axis_order[2] ||
           o.axis_order[1] == o.axis_order[2])
         n.fail("must be a permutation of [1, 2, 3]");
     }},
    // Embedded pairs: giving rtol and atol makes the run adaptive (integrators/adaptive.hpp); dt is then the
    // initial step. rtol ≥ 10 ε like DOPRI5/DOP853 (below it the error estimate cannot see round-off).
    {"rtol",
     [](const Node& n, StepperOptions& o) {
       o.rtol = n.positive();
       if (!(o.rtol >= lgi::min_rtol && o.rtol < 1))
         n.fail("must be in [" + format_number(lgi::min_rtol) + " (10 machine epsilons), 1), got " + format_number(o.rtol));
     }},
    {"atol", [](const Node& n, StepperOptions& o) { o.atol = n.positive(); }},
    // Non-symplectic methods: restore energy and momentum after every step (integrators/projection.hpp).
    {"projection",
     [](const Node& n, StepperOptions& o) {
       if (!n.value().is_boolean()) n.fail("expected true or false, got " + describe(n.value()));
       o.projection = n.value().get<bool>();
     }},
};

// "euler_angles": [φ, θ, ψ] (the seed paper's z-x-z, radians) or {"convention": "zxz" | "zyx", "angles": [...],
// "unit": "rad" | "deg"} (core/attitude.hpp).
struct EulerAngles {
  EulerConvention convention = EulerConvention::zxz;
  Vec3<double> angles;   // radians
  double to_radians = 1;  // the unit's factor, for the rates
};
EulerAngles read_euler_angles(const Node& node) {
  EulerAngles e;
  if (node.is_array()) {
    e.angles = node.vec3();
    return e;
  }
  if (!node.is_object())
    node.fail("expected [phi, theta, psi] (z-x-z, radians) or an object with convention, angles and unit, got " +
              describe(node.value()));
  node.allow_only({"convention", "angles", "unit"}, "euler_angles");
  const Node c = node.at("convention");
  const std::string name = c.string();
  if (name == "zxz")
    e.convention = EulerConvention::zxz;
  else if (name == "zyx")
    e.convention = EulerConvention::zyx;
  else
    c.fail("unknown convention " + quoted_input(name) + did_you_mean(name, {"zxz", "zyx"}) +
           " (known: zxz, the seed paper's (phi, theta, psi); zyx, (yaw, pitch, roll))");
  e.to_radians = read_angle_unit(node.find("unit"));
  e.angles = node.at("angles").vec3() * e.to_radians;
  return e;
}

}  // namespace

Scene parse_scene(const json& document, const std::string& file, const std::string& directory) {
  Scene scene;
  scene.file = file;
  const Node root(document, "", file, &scene.adjustments, directory.empty() ? nullptr : &directory);
  root.allow_only({"description", "problem", "initial", "integrator", "t_end", "output", "limits"});
  if (auto d = root.find("description")) (void)d->string();

  // problem
  const Node problem = root.at("problem");
  const std::string type = problem.at("type").string();
  const ProblemInfo* info = find_problem(type);
  if (!info) {
    std::vector<std::string_view> names;
    for (const ProblemInfo& p : problem_registry()) names.push_back(p.name);
    problem.at("type").fail("unknown problem type " + quoted_input(type) + did_you_mean(type, names) +
                            " (known: " + known_problems() + ")");
  }
  problem.allow_only(info->keys, type);
  scene.problem = info->parse(problem);

  // initial: the attitude in one of four forms (none: R = I), the angular velocity as omega or Euler-angle rates
  // (core/attitude.hpp; docs/scenes.md).
  const Node initial = root.at("initial");
  initial.allow_only({"R", "quaternion", "axis_angle", "euler_angles", "omega", "euler_rates"});
  std::string forms;
  for (const char* key : {"R", "quaternion", "axis_angle", "euler_angles"})
    if (initial.find(key)) forms += (forms.empty() ? "" : ", ") + std::string(key);
  if (forms.find(',') != std::string::npos)
    initial.fail("give the attitude once, as R, quaternion, axis_angle or euler_angles (got " + forms + ")");
  std::optional<EulerAngles> euler;
  if (const auto R = initial.find("R")) {
    scene.initial.R = read_rotation(*R);
  } else if (const auto q = initial.find("quaternion")) {
    scene.initial.R = read_quaternion(*q);
  } else if (const auto a = initial.find("axis_angle")) {
    scene.initial.R = read_axis_angle(*a);
  } else if (const auto e = initial.find("euler_angles")) {
    euler = read_euler_angles(*e);
    scene.initial.R = rotation_from_euler(euler->convention, euler->angles);
  }
  const auto omega = initial.find("omega"), rates = initial.find("euler_rates");
  if (omega && rates) initial.fail("give the angular velocity once, as omega or euler_rates (not both)");
  if (rates) {
    if (!euler) rates->fail("euler_rates need euler_angles (their convention and unit)");
    scene.initial.Omega = body_rate_from_euler(euler->convention, euler->angles, Vec3<double>(rates->vec3() * euler->to_radians));
  } else if (omega) {
    scene.initial.Omega = omega->vec3();
  } else {
    initial.fail("missing the angular velocity: omega (body frame, rad per time unit), or euler_rates with "
                 "euler_angles");
  }

  // integrator
  const Node integrator = root.at("integrator");
  const std::string method = integrator.at("method").string();
  // "auto" (auto_method.hpp): the method and its settings are chosen once t_end is known.
  double auto_tolerance = 0;
  if (method == "auto") {
    integrator.allow_only({"method", "tolerance"}, "method auto (it chooses dt and the method's settings)");
    const Node tolerance = integrator.at("tolerance");
    auto_tolerance = tolerance.positive();
    if (!(auto_tolerance >= auto_min_tolerance && auto_tolerance <= auto_max_tolerance))
      tolerance.fail("must be in [" + format_number(auto_min_tolerance) + ", " + format_number(auto_max_tolerance) +
                     "], got " + format_number(auto_tolerance));
    if (!info->on_group)
      integrator.at("method").fail("method auto chooses for a state (R, Omega) on SO(3) x R^3 alone; problem " + type +
                                   "'s state is not: give its method (" + known_methods(type) + ")");
  } else {
    scene.method = find_method(method);
    if (!scene.method) {
      std::vector<std::string_view> names;
      for (const MethodInfo& m : method_registry()) names.push_back(m.traits.name);
      const std::string hint = did_you_mean(method, names);
      integrator.at("method").fail("unknown method " + quoted_input(method) + hint +
                                   (hint.empty() ? " (known: " + known_methods() + ")"
                                                 : " (`lgi list` shows all " + std::to_string(names.size()) + ")"));
    }
    if (!method_applies(method, type)) {
      std::string types;
      for (const ProblemInfo& p : problem_registry())
        if (method_applies(method, p.name)) types += (types.empty() ? "" : ", ") + std::string(p.name);
      const std::string note = scene.problem->methods_note();
      const std::string why = !note.empty() ? note
                              : scene.problem->reads_omega()
                                  ? " (its torque reads the angular velocity, and the splittings and their "
                                    "compositions need a torque of the attitude alone)"
                                  : "";
      integrator.at("method").fail("method \"" + method + "\" does not apply to problem " + type + why +
                                   "; it applies to " + types + " (methods that apply to " + type + ": " +
                                   known_methods(type) + ")");
    }
    std::vector<std::string_view> keys = {"method", "dt"};
    // A problem whose state is not on SO(3) runs the method's tableau with fixed steps (problems/euler_angle_methods.hpp).
    const bool takes_options = info->on_group;  // a problem not on SO(3): fixed steps of the tableau, no options
    for (const std::string_view key : scene.method->traits.options)
      if (!key.empty() && takes_options) keys.push_back(key);
    // rtol/atol or projection on a method that does not take them: say why, before the generic unknown-key error.
    const auto takes = [](const MethodTraits& traits, std::string_view key) {
      return std::find(traits.options.begin(), traits.options.end(), key) != traits.options.end();
    };
    for (const std::string_view key : {std::string_view("rtol"), std::string_view("atol")}) {
      const auto node = integrator.find(key);
      if (!node || !takes_options || takes(scene.method->traits, key)) continue;
      std::string pairs;
      for (const MethodInfo& m : method_registry())
        if (takes(m.traits, key) && method_applies(m.traits.name, type))
          pairs += (pairs.empty() ? "" : ", ") + std::string(m.traits.name);
      node->fail("method " + method + " has no embedded error estimate: adaptive steps (rtol, atol) need one of " +
                 pairs);
    }
    // Why a problem has nothing to project onto (said first: a forced LGVI is not symplectic either).
    const auto no_projection = [&] {
      return "problem " + type +
             (scene.problem->reads_omega() ? "'s torque reads the angular velocity (damping, control): its energy is not "
                                             "conserved, nothing to project onto"
                                           : " has a time-dependent torque: no energy to project onto");
    };
    if (const auto node = integrator.find("projection");
        node && takes_options && !takes(scene.method->traits, "projection")) {
      if (!scene.problem->projectable()) node->fail(no_projection());
      node->fail("method " + method +
                 (scene.method->traits.symplectic
                      ? " is symplectic (its energy error stays bounded): projection is for non-symplectic methods"
                      : " does not take projection"));
    }
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
    if ((scene.options.rtol > 0) != (scene.options.atol > 0))
      integrator.fail("an adaptive run needs both \"rtol\" and \"atol\" (fixed steps: neither)");
    if (scene.options.projection && !scene.problem->projectable()) integrator.at("projection").fail(no_projection());
  }

  // t_end and the number of steps it implies
  const Node t_end = root.at("t_end");
  scene.t_end = t_end.non_negative();
  // Data that end (a torque table) end the run's reach: beyond them the torque is not known.
  if (const double limit = scene.problem->time_limit(); scene.t_end > limit) {
    const auto files = scene.problem->input_files();
    t_end.fail("t_end = " + format_number(scene.t_end) + " is beyond the last row of the torque table" +
               (files.empty() ? std::string() : " " + files.front().first) + " (t = " + format_number(limit) +
               "): the torque is not known there");
  }
  if (auto_tolerance > 0) {
    try {
      choose_auto(scene, auto_tolerance);
    } catch (const std::invalid_argument& e) {
      integrator.at("method").fail(e.what());
    }
  }
  // dt is the step (adaptive runs: the first step); one longer than the whole run is a slip of units or digits.
  if (scene.t_end > 0 && scene.dt > scene.t_end)
    integrator.at("dt").fail("must be <= t_end = " + format_number(scene.t_end) + ", got " + format_number(scene.dt));
  if (scene.t_end / scene.dt > max_scene_steps)
    integrator.at("dt").fail("t_end/dt = " + format_number(scene.t_end / scene.dt) + " steps, more than the " +
                             format_number(max_scene_steps) + " a scene may take");

  // output
  if (auto output = root.find("output")) {
    output->allow_only({"times", "every", "interval", "columns"});
    if (const auto columns = output->find("columns")) scene.columns = read_column_groups(*columns);
    const auto times = output->find("times");
    const auto every = output->find("every");
    const auto interval = output->find("interval");
    if ((times.has_value() + every.has_value() + interval.has_value()) > 1)
      output->fail("give one of \"times\", \"every\" and \"interval\"");
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
    if (every && auto_tolerance > 0)
      every->fail("counts steps, and method auto chooses them: give \"interval\" or \"times\"");
    if (every) scene.output_every = every->integer(1, std::int64_t{1} << 53);
    if (interval) {
      // The grid k·interval (k = 1, 2, … below t_end; t_end itself is always written), as output times: adaptive
      // methods fill it from their dense output, fixed-step methods as any output time.
      const double dt_out = interval->positive();
      const double count = std::floor(scene.t_end / dt_out);
      if (count > max_interval_rows)
        interval->fail("t_end/interval = " + format_number(scene.t_end / dt_out) + " rows, more than the " +
                       format_number(max_interval_rows) + " an output grid may have (use \"every\")");
      for (double k = 1; k <= count; ++k) {
        const double t = k * dt_out;  // not a running sum: no drift along the grid
        // A grid point within rounding of t_end is t_end's row.
        if (scene.t_end - t > 16 * std::numeric_limits<double>::epsilon() * scene.t_end) scene.output_times.push_back(t);
      }
    }
  }

  // limits (budgets): see Scene
  if (auto limits = root.find("limits")) {
    limits->allow_only({"max_steps", "max_wall_seconds"});
    if (auto n = limits->find("max_steps")) scene.max_steps = n->integer(1, std::int64_t{1} << 53);
    if (auto s = limits->find("max_wall_seconds")) scene.max_wall_seconds = s->positive();
  }
  return scene;
}

Scene load_scene(const std::string& file) { return parse_scene(read_json_file(file), file); }

std::string output_replaces_input(const Scene& scene, const std::string& output) {
  if (output.empty() || is_streamed_path(output)) return {};
  for (const auto& in : scene.problem->input_files())
    if (same_file(output, in.first))
      return "-o " + output + " is the scene's torque table " + in.first + ": lgi does not replace its input";
  return {};
}

}  // namespace lgi::app
