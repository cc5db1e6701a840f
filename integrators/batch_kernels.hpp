/// \file
/// lgi/integrators/batch_kernels.hpp — which lane-block kernel a batched method runs (BatchKernel), and which
/// ones this program and CPU can run. Shared by the batched LGVI (batch_lgvi.hpp) and RKMK4 (batch_rkmk.hpp).
///
/// ~~~{.unparsed}
///   baseline   lane blocks of 4 bodies (two SSE2 vectors), the build's own flags (x86-64 baseline)
///   avx2       lane blocks of 8 (two ymm vectors), integrators/batch_avx2.cpp in lgi::batch, compiled with -mavx2
///              -mfma -ffp-contract=off; needs that library linked (LGI_HAVE_BATCH_AVX2) and an AVX2+FMA CPU
///   avx512     lane blocks of 16 (two zmm vectors), integrators/batch_avx512.cpp in lgi::batch, compiled with
///              -mavx512f -mavx512dq -ffp-contract=off; needs LGI_HAVE_BATCH_AVX512 and an AVX-512F+DQ CPU and OS
/// ~~~
/// Two machine vectors a block (U = 2 in batch_lanes.hpp's Pack) interleave two independent dependency chains:
/// faster in CPU time than one vector a block for both methods with every kernel, although the wider blocks
/// spill more and take more instructions per body-step (bench_batch measures both: docs/performance.md).
/// ~~~{.unparsed}
///   per_body   the single-body stepper per body (core/batch.hpp's integrate_batch)
///   automatic  the widest of avx512, avx2, baseline that can run (per_body where the kernels do not apply)
/// ~~~
/// No FMA contraction anywhere, so every kernel gives the baseline single-body bits.
#pragma once

#include "../core/integrator.hpp"
#include "batch_lanes.hpp"

#include <cstddef>
#include <cstdint>
#include <span>

namespace lgi {

namespace batch_kernel {
static_assert(status_ok == static_cast<std::uint8_t>(StepStatus::ok) &&
              status_not_converged == static_cast<std::uint8_t>(StepStatus::not_converged) &&
              status_non_finite == static_cast<std::uint8_t>(StepStatus::non_finite));
static_assert(sizeof(StepStatus) == 1);
inline constexpr int baseline_width = 4;
inline constexpr int avx2_width = 8;
inline constexpr int avx512_width = 16;

/// The kernels' view of a BodyBatch: pointers to its structure-of-arrays columns, and the per-body b or nullptr.
template <class Batch>
BatchIO bind_io(Batch& batch, std::span<const double> b) {
  BatchIO io{};
  for (std::size_t e = 0; e < 9; ++e) io.R[e] = batch.R[e].data();
  for (std::size_t j = 0; j < 3; ++j) io.Omega[j] = batch.Omega[j].data();
  io.status = reinterpret_cast<std::uint8_t*>(batch.status.data());
  io.steps = batch.steps.data();
  io.b = b.empty() ? nullptr : b.data();
  io.n = batch.size();
  return io;
}
}  // namespace batch_kernel

/// Which kernel a batched method runs: automatic, baseline, avx2, per_body, avx512 (this header's list).
enum class BatchKernel : std::uint8_t { automatic, baseline, avx2, per_body, avx512 };

/// The kernel's name as this header lists it ("?" outside the enumeration).
inline const char* to_string(BatchKernel k) {
  switch (k) {
    case BatchKernel::automatic: return "automatic";
    case BatchKernel::baseline: return "baseline";
    case BatchKernel::avx2: return "avx2";
    case BatchKernel::avx512: return "avx512";
    case BatchKernel::per_body: return "per_body";
  }
  return "?";
}

/// True when the AVX2 kernel is linked in (lgi::batch) and this CPU runs it.
inline bool batch_avx2_available() {
#if defined(LGI_HAVE_BATCH_AVX2)
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

/// True when the AVX-512 kernel is linked in (lgi::batch) and this CPU (and operating system) runs it.
inline bool batch_avx512_available() {
#if defined(LGI_HAVE_BATCH_AVX512)
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq");
#else
  return false;
#endif
}

/// True when `kernel` can run here (automatic and per_body always can).
inline bool batch_kernel_available(BatchKernel kernel) {
  switch (kernel) {
    case BatchKernel::avx2: return batch_avx2_available();
    case BatchKernel::avx512: return batch_avx512_available();
    default: return true;
  }
}

/// The widest lane-block kernel this program and CPU run: avx512, avx2 or baseline.
inline BatchKernel batch_widest_kernel() {
  return batch_avx512_available() ? BatchKernel::avx512 : batch_avx2_available() ? BatchKernel::avx2 : BatchKernel::baseline;
}

/// The bodies per lane block of a lane-block kernel: 16 (avx512), 8 (avx2), 4 (baseline and the others).
inline int batch_kernel_width(BatchKernel kernel) {
  return kernel == BatchKernel::avx512 ? batch_kernel::avx512_width
         : kernel == BatchKernel::avx2 ? batch_kernel::avx2_width
                                       : batch_kernel::baseline_width;
}

}  // namespace lgi
