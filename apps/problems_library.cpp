#include "registry.hpp"

namespace lgi::app {

std::vector<ProblemInfo> library_problem_infos() { return {}; }

}  // namespace lgi::app
