// lgi/integrators/batch_avx512.cpp — the batched kernels' lane blocks compiled for AVX-512 (library lgi::batch).
//
// Compiled with -mavx512f -mavx512dq -ffp-contract=off (CMakeLists.txt): 8 doubles a vector (lane blocks of 16,
// two zmm registers), and no multiply–add contraction, so every operation rounds as in the baseline build and
// the results stay bit-identical to the single-body steppers (see batch_lgvi.hpp). This file includes nothing
// but the self-contained kernel headers, whose functions live in namespace lgi::batch_kernel::avx512: no inline
// function compiled here for AVX-512 can replace, at link time, one that baseline code calls. batch_lgvi.hpp
// and batch_rkmk.hpp call these only after __builtin_cpu_supports("avx512f") and ("avx512dq") (which also check
// that the operating system saves the zmm state).
#define LGI_BATCH_ISA avx512
#include "batch_lgvi_kernel.hpp"
#include "batch_rkmk_kernel.hpp"

namespace lgi::batch_kernel {

void run_blocks_avx512(const LgviParams& p, const LgviIO& io, std::size_t block_begin, std::size_t block_end,
                       double h, std::int64_t n_steps, bool torque);

void run_blocks_avx512(const LgviParams& p, const LgviIO& io, std::size_t block_begin, std::size_t block_end,
                       double h, std::int64_t n_steps, bool torque) {
  if (torque)
    avx512::run_blocks<16, true>(p, io, block_begin, block_end, h, n_steps);
  else
    avx512::run_blocks<16, false>(p, io, block_begin, block_end, h, n_steps);
}

void rkmk4_blocks_avx512(const Rkmk4Params& p, const Rkmk4IO& io, std::size_t block_begin, std::size_t block_end,
                       double h, std::int64_t n_steps, bool torque);

void rkmk4_blocks_avx512(const Rkmk4Params& p, const Rkmk4IO& io, std::size_t block_begin, std::size_t block_end,
                       double h, std::int64_t n_steps, bool torque) {
  if (torque)
    avx512::rkmk4_blocks<16, true>(p, io, block_begin, block_end, h, n_steps);
  else
    avx512::rkmk4_blocks<16, false>(p, io, block_begin, block_end, h, n_steps);
}

}  // namespace lgi::batch_kernel
