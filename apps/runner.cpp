// lgi/apps/runner.cpp — run_scene's dispatch on the problem, the CSV header and the brief report. The
// runs themselves are in runner_impl.hpp, compiled in parts (runner_detail.hpp).
#include "runner_detail.hpp"

#include <cmath>
#include <variant>

namespace lgi::app {

// LGI_RUNNER_PARTS: the number of runner parts apps/CMakeLists.txt configures.
static_assert(std::variant_size_v<AnyProblem> == LGI_RUNNER_PARTS,
              "a problem was added to the registry: raise LGI_RUNNER_PARTS in apps/CMakeLists.txt to the number "
              "of problems, so that its runner part is compiled");

namespace {

std::string relative(double initial, double final) {
  const double scale = std::abs(initial) > 0 ? std::abs(initial) : 1.0;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3e", std::abs(final - initial) / scale);
  return buf;
}

}  // namespace

RunReport run_scene(const Scene& scene, const RunOptions& options) {
  return std::visit([&](const auto& p) { return run_problem(p, scene, options); }, scene.problem);
}

std::string csv_header(const Scene& scene) {
  return std::visit([](const auto& p) { return runner_detail::header_for<std::decay_t<decltype(p)>>(); }, scene.problem);
}

std::string brief_report(const Scene& scene, const RunReport& r) {
  const MethodTraits& m = scene.method->traits;
  const std::string problem = std::visit([](const auto& p) { return std::string(p.name); }, scene.problem);
  const bool euler_angles = problem == EulerAngleTop<double>::name;  // its own path: RK on the angles
  // A method whose order is higher without torque (preprocessed DMV) shows that order on a torque-free problem.
  const bool torque_free = std::visit(
      [](const auto& p) {
        using P = std::decay_t<decltype(p)>;
        if constexpr (requires { P::has_torque; })
          return !P::has_torque;
        else
          return false;
      },
      scene.problem);
  const int order = torque_free && m.free_body_order > 0 ? m.free_body_order : m.order;
  char buf[512];
  std::string s;
  std::snprintf(buf, sizeof buf, "%s: %s, %s (order %d%s%s), dt = %s\n", scene.file.c_str(), problem.c_str(),
                std::string(m.name).c_str(), order, m.symplectic ? ", symplectic" : "",
                euler_angles ? ", Runge-Kutta on the Euler angles" : m.exact_on_group ? ", on SO(3)" : "",
                format_number(scene.dt).c_str());
  s += buf;
  // How the run was made, where the scene asked for more than fixed steps.
  if (scene.options.rtol > 0)
    s += "  adaptive         rtol = " + format_number(scene.options.rtol) + ", atol = " +
         format_number(scene.options.atol) + " (dt is the initial step; steps below are the accepted ones)\n";
  if (scene.options.projection) s += "  projected        energy and m.k (free body: |J Omega|) restored after every step\n";
  std::snprintf(buf, sizeof buf, "  steps            %lld to t = %s", static_cast<long long>(r.summary.steps),
                format_number(r.summary.t).c_str());
  s += buf;
  if (r.newton_iterations >= 0 && r.summary.steps > 0)
    std::snprintf(buf, sizeof buf, " (%.2f Newton iterations per step)\n",
                  static_cast<double>(r.newton_iterations) / static_cast<double>(r.summary.steps));
  else
    std::snprintf(buf, sizeof buf, "\n");
  s += buf;
  s += "  energy error     " + relative(r.energy_initial, r.energy_final) + " (relative)\n";
  for (const auto& inv : r.invariants)
    s += "  " + inv.name + std::string(inv.name.size() < 16 ? 16 - inv.name.size() : 1, ' ') + " " +
         relative(inv.initial, inv.final) + " (relative change)\n";
  std::snprintf(buf, sizeof buf, "  orthogonality    %.3e (|R^T R - I|)\n  wall time        %.3f s (%.1f ns/step)\n",
                so3::orthogonality_error(r.final_state.R), r.wall_seconds,
                r.summary.steps > 0 ? 1e9 * r.wall_seconds / static_cast<double>(r.summary.steps) : 0.0);
  s += buf;
  return s;
}

}  // namespace lgi::app
