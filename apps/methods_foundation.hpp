// The foundation's methods: LGVI, RKMK4, Lie–Euler (see registry.hpp).
#pragma once

#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/rkmk.hpp>

namespace lgi::app {
using FoundationMethods = MethodList<Lgvi, Rkmk4, LieEuler>;
}  // namespace lgi::app
