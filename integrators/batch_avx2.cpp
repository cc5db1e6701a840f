// lgi/integrators/batch_avx2.cpp — the batched kernels' lane blocks compiled for AVX2 (library lgi::batch).
//
// Compiled with -mavx2 -mfma -ffp-contract=off (CMakeLists.txt): 4 doubles a vector (lane blocks of 8), and no
// multiply–add contraction, so every operation rounds as in the baseline build and the results stay
// bit-identical to the single-body steppers (see batch_lgvi.hpp). This file includes nothing but the
// self-contained kernel headers, whose functions live in namespace lgi::batch_kernel::avx2: no inline function
// compiled here for AVX2 can replace, at link time, one that baseline code calls. batch_lgvi.hpp and
// batch_rkmk.hpp call these only after __builtin_cpu_supports("avx2") and ("fma").
#define LGI_BATCH_ISA avx2
#include "batch_lgvi_kernel.hpp"
#include "batch_rkmk_kernel.hpp"

namespace lgi::batch_kernel {

void run_blocks_avx2(const LgviParams& p, const LgviIO& io, std::size_t block_begin, std::size_t block_end, double h,
                     std::int64_t n_steps, bool torque);

void run_blocks_avx2(const LgviParams& p, const LgviIO& io, std::size_t block_begin, std::size_t block_end, double h,
                     std::int64_t n_steps, bool torque) {
  if (torque)
    avx2::run_blocks<8, true>(p, io, block_begin, block_end, h, n_steps);
  else
    avx2::run_blocks<8, false>(p, io, block_begin, block_end, h, n_steps);
}

void rkmk4_blocks_avx2(const Rkmk4Params& p, const Rkmk4IO& io, std::size_t block_begin, std::size_t block_end,
                       double h, std::int64_t n_steps, bool torque);

void rkmk4_blocks_avx2(const Rkmk4Params& p, const Rkmk4IO& io, std::size_t block_begin, std::size_t block_end,
                       double h, std::int64_t n_steps, bool torque) {
  if (torque)
    avx2::rkmk4_blocks<8, true>(p, io, block_begin, block_end, h, n_steps);
  else
    avx2::rkmk4_blocks<8, false>(p, io, block_begin, block_end, h, n_steps);
}

}  // namespace lgi::batch_kernel
