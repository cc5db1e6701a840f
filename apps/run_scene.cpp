// lgi/apps/run_scene.cpp — run_scene's dispatch on the problem to run_problem<P>, which the runner parts instantiate
// (runner_detail.hpp, runner_impl.hpp).
#include "runner_detail.hpp"

#include <variant>

namespace lgi::app {

// LGI_RUNNER_PARTS: the number of runner parts apps/CMakeLists.txt configures.
static_assert(std::variant_size_v<AnyProblem> == LGI_RUNNER_PARTS,
              "a problem was added to the registry: raise LGI_RUNNER_PARTS in apps/CMakeLists.txt to the number "
              "of problems, so that its runner part is compiled");

RunReport run_scene(const Scene& scene, const RunOptions& options) {
  return std::visit([&](const auto& p) { return run_problem(p, scene, options); }, scene.problem);
}

}  // namespace lgi::app
