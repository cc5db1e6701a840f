// Methods: splittings of the heavy top into gravity kicks and free-body flows (see registry.hpp):
// split_axes (principal-axis rotations), split_dmv (discrete Moser-Veselov, fast form), split_dmv4 …
// split_dmv10 (Hairer-Vilmart preprocessed DMV): integrators/splitting.hpp; split_exact (the exact
// free-body flow by elliptic functions): integrators/split_exact.hpp.
#pragma once

#include <lgi/integrators/split_exact.hpp>
#include <lgi/integrators/splitting.hpp>

namespace lgi::app {
using SplittingMethods =
    MethodList<SplitAxes, SplitDmv, SplitDmv4, SplitDmv6, SplitDmv8, SplitDmv10, SplitExact>;
}  // namespace lgi::app
