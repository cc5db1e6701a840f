// Problems: the seed paper's Euler-angle formulation (see registry.hpp).
#pragma once

namespace lgi::app {
using PaperProblems = ProblemList<>;
}  // namespace lgi::app
