#include "registry.hpp"

namespace lgi::app {

std::vector<ProblemInfo> paper_problem_infos() { return {}; }

}  // namespace lgi::app
