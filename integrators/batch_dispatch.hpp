// lgi/integrators/batch_dispatch.hpp — what the batched methods (integrate_batch_lgvi, integrate_batch_rkmk4) share
// around their lane-block kernels: the argument checks, the choice of kernel, the per-body path, and the run of a
// batch's blocks over threads with the kernel the caller chose.
#pragma once

#include "../core/batch.hpp"
#include "../core/inertia.hpp"
#include "batch_kernels.hpp"

#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>

namespace lgi::detail {

// The kernel a batched method runs for `problem` (torque: a HeavyTop whose b a per-body `b` may replace), after
// checking the arguments — options, the batch, h and n_steps (check_batch_run), b's length and use, the kernel's
// availability — each failure a std::invalid_argument naming `who`. A requested kernel is kept; `automatic` is
// the widest available one for a diagonal inertia tensor and per_body otherwise; a non-diagonal tensor always
// runs per body. For per_body the bodies are integrated here, each by integrate_batch<Method> with b[i] in place
// of problem.b when b is given; the caller then returns per_body.
template <template <class> class Method, bool torque, class P>
BatchKernel batch_prologue(const char* who, const P& problem, BodyBatch& batch, double t0, double h,
                           std::int64_t n_steps, const StepperOptions& options, const BatchOptions& batch_options,
                           std::span<const double> b, BatchKernel kernel) {
  options.check();
  check_batch_run(batch, h, n_steps);
  if (!b.empty() && !torque) throw std::invalid_argument(std::string(who) + ": per-body b given for a free body");
  if (!b.empty() && b.size() != batch.size())
    throw std::invalid_argument(std::string(who) + ": per-body b has " + std::to_string(b.size()) + " entries for " +
                                std::to_string(batch.size()) + " bodies");
  if (!batch_kernel_available(kernel))
    throw std::invalid_argument(std::string(who) + ": the " + to_string(kernel) +
                                " kernel is not available (lgi::batch not linked, or the CPU lacks it)");
  const bool diagonal = Inertia<double>::is_diagonal(problem.inertia);
  if (kernel == BatchKernel::automatic) kernel = !diagonal ? BatchKernel::per_body : batch_widest_kernel();
  if (kernel == BatchKernel::per_body || !diagonal) {
    if (b.empty()) {
      integrate_batch<Method>(problem, batch, t0, h, n_steps, options, batch_options);
    } else {
      integrate_batch<Method>(
          [&](std::size_t i) {
            P p = problem;
            if constexpr (torque) p.b = b[i];
            return p;
          },
          batch, t0, h, n_steps, options, batch_options);
    }
    return BatchKernel::per_body;
  }
  return kernel;
}

// Runs the `bodies` of a batch in blocks of batch_kernel_width(kernel) lanes over the threads batch_options allows
// (the calling thread takes the first slice): each slice [begin, end) of blocks by avx512(begin, end) or
// avx2(begin, end) when the kernel is that one and lgi::batch provides it, else by baseline(begin, end).
template <class Avx512, class Avx2, class Baseline>
void run_batch_blocks(std::size_t bodies, BatchKernel kernel, const BatchOptions& batch_options,
                      [[maybe_unused]] const Avx512& avx512, [[maybe_unused]] const Avx2& avx2,
                      const Baseline& baseline) {
  const auto width = static_cast<std::size_t>(batch_kernel_width(kernel));
  const std::size_t blocks = (bodies + width - 1) / width;
  parallel_slices(blocks, batch_threads(batch_options, blocks), [&](std::size_t begin, std::size_t end) {
#if defined(LGI_HAVE_BATCH_AVX512)
    if (kernel == BatchKernel::avx512) return avx512(begin, end);
#endif
#if defined(LGI_HAVE_BATCH_AVX2)
    if (kernel == BatchKernel::avx2) return avx2(begin, end);
#endif
    baseline(begin, end);
  });
}

}  // namespace lgi::detail
