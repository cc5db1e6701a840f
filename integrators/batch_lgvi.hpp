/// \file
/// lgi/integrators/batch_lgvi.hpp — the LGVI on many heavy tops (or free bodies) at once, vectorised across bodies.
///
/// Computes, for every body i of a BodyBatch (core/batch.hpp), n_steps steps of `Lgvi<HeavyTop<double>>` or
/// `Lgvi<FreeBody<double>>` (integrators/lgvi.hpp) — the kick + LGVI (Lee, Leok, McClamroch 2005/2007):
///
/// ~~~{.unparsed}
///   h hat(Π_k + ½h M_k) = F_k J_d − J_d F_kᵀ,   R_{k+1} = R_k F_k,   Π_{k+1} = F_kᵀ(Π_k + ½h M_k) + ½h M_{k+1},
/// ~~~
///
/// with F_k the Cayley map of 2c, G(c) = Jc + c × Jc − ½(1 + c·c) h(Π_k + ½h M_k) = 0 solved by two
/// fixed-point sweeps and Newton as in lgvi.hpp, and the heavy-top torque M = b (Rᵀk) × z0
/// (problems/heavy_top.hpp). See lgvi.hpp for the equations' sources and what the method preserves.
///
/// What is preserved: the results — R, Ω, status and the step at which a body stopped — equal, bit for bit, a
/// single-body run y = to_internal(x, t0), y ← step(y, t0 + n h, h) of the same Lgvi stepper (problem, options),
/// for every body, whatever the lane width and the number of threads. The lane loops
/// (integrators/batch_lgvi_kernel.hpp) repeat the single-body arithmetic operation for operation (Eigen's
/// evaluation order included); lanes whose Newton needs fewer iterations stop updating while the others
/// continue; a failing body (not_converged, non_finite) keeps its last good state and leaves its lane.
/// tests/integrators/test_batch.cpp checks all of this.
///
/// Kernels (BatchKernel):
/// ~~~{.unparsed}
///   baseline   lane blocks of 4 bodies (two SSE2 vectors), the build's own flags (x86-64 baseline)
///   avx2       lane blocks of 8 bodies (two AVX vectors), compiled with -mavx2 -mfma -ffp-contract=off in the library
///              lgi::batch (integrators/batch_avx2.cpp); available when that library is linked
///              (it defines LGI_HAVE_BATCH_AVX2) and the CPU has AVX2 and FMA. No FMA contraction, so the bits
///              are the baseline's.
///   avx512     lane blocks of 16 bodies (two zmm vectors), compiled with -mavx512f -mavx512dq -ffp-contract=off in
///              lgi::batch (integrators/batch_avx512.cpp); available when that library is linked (it defines
///              LGI_HAVE_BATCH_AVX512) and the CPU (and OS) support AVX-512F and DQ. Same bits again.
///   per_body   integrate_batch<Lgvi> (core/batch.hpp): the single-body stepper per body
///   automatic  the widest available of avx512, avx2, baseline; per_body when J is not diagonal
/// ~~~
/// Per-body parameters: the heavy top's b (m g ℓ) may differ per body (the span `b`); J, k, z0, h and the
/// stepper options are shared.
///
/// Speed per body-step of every kernel, on one and two threads, and instructions per body-step: bench_batch,
/// docs/performance.md ("Many bodies at once: batches").
///
/// Limits: diagonal J only (the principal-axes frame, J = diag(I1, I2, I3)); any other J runs per_body. Double only.
/// Autonomous problems only (the heavy-top torque does not depend on t; t0 is passed to per_body alone).
/// Bit identity holds against the single-body stepper compiled for the baseline x86-64 instruction set
/// without FMA contraction (the library's builds): compiled with -mavx or wider, Eigen evaluates some 3-term
/// sums of the single-body code in another order, and with FMA contraction its products round differently.
#pragma once

#include "../core/batch.hpp"
#include "../core/inertia.hpp"
#include "../problems/free_body.hpp"
#include "../problems/heavy_top.hpp"
#include "batch_dispatch.hpp"
#include "batch_kernels.hpp"
#include "batch_lgvi_kernel.hpp"
#include "lgvi.hpp"

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>

namespace lgi {

namespace batch_kernel {
// Declared in every build, defined in lgi::batch: called only where it is linked (LGI_HAVE_BATCH_AVX2,
// LGI_HAVE_BATCH_AVX512; detail::run_batch_blocks).
// In lgi::batch (integrators/batch_avx2.cpp): blocks [block_begin, block_end) of avx2_width bodies.
void run_blocks_avx2(const LgviParams& p, const LgviIO& io, std::size_t block_begin, std::size_t block_end, double h,
                     std::int64_t n_steps, bool torque);
// In lgi::batch (integrators/batch_avx512.cpp): blocks [block_begin, block_end) of avx512_width bodies.
void run_blocks_avx512(const LgviParams& p, const LgviIO& io, std::size_t block_begin, std::size_t block_end,
                       double h, std::int64_t n_steps, bool torque);
}  // namespace batch_kernel

/// The problems the LGVI kernels take: the heavy top and the free body, in double.
template <class P>
concept LgviBatchProblem = std::same_as<P, HeavyTop<double>> || std::same_as<P, FreeBody<double>>;

namespace batch_kernel {
/// What every body of an LGVI batch shares, exactly as `Lgvi<P>`(problem, options)'s constructor and solve_cayley
/// compute them. Precondition: problem.inertia diagonal (not checked; integrate_batch_lgvi runs other J per body).
template <LgviBatchProblem P>
LgviParams lgvi_params(const P& problem, const StepperOptions& options) {
  constexpr bool torque = std::same_as<P, HeavyTop<double>>;
  const Inertia<double> J(problem.inertia);
  LgviParams p{};
  const auto inf_norm = [](const Mat3<double>& M) {
    double n = 0;
    for (int r = 0; r < 3; ++r) {
      double row = 0;
      for (int c = 0; c < 3; ++c) row += std::abs(M(r, c));
      n = std::max(n, row);
    }
    return n;
  };
  const Vec3<double> I = J.J.diagonal();
  for (int j = 0; j < 3; ++j) {
    p.J[j] = J.J(j, j);
    p.J_inv[j] = J.J_inv(j, j);
  }
  p.d[0] = I(2) - I(1);
  p.d[1] = I(0) - I(2);
  p.d[2] = I(1) - I(0);
  p.J_norm = inf_norm(J.J);
  p.J_inv_norm = inf_norm(J.J_inv);
  p.floor = std::max(options.tolerance, static_cast<double>(16 * std::numeric_limits<double>::epsilon()) * p.J_norm *
                                            p.J_inv_norm);
  p.tolerance = options.tolerance;
  p.max_iterations = options.max_iterations;
  if constexpr (torque) {
    for (int j = 0; j < 3; ++j) {
      p.k[j] = problem.k(j);
      p.z0[j] = problem.z0(j);
    }
    p.b = problem.b;
  }
  return p;
}
}  // namespace batch_kernel

/// Integrates every body of `batch` n_steps steps of h with `Lgvi<P>`(problem, options) (per body: b[i] in place of
/// problem.b when `b` is not empty; heavy top only). Returns the kernel that ran. Throws std::invalid_argument
/// for a bad argument (b's length, b with the free body, avx2 or avx512 requested but unavailable, h, n_steps,
/// options).
template <LgviBatchProblem P>
BatchKernel integrate_batch_lgvi(const P& problem, BodyBatch& batch, double t0, double h, std::int64_t n_steps,
                                 const StepperOptions& options = {}, const BatchOptions& batch_options = {},
                                 std::span<const double> b = {}, BatchKernel kernel = BatchKernel::automatic) {
  constexpr bool torque = std::same_as<P, HeavyTop<double>>;
  kernel = detail::batch_prologue<Lgvi, torque>("lgi::integrate_batch_lgvi", problem, batch, t0, h, n_steps, options,
                                                   batch_options, b, kernel);
  if (kernel == BatchKernel::per_body) return kernel;
  const batch_kernel::LgviParams p = batch_kernel::lgvi_params(problem, options);
  const auto io = batch_kernel::bind_io(batch, b);
  detail::run_batch_blocks(
      batch.size(), kernel, batch_options,
      [&](std::size_t begin, std::size_t end) {
        batch_kernel::run_blocks_avx512(p, io, begin, end, h, n_steps, torque);
      },
      [&](std::size_t begin, std::size_t end) {
        batch_kernel::run_blocks_avx2(p, io, begin, end, h, n_steps, torque);
      },
      [&](std::size_t begin, std::size_t end) {
        batch_kernel::baseline::run_blocks<batch_kernel::baseline_width, torque>(p, io, begin, end, h, n_steps);
      });
  return kernel;
}

}  // namespace lgi
