// lgi/apps/auto_method.cpp — the choice of "method": "auto" (auto_method.hpp).
#include "auto_method.hpp"

#include "runner_detail.hpp"

#include <lgi/core/engine.hpp>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <initializer_list>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace lgi::app {
namespace {

// The methods auto chooses from, looked up in the registry once (its table of 48 traits is not walked per choice).
constexpr std::string_view candidates[] = {"exact",           "lagrange_split_kahan_li8", "lagrange_split_sofroniou_spaletta10",
                                           "rkmk_vern9_cayley", "rkmk_vern9", "rkmk_dp8_cayley", "rkmk_dp8",
                                           "rkmk_dp5_cayley",   "rkmk_dp5",   "rkmk4",           "lgvi"};
const MethodInfo* method_named(std::string_view name) {
  static const auto resolved = [] {
    std::array<const MethodInfo*, std::size(candidates)> r{};
    for (std::size_t i = 0; i < r.size(); ++i) r[i] = find_method(candidates[i]);
    return r;
  }();
  for (std::size_t i = 0; i < resolved.size(); ++i)
    if (candidates[i] == name) return resolved[i];
  return find_method(name);
}

// The first of `names` this build offers for the problem, or nullptr.
const MethodInfo* first_applying(const ProblemInfo* problem, std::initializer_list<std::string_view> names) {
  if (!problem) return nullptr;
  for (const std::string_view name : names)
    if (std::find(problem->methods.begin(), problem->methods.end(), name) != problem->methods.end())
      return method_named(name);
  return nullptr;
}

// √(b / min J_ii): the frequency scale of a body's pendulum motion under gravity (0 without gravity, or a b not
// known).
double gravity_frequency(const ProblemModel& model) {
  const BodyData body = model.body();
  const double I = body.J.diagonal().minCoeff();
  return body.has_gravity && body.b > 0 && I > 0 ? std::sqrt(body.b / I) : 0.0;
}

// The error measure of the tolerance: R's rotation angle + |ΔΩ| / max(|Ω|, |Ω0|) (runner.hpp).
double distance(const State<double>& a, const State<double>& b, double w0) {
  const StateDifference d = state_difference(a, b, w0);
  return d.angle + d.omega;
}

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

// The fixed step for `scene.method` (auto_method.hpp, probes). Returns h = t_end / N.
double probe_step(Scene& scene, double tolerance, int order, double h_cap, AutoChoice& choice) {
  const auto start = std::chrono::steady_clock::now();
  const double T = scene.t_end;
  const auto engine = scene.problem->runner()->integrator(scene);
  const State<double> x0 = scene.initial;
  const double p = order;
  // The local error constant C of l(h) = C h^(p+1), from one step of h against two of h/2; < 0: a step failed.
  const auto constant = [&](double h) {
    engine->set(Slot::scratch, x0, 0.0);
    if (engine->step(Slot::scratch, 0.0, h) != StepStatus::ok) return -1.0;
    const State<double> one = engine->state(Slot::scratch);
    engine->set(Slot::scratch, x0, 0.0);
    if (engine->step(Slot::scratch, 0.0, h / 2) != StepStatus::ok) return -1.0;
    if (engine->step(Slot::scratch, h / 2, h / 2) != StepStatus::ok) return -1.0;
    choice.probe_steps += 3;
    const double d = distance(engine->state(Slot::scratch), one, x0.Omega.norm());
    // one − truth ≈ C h^(p+1), two halves − truth ≈ C h^(p+1) / 2^p.
    return d / (1 - std::ldexp(1.0, -order)) / std::pow(h, p + 1);
  };
  // The step whose global error T·C·h^p is tolerance / 2.
  const auto step_for = [&](double C) {
    const double h = C > 0 ? std::pow(tolerance / (2 * T * C), 1 / p) : h_cap;
    return std::min(h, h_cap);
  };
  double h = std::min(h_cap, T / 8), C_prev = -1;
  for (int probe = 0; probe < 6; ++probe) {
    const double C = constant(h);
    if (C < 0) {  // the step failed (an implicit method beyond its limit): smaller
      h /= 4;
      continue;
    }
    const double next = step_for(C);
    // The first probe asks for a step between a quarter of its own and its own: taken.
    if (C_prev < 0 && next <= h && next >= h / 4) {
      h = next;
      break;
    }
    // Two successive constants within a factor 3 (or the cap reached twice): the asymptotic regime.
    if (C_prev >= 0 && ((C <= 3 * C_prev && C_prev <= 3 * C) || (next == h_cap && h == h_cap))) {
      h = step_for(std::max(C, C_prev));
      break;
    }
    C_prev = C;
    h = next;
  }
  const double steps = std::max(1.0, std::ceil(T / h));
  choice.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return T / steps;
}

}  // namespace

void choose_auto(Scene& scene, double tolerance) {
  const ProblemModel& model = *scene.problem;
  const std::string type(model.type_name());
  if (!model.on_group())
    throw std::invalid_argument("method auto chooses for a state (R, Omega) on SO(3) x R^3 alone; problem " + type +
                                "'s state is not: give its method (" + known_methods(type) + ")");
  const ProblemInfo* info = find_problem(type);
  AutoChoice& choice = scene.auto_choice;
  choice.tolerance = tolerance;
  choice.probe_steps = 0;
  choice.seconds = 0;
  scene.options = StepperOptions{};
  const double T = scene.t_end;
  const double w0 = scene.initial.Omega.norm();

  if (const MethodInfo* exact = first_applying(info, {"exact"})) {
    scene.method = exact;
    scene.dt = T > 0 ? T : 1.0;
    choice.reason = "a free body: its exact solution, one evaluation per output time (error ~1e-16 x the state's "
                    "sensitivity, below any tolerance)";
  } else if (const MethodInfo* split = tolerance >= 1e-8
                                           ? first_applying(info, {"lagrange_split_kahan_li8",
                                                                   "lagrange_split_sofroniou_spaletta10"})
                                           : first_applying(info, {"lagrange_split_sofroniou_spaletta10",
                                                                   "lagrange_split_kahan_li8"})) {
    scene.method = split;
    // The spin about the symmetry axis is integrated exactly, and the kicks take any step: no cap but T.
    scene.dt = T > 0 ? probe_step(scene, tolerance, split->traits.order, T, choice) : 1.0;
    choice.reason = "an axisymmetric top with its centre of mass on the axis: a composition of the spin-frame "
                    "splitting (the spin integrated exactly), fixed steps from " +
                    std::to_string(choice.probe_steps) + " probe steps";
  } else if (const MethodInfo* pair = first_applying(info, {"rkmk_vern9_cayley", "rkmk_vern9", "rkmk_dp8_cayley",
                                                             "rkmk_dp8", "rkmk_dp5_cayley", "rkmk_dp5"})) {
    scene.method = pair;
    const double w = w0 + gravity_frequency(model);  // a scale of the motion's frequencies
    const double rtol = std::max(min_rtol, tolerance / (1 + T * w / 20));
    scene.options.rtol = scene.options.atol = rtol;
    scene.dt = T > 0 ? std::min(T, w > 0 ? 0.1 / w : T / 100) : 1.0;
    const auto& keys = pair->traits.options;
    scene.options.projection = T * w > 1e4 && model.projectable() &&
                               std::find(keys.begin(), keys.end(), "projection") != keys.end();
    choice.reason = "an embedded pair, adaptive steps with rtol = atol = " + number(rtol) + " (the tolerance / (1 + " +
                    number(T * w) + " rad of motion / 20))" +
                    (scene.options.projection ? ", projected onto the invariants (a long horizon)" : "");
  } else if (const MethodInfo* fixed = first_applying(info, {"rkmk4", "lgvi"})) {
    scene.method = fixed;
    scene.dt = T > 0 ? probe_step(scene, tolerance, fixed->traits.order, w0 > 0 ? std::min(T, 1 / w0) : T, choice)
                     : 1.0;
    choice.reason = "no embedded pair in this build: fixed steps from " + std::to_string(choice.probe_steps) +
                    " probe steps";
  } else {
    throw std::invalid_argument("method auto finds no method for problem " + type + " in this build");
  }
}

}  // namespace lgi::app
