// Methods: problem-specific methods of the problem library — the Lagrange top's splitting around the
// exact symmetric free flow (see registry.hpp).
#pragma once

#include <lgi/integrators/lagrange_split.hpp>

namespace lgi::app {
using LibraryMethods = MethodList<LagrangeSplit>;
}  // namespace lgi::app
