/// \file
/// lgi/integrators/batch_rkmk.hpp — RKMK4 on many heavy tops (or free bodies) at once, vectorised across bodies.
///
/// Computes, for every body i of a BodyBatch (core/batch.hpp), n_steps steps of `Rkmk4<HeavyTop<double>>` or
/// `Rkmk4<FreeBody<double>>` (integrators/rkmk.hpp: Runge–Kutta–Munthe-Kaas with the classical RK4 tableau,
/// Munthe-Kaas, BIT 38 (1998) 92; Hairer–Lubich–Wanner, GNI 2nd ed., Algorithm IV.8.3):
///
/// ~~~{.unparsed}
///   stage i:  u_i = h Σ_j a_ij U_j,  W_i = Ω_n + h Σ_j a_ij V_j,  U_i = J_r⁻¹(u_i) W_i (series to ad²),
///             V_i = J⁻¹((JW_i) × W_i + b Γ_i × z0),  Γ_i = exp(u_i)ᵀ R_nᵀ k
///   update:   R_{n+1} = R_n exp(h Σ b_i U_i),  Ω_{n+1} = Ω_n + h Σ b_i V_i.
/// ~~~
///
/// Order 4; R stays on SO(3) to round-off; not symplectic, energy and momentum drift like RK4's (see rkmk.hpp).
///
/// What is preserved: the results — R, Ω, status and the step at which a body stopped — equal, bit for bit, a
/// single-body run y = to_internal(x, t0), y ← step(y, t0 + n h, h) of the same Rkmk4 stepper, for every body,
/// whatever the kernel and the number of threads. The lane loops (integrators/batch_rkmk_kernel.hpp) repeat the
/// single-body arithmetic operation for operation; the exponential's coefficients come from core/trig.hpp's
/// series and polynomial sin (the same data and templates as so3::exp_coefficients) for rotation angles up to π,
/// and from so3::exp_coefficients itself, lane by lane, beyond π. RKMK4 is explicit: a body fails only when its state
/// becomes non-finite (status non_finite); it keeps its last good state and leaves its lane.
/// tests/integrators/test_batch.cpp checks all of this.
///
/// Kernels: BatchKernel (integrators/batch_kernels.hpp) — baseline (4 lanes), avx2 (8), avx512 (16), per_body,
/// automatic (the widest available; per_body when J is not diagonal). Per-body parameters: the heavy top's b
/// (span `b`); J, k, z0 and h are shared.
///
/// Limits: diagonal J only (other J run per_body); double only; autonomous problems (t0 reaches per_body alone).
/// Bit identity holds against the single-body stepper compiled for the baseline x86-64 instruction set without
/// FMA contraction (the library's builds), as for batch_lgvi.hpp.
#pragma once

#include "../core/batch.hpp"
#include "../core/inertia.hpp"
#include "../core/so3.hpp"
#include "../problems/free_body.hpp"
#include "../problems/heavy_top.hpp"
#include "batch_dispatch.hpp"
#include "batch_kernels.hpp"
#include "batch_rkmk_kernel.hpp"
#include "butcher_tableaus.hpp"
#include "rkmk.hpp"

#include <concepts>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>

namespace lgi {

namespace batch_kernel {
// Declared in every build, defined in lgi::batch: called only where it is linked (LGI_HAVE_BATCH_AVX2,
// LGI_HAVE_BATCH_AVX512; detail::run_batch_blocks).
// In lgi::batch (integrators/batch_avx2.cpp): blocks [block_begin, block_end) of avx2_width bodies.
void rkmk4_blocks_avx2(const Rkmk4Params& p, const Rkmk4IO& io, std::size_t block_begin, std::size_t block_end,
                       double h, std::int64_t n_steps, bool torque);
// In lgi::batch (integrators/batch_avx512.cpp): blocks [block_begin, block_end) of avx512_width bodies.
void rkmk4_blocks_avx512(const Rkmk4Params& p, const Rkmk4IO& io, std::size_t block_begin, std::size_t block_end,
                         double h, std::int64_t n_steps, bool torque);

/// The kernels' fallback for lanes beyond the polynomial sin's range (θ > π, or not finite): so3::exp_coefficients,
/// compiled here, in the caller's translation unit (never in lgi::batch's AVX ones).
inline void rkmk4_exp_coefficients(const double* w, double* AB) {
  const so3::Coefficients<double> k = so3::exp_coefficients(Vec3<double>(w[0], w[1], w[2]));
  AB[0] = k.A;
  AB[1] = k.B;
}

/// The kernel is written for the classical RK4 pattern: a10, a21, a32 the only non-zero entries, every b_i ≠ 0.
constexpr bool rkmk4_kernel_pattern() {
  const auto& T = tableaus::classical_rk4;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j)
      if ((T.a[i][j] != 0) != (j + 1 == i)) return false;
    if (T.b[i] == 0) return false;
  }
  return true;
}
static_assert(rkmk4_kernel_pattern(), "batch_rkmk_kernel.hpp assumes the classical RK4 tableau's sparsity");
}  // namespace batch_kernel

/// The problems the RKMK4 kernels take: the heavy top and the free body, in double.
template <class P>
concept Rkmk4BatchProblem = std::same_as<P, HeavyTop<double>> || std::same_as<P, FreeBody<double>>;

namespace batch_kernel {
/// What every body of an RKMK4 batch shares, exactly as `Rkmk4<P>`(problem)'s constructor and the classical RK4
/// tableau give them. Precondition: problem.inertia diagonal (not checked; integrate_batch_rkmk4 runs other J per
/// body).
template <Rkmk4BatchProblem P>
Rkmk4Params rkmk4_params(const P& problem) {
  constexpr bool torque = std::same_as<P, HeavyTop<double>>;
  const Inertia<double> J(problem.inertia);
  Rkmk4Params p{};
  for (int j = 0; j < 3; ++j) {
    p.J[j] = J.J(j, j);
    p.J_inv[j] = J.J_inv(j, j);
  }
  if constexpr (torque) {
    for (int j = 0; j < 3; ++j) {
      p.k[j] = problem.k(j);
      p.z0[j] = problem.z0(j);
    }
    p.b = problem.b;
  }
  const auto& T = tableaus::classical_rk4;
  p.a10 = T.a[1][0];
  p.a21 = T.a[2][1];
  p.a32 = T.a[3][2];
  p.b0 = T.b[0];
  p.b1 = T.b[1];
  p.b2 = T.b[2];
  p.b3 = T.b[3];
  p.exp_coefficients = &rkmk4_exp_coefficients;
  return p;
}
}  // namespace batch_kernel

/// Integrates every body of `batch` n_steps steps of h with `Rkmk4<P>`(problem, options) (per body: b[i] in place of
/// problem.b when `b` is not empty; heavy top only). Returns the kernel that ran. Throws std::invalid_argument for
/// a bad argument (b's length, b with the free body, a kernel requested but unavailable, h, n_steps, options).
template <Rkmk4BatchProblem P>
BatchKernel integrate_batch_rkmk4(const P& problem, BodyBatch& batch, double t0, double h, std::int64_t n_steps,
                                  const StepperOptions& options = {}, const BatchOptions& batch_options = {},
                                  std::span<const double> b = {}, BatchKernel kernel = BatchKernel::automatic) {
  constexpr bool torque = std::same_as<P, HeavyTop<double>>;
  kernel = detail::batch_prologue<Rkmk4, torque>("lgi::integrate_batch_rkmk4", problem, batch, t0, h, n_steps, options,
                                                   batch_options, b, kernel);
  if (kernel == BatchKernel::per_body) return kernel;
  const batch_kernel::Rkmk4Params p = batch_kernel::rkmk4_params(problem);
  const auto io = batch_kernel::bind_io(batch, b);
  detail::run_batch_blocks(
      batch.size(), kernel, batch_options,
      [&](std::size_t begin, std::size_t end) {
        batch_kernel::rkmk4_blocks_avx512(p, io, begin, end, h, n_steps, torque);
      },
      [&](std::size_t begin, std::size_t end) {
        batch_kernel::rkmk4_blocks_avx2(p, io, begin, end, h, n_steps, torque);
      },
      [&](std::size_t begin, std::size_t end) {
        batch_kernel::baseline::rkmk4_blocks<batch_kernel::baseline_width, torque>(p, io, begin, end, h, n_steps);
      });
  return kernel;
}

}  // namespace lgi
