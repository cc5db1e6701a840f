// Methods: symmetric compositions, commutator-free and Crouch-Grossman methods (see registry.hpp).
#pragma once

namespace lgi::app {
using CompositionMethods = MethodList<>;
}  // namespace lgi::app
