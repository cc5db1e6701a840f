// The foundation's problems: the free body and the heavy top (see registry.hpp).
#pragma once

#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>

namespace lgi::app {
using FoundationProblems = ProblemList<FreeBody<double>, HeavyTop<double>>;
}  // namespace lgi::app
