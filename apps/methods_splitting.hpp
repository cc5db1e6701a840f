// Methods: splittings of the heavy top and free-body flows (see registry.hpp).
#pragma once

namespace lgi::app {
using SplittingMethods = MethodList<>;
}  // namespace lgi::app
