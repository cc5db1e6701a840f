// Methods: RKMK for any tableau, adaptive pairs, embedding baselines (see registry.hpp).
//   rkmk_heun, rkmk3, rkmk4_38, rkmk_dp5, rkmk_dp8,    integrators/rkmk.hpp (rkmk4, lie_euler: the foundation's)
//   rkmk_vern9
//   rkmk4_cayley, rkmk_dp5_cayley, rkmk_dp8_cayley,    the same tableaus in Cayley coordinates (rkmk.hpp)
//   rkmk_vern9_cayley
//   rk4_quat[_renorm], rk4_mat[_renorm],
//   dop853_quat[_renorm], dop853_mat[_renorm]          integrators/embedding.hpp (non-geometric baselines)
// rkmk_dp5, rkmk_dp8, rkmk_vern9 (and their _cayley forms) and the dop853_* baselines run adaptively when the scene
// gives rtol and atol (integrators/adaptive.hpp); every method here takes "projection" (integrators/projection.hpp).
// Verner's 8(7) pair (tableaus::verner8) is not offered: measured, it does not pay (butcher_tableaus.hpp).
#pragma once

#include <lgi/integrators/embedding.hpp>
#include <lgi/integrators/rkmk.hpp>

namespace lgi::app {
using RkmkFamilyMethods = MethodList<RkmkHeun, Rkmk3, Rkmk4Rule38, RkmkDp5, RkmkDp8, RkmkVern9, Rkmk4Cayley,
                                     RkmkDp5Cayley, RkmkDp8Cayley, RkmkVern9Cayley, Rk4Quat, Rk4QuatRenorm, Rk4Mat,
                                     Rk4MatRenorm, Dop853Quat, Dop853QuatRenorm, Dop853Mat, Dop853MatRenorm>;
}  // namespace lgi::app
