// Problems: the problem library: Lagrange, Kovalevskaya, satellite, potential-defined (see registry.hpp).
#pragma once

namespace lgi::app {
using LibraryProblems = ProblemList<>;
}  // namespace lgi::app
