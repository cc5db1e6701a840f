// Methods: problem-specific methods of the problem library — the Lagrange top's splitting around the
// exact symmetric free flow and its compositions to orders 4-10, and the free body's exact solution (exact)
// (see registry.hpp).
#pragma once

#include <lgi/integrators/composition.hpp>
#include <lgi/integrators/exact.hpp>
#include <lgi/integrators/lagrange_split.hpp>

namespace lgi::app {
using LibraryMethods = MethodList<LagrangeSplit, LagrangeSplitYoshida4, LagrangeSplitKahanLi6, LagrangeSplitKahanLi8,
                                  LagrangeSplitSofroniouSpaletta10, ExactFreeBody>;
}  // namespace lgi::app
