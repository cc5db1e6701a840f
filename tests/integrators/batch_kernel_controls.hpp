// tests/integrators/batch_kernel_controls.hpp — the negative controls of test_batch's bit identity: the AVX2 lane
// blocks (8 bodies) of the LGVI and RKMK4 kernels compiled as a careless build would compile them,
//   contracted:    -O3 -mavx2 -mfma -ffp-contract=fast (products and sums fused into FMAs),
//   reassociated:  -O3 -mavx2 -mfma -ffp-contract=off -fassociative-math -fno-signed-zeros -fno-trapping-math
//                  (sums evaluated in another order),
// in translation units of their own (batch_control_contracted.cpp, batch_control_reassociated.cpp) whose functions
// live in the namespaces named below (LGI_BATCH_ISA), so nothing compiled there can stand in, at link time, for
// the library's kernels or for the single-body steppers. Each runs blocks [block_begin, block_end) of all the
// bodies of `io` as lgi::batch's run_blocks_avx2 / rkmk4_blocks_avx2 do.
#pragma once

#include <lgi/integrators/batch_lgvi_kernel.hpp>
#include <lgi/integrators/batch_rkmk_kernel.hpp>

#include <cstddef>
#include <cstdint>

namespace lgi::batch_kernel::avx2_contracted {
void lgvi_control_blocks(const LgviParams& p, const LgviIO& io, std::size_t block_begin, std::size_t block_end,
                         double h, std::int64_t n_steps, bool torque);
void rkmk4_control_blocks(const Rkmk4Params& p, const Rkmk4IO& io, std::size_t block_begin, std::size_t block_end,
                          double h, std::int64_t n_steps, bool torque);
}  // namespace lgi::batch_kernel::avx2_contracted

namespace lgi::batch_kernel::avx2_reassociated {
void lgvi_control_blocks(const LgviParams& p, const LgviIO& io, std::size_t block_begin, std::size_t block_end,
                         double h, std::int64_t n_steps, bool torque);
void rkmk4_control_blocks(const Rkmk4Params& p, const Rkmk4IO& io, std::size_t block_begin, std::size_t block_end,
                          double h, std::int64_t n_steps, bool torque);
}  // namespace lgi::batch_kernel::avx2_reassociated
