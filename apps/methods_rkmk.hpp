// Methods: RKMK for any tableau, adaptive pairs, embedding baselines (see registry.hpp).
#pragma once

namespace lgi::app {
using RkmkFamilyMethods = MethodList<>;
}  // namespace lgi::app
