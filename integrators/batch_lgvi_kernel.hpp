/// \file
/// lgi/integrators/batch_lgvi_kernel.hpp — the vectorised lane blocks of the batched LGVI (see batch_lgvi.hpp).
///
/// Computes, for W bodies at once (one "lane block"), exactly the operations of `Lgvi<HeavyTop<double>>`::step
/// (integrators/lgvi.hpp; torque M = b (Rᵀk) × z0, problems/heavy_top.hpp) and of `Lgvi<FreeBody<double>>`::step
/// (Torque = false) for a diagonal inertia tensor J = diag(I):
///
/// ~~~{.unparsed}
///   Π̃ = Π_k + ½h M_k,  μ = hΠ̃,  c₀ = J⁻¹ ½μ,  two sweeps c ← J⁻¹(½(1 + c·c)μ − c × Jc),
///   Newton c ← c − dG⁻¹ G(c) (Cramer's rule) until lgvi.hpp's convergence test holds,
///   s = 2/(1 + c·c),  F − I = s(hat(c) + hat(c)²),  R_{k+1} = R_k + R_k (F − I),
///   Π_{k+1} = Π̃ + (F − I)ᵀ Π̃ + ½h M_{k+1},  M_{k+1} = b (R_{k+1}ᵀ k) × z0.
/// ~~~
///
/// Each scalar expression below is written in the order in which Eigen 3.4 evaluates the single-body code on
/// x86-64 with SSE2 (2-double packets) and no FMA contraction: 3-term dots and squared norms ((x₀ + x₁) + x₂);
/// maxCoeff of |v| a left fold m ← (m < vᵢ) ? vᵢ : m (so a NaN in v₁ or v₂ is skipped, as Eigen does); the 3×3
/// product R·(F − I) with rows 0 and 1 as ((p₀ + p₁) + p₂) (packet path) and row 2 as p₀ + (p₁ + p₂) (scalar
/// redux); (F − I)ᵀΠ and Rᵀk as ((p₀ + p₁) + p₂); cross products a × b = (a₁b₂ − a₂b₁, a₂b₀ − a₀b₂, a₀b₁ − a₁b₀).
/// tests/integrators/test_batch.cpp checks the outcome bit for bit against the single-body stepper.
///
/// Per-lane Newton iteration counts differ: the block iterates while any lane is active and applies an update
/// only to active lanes (a blend), so each lane performs exactly the single-body iterations. A lane whose
/// step fails (not_converged, non_finite) is written out with its last good state and then replaced by a
/// benign body (R = I, Π = 0, b = 0: Newton converges at once on c = 0), so it neither slows nor disturbs the
/// other lanes. No libm calls: only + − × ÷, comparisons and bit operations.
///
/// Vectorisation (integrators/batch_lanes.hpp): GCC vector extensions, a Pack of U machine vectors per block,
/// W = U·VW lanes (batch_kernels.hpp picks U = 2: W = 4 with SSE2, 8 with AVX2, 16 with AVX-512; faster than
/// U = 1, see there). Plain lane loops were tried first: GCC 12 left the Newton and update loops scalar
/// ("control flow in loop"); generic vectors wider than the machine's were lowered to scalar code for ?: and
/// comparisons, hence masks are blended with bit operations and blocks are whole machine vectors.
///
/// Limits: GCC (or Clang) only — vector extensions and __builtin_bit_cast; diagonal J; double.
///
/// Self-contained on purpose (no Eigen, no standard-library functions): integrators/batch_avx2.cpp compiles
/// this header with -mavx2 -mfma -ffp-contract=off and integrators/batch_avx512.cpp with -mavx512f -mavx512dq
/// -ffp-contract=off, and every function here lives in the namespace named by LGI_BATCH_ISA, so no inline
/// function compiled for AVX2 or AVX-512 can be merged by the linker into code that runs on the baseline
/// instruction set.
#pragma once

#include "batch_lanes.hpp"

#include <cstddef>
#include <cstdint>

namespace lgi::batch_kernel {

/// What every body of the batch shares: from Lgvi's constructor (`Inertia<double>`, StepperOptions) and the
/// heavy top's k and z0. b is the default m g ℓ when no per-body array is given.
struct LgviParams {
  double J[3];      ///< diagonal of J
  double J_inv[3];  ///< diagonal of `Inertia<double>`::J_inv (J.inverse(): not necessarily 1/I_i to the bit)
  double d[3];      ///< (I3 − I2, I1 − I3, I2 − I1)
  double J_norm, J_inv_norm;
  double floor;  ///< max(tolerance, 16 ε ‖J‖∞‖J⁻¹‖∞)
  double tolerance;
  int max_iterations;
  double k[3], z0[3];
  double b;
};

using LgviIO = BatchIO;  ///< batch_lanes.hpp

}  // namespace lgi::batch_kernel


namespace lgi::batch_kernel::LGI_BATCH_ISA {

/// One block of W lanes, bodies first … first + W − 1 (lanes past io.n are benign padding), n_steps steps.
template <int W, bool Torque>
void run_block(const LgviParams& p, const LgviIO& io, std::size_t first, double h, std::int64_t n_steps) {
  static_assert(W % VW == 0, "lane block width: a multiple of the machine vector's");
  constexpr int U = W / VW;
  using V = Pack<MV, U>;
  using I = Pack<MI, U>;
  const I true_mask = all_true<U>();
  // m = Eigen's (|a|, |b|, |c|).maxCoeff(): |x| clears the sign bit (as fabs), then a left fold that keeps m
  // when the comparison is false (a NaN in the 2nd or 3rd entry is skipped). Results by reference: a lambda
  // returning a vector wider than the baseline ABI's registers draws GCC's -Wpsabi note.
  const auto max3abs = [&](V& m, const V& a, const V& b, const V& c) {
    m = abs(a);
    const V ab = abs(b), ac = abs(c);
    select(m, m < ab, ab, m);
    select(m, m < ac, ac, m);
  };

  // (R, Π, M) of the lanes in two buffers, S[cur] the current state: a step writes the next state into the
  // other buffer and flips cur when every lane succeeded (no copy in the common case).
  V S[2][15], b;  // R(r, c) at [3r + c], Π at [9 + j], M at [12 + j]
  int cur = 0;
  bool live[W];
  const int all_lanes = (1 << W) - 1;
  const double J0 = p.J[0], J1 = p.J[1], J2 = p.J[2];
  const double iJ0 = p.J_inv[0], iJ1 = p.J_inv[1], iJ2 = p.J_inv[2];
  const double d0 = p.d[0], d1 = p.d[1], d2 = p.d[2];
  const double k0 = p.k[0], k1 = p.k[1], k2 = p.k[2], z0 = p.z0[0], z1 = p.z0[1], z2 = p.z0[2];
  const double Jn = p.J_norm, Jin = p.J_inv_norm, floor = p.floor, tol = p.tolerance;
  const double half_h = 0.5 * h;

  const auto benign = [&](int l) {
    for (int e = 0; e < 15; ++e) set_lane(S[cur][e], l, (e < 9 && e % 4 == 0) ? 1.0 : 0.0);
    set_lane(b, l, 0.0);
    live[l] = false;
  };
  // Omega = J⁻¹Π (Inertia::solve): the last good state of lane l, with its status and step count.
  const auto write_out = [&](int l, std::uint8_t status, std::int64_t steps) {
    const std::size_t i = first + static_cast<std::size_t>(l);
    const V* X = S[cur];
    for (int e = 0; e < 9; ++e) io.R[e][i] = lane(X[e], l);
    io.Omega[0][i] = iJ0 * lane(X[9], l);
    io.Omega[1][i] = iJ1 * lane(X[10], l);
    io.Omega[2][i] = iJ2 * lane(X[11], l);
    io.status[i] = status;
    io.steps[i] = steps;
  };
  // M = b (Rᵀk) × z0 (body_torque → reduced_torque), or 0 for the free body; r[3r + c] = R(r, c).
  const auto torque = [&](const V* r, const V& bl, V* m) {
    if constexpr (Torque) {
      const V g0 = (r[0] * k0 + r[3] * k1) + r[6] * k2;  // Γ_i = (R(0,i) k0 + R(1,i) k1) + R(2,i) k2
      const V g1 = (r[1] * k0 + r[4] * k1) + r[7] * k2;
      const V g2 = (r[2] * k0 + r[5] * k1) + r[8] * k2;
      m[0] = bl * (g1 * z2 - g2 * z1);
      m[1] = bl * (g2 * z0 - g0 * z2);
      m[2] = bl * (g0 * z1 - g1 * z0);
    } else {
      (void)r;
      (void)bl;
      m[0] = m[1] = m[2] = V{};
    }
  };

  int alive = 0;
  for (int l = 0; l < W; ++l) {
    const std::size_t i = first + static_cast<std::size_t>(l);
    if (i >= io.n) {
      benign(l);
      continue;
    }
    for (int e = 0; e < 9; ++e) set_lane(S[cur][e], l, io.R[e][i]);
    set_lane(S[cur][9], l, J0 * io.Omega[0][i]);  // Π = Inertia::apply(Ω): J.diagonal() ⊙ Ω
    set_lane(S[cur][10], l, J1 * io.Omega[1][i]);
    set_lane(S[cur][11], l, J2 * io.Omega[2][i]);
    set_lane(b, l, io.b ? io.b[i] : p.b);
    live[l] = true;
    ++alive;
  }
  torque(S[cur], b, S[cur] + 12);

  for (std::int64_t n = 0; n < n_steps && alive > 0; ++n) {
    V* const R = S[cur];
    const V* const Pi = R + 9;
    const V* const M = R + 12;
    V* const q = S[cur ^ 1];  // the next R, Π (Q) and M (N)
    V* const Q = q + 9;
    V* const N = q + 12;
    // Kick, predictor: μ = hΠ̃, c = J⁻¹ ½μ, two fixed-point sweeps; the bound K of the convergence test.
    V P0 = Pi[0], P1 = Pi[1], P2 = Pi[2];
    if constexpr (Torque) {
      P0 = P0 + half_h * M[0];
      P1 = P1 + half_h * M[1];
      P2 = P2 + half_h * M[2];
    }
    const V mu0 = h * P0, mu1 = h * P1, mu2 = h * P2;
    const V h0 = 0.5 * mu0, h1 = 0.5 * mu1, h2 = 0.5 * mu2;
    V c0 = iJ0 * h0, c1 = iJ1 * h1, c2 = iJ2 * h2;
    for (int sweep = 0; sweep < 2; ++sweep) {
      const V a = 1.0 + ((c0 * c0 + c1 * c1) + c2 * c2);
      const V n0 = (a * h0 - d0 * c1 * c2) * iJ0;
      const V n1 = (a * h1 - d1 * c2 * c0) * iJ1;
      const V n2 = (a * h2 - d2 * c0 * c1) * iJ2;
      c0 = n0;
      c1 = n1;
      c2 = n2;
    }
    V mu_max;
    max3abs(mu_max, mu0, mu1, mu2);
    const V K = Jin * (Jn + mu_max);
    const V m0 = 2.0 * h0, m1 = 2.0 * h1, m2 = 2.0 * h2;
    // Newton on G(c) = Jc + c × Jc − ½(1 + c·c)μ, updates applied to active lanes only.
    I active = true_mask, non_finite = I{};
    for (int it = 0; it < p.max_iterations; ++it) {
      const V a = 1.0 + ((c0 * c0 + c1 * c1) + c2 * c2);
      const V G0 = J0 * c0 + d0 * c1 * c2 - a * h0;
      const V G1 = J1 * c1 + d1 * c2 * c0 - a * h1;
      const V G2 = J2 * c2 + d2 * c0 * c1 - a * h2;
      const V r00 = J0 - m0 * c0, r01 = d0 * c2 - m0 * c1, r02 = d0 * c1 - m0 * c2;
      const V r10 = d1 * c2 - m1 * c0, r11 = J1 - m1 * c1, r12 = d1 * c0 - m1 * c2;
      const V r20 = d2 * c1 - m2 * c0, r21 = d2 * c0 - m2 * c1, r22 = J2 - m2 * c2;
      const V x12 = r11 * r22 - r12 * r21, y12 = r12 * r20 - r10 * r22, z12 = r10 * r21 - r11 * r20;
      const V x20 = r21 * r02 - r22 * r01, y20 = r22 * r00 - r20 * r02, z20 = r20 * r01 - r21 * r00;
      const V x01 = r01 * r12 - r02 * r11, y01 = r02 * r10 - r00 * r12, z01 = r00 * r11 - r01 * r10;
      const V det = (r00 * x12 + r01 * y12) + r02 * z12;
      const V e0 = (G0 * x12 + G1 * x20 + G2 * x01) / det;
      const V e1 = (G0 * y12 + G1 * y20 + G2 * y01) / det;
      const V e2 = (G0 * z12 + G1 * z20 + G2 * z01) / det;
      const V n0 = c0 - e0, n1 = c1 - e1, n2 = c2 - e2;
      V dd, scale;
      max3abs(dd, e0, e1, e2);
      max3abs(scale, n0, n1, n2);
      const I fin = dd <= 1.7976931348623157e308;  // false for NaN and ∞, like std::isfinite
      V ds;
      select(ds, fin, dd, V{});
      const I converged = (ds <= floor * scale) | ((ds <= 1e-3 * scale) & (4.0 * K * ds * ds <= tol * scale));
      select(c0, active, n0, c0);
      select(c1, active, n1, c1);
      select(c2, active, n2, c2);
      non_finite = non_finite | (active & ~fin);
      active = active & fin & ~converged;
      if (bits(active) == 0) break;
    }
    // The update of (R, Π, M) for lanes whose Newton converged; committed only where all of it is finite.
    const V s = 2.0 / (1.0 + ((c0 * c0 + c1 * c1) + c2 * c2));
    const V bx = s * c0, by = s * c1, bz = s * c2;  // so3::rodrigues_increment(c, s, s)
    const V bxx = bx * c0, byy = by * c1, bzz = bz * c2;
    const V bxy = bx * c1, bxz = bx * c2, byz = by * c2;
    const V D00 = -(byy + bzz), D01 = bxy - bz, D02 = bxz + by;
    const V D10 = bxy + bz, D11 = -(bxx + bzz), D12 = byz - bx;
    const V D20 = bxz - by, D21 = byz + bx, D22 = -(bxx + byy);
    // q = R + R (F − I): rows 0, 1 as Eigen's packet path, row 2 as its scalar redux
    for (int i = 0; i < 2; ++i) {
      const V a0 = R[3 * i], a1 = R[3 * i + 1], a2 = R[3 * i + 2];
      q[3 * i + 0] = R[3 * i + 0] + ((a0 * D00 + a1 * D10) + a2 * D20);
      q[3 * i + 1] = R[3 * i + 1] + ((a0 * D01 + a1 * D11) + a2 * D21);
      q[3 * i + 2] = R[3 * i + 2] + ((a0 * D02 + a1 * D12) + a2 * D22);
    }
    q[6] = R[6] + (R[6] * D00 + (R[7] * D10 + R[8] * D20));
    q[7] = R[7] + (R[6] * D01 + (R[7] * D11 + R[8] * D21));
    q[8] = R[8] + (R[6] * D02 + (R[7] * D12 + R[8] * D22));
    // Q = Π̃ + (F − I)ᵀ Π̃ + ½h M_{k+1}
    Q[0] = P0 + ((D00 * P0 + D10 * P1) + D20 * P2);
    Q[1] = P1 + ((D01 * P0 + D11 * P1) + D21 * P2);
    Q[2] = P2 + ((D02 * P0 + D12 * P1) + D22 * P2);
    torque(q, b, N);
    if constexpr (Torque)
      for (int j = 0; j < 3; ++j) Q[j] = Q[j] + half_h * N[j];
    // All finite: x − x is 0 for finite x and NaN for ±∞ and NaN (Eigen's allFinite), and a sum of zeros is 0.
    V zero = (q[0] - q[0]) + (q[1] - q[1]);
    for (int e = 2; e < 9; ++e) zero = zero + (q[e] - q[e]);
    for (int j = 0; j < 3; ++j) zero = zero + (Q[j] - Q[j]);
    const I ok = ~active & ~non_finite & (zero == zero);
    if (bits(ok) == all_lanes) [[likely]] {
      cur ^= 1;
    } else {  // failing lanes keep their state
      for (int e = 0; e < 15; ++e) select(q[e], ok, q[e], R[e]);
      cur ^= 1;
      for (int l = 0; l < W; ++l)
        if (live[l] && lane(ok, l) == 0) {
          write_out(l, lane(active, l) != 0 ? status_not_converged : status_non_finite, n);
          benign(l);
          --alive;
        }
    }
  }
  for (int l = 0; l < W; ++l)
    if (live[l]) write_out(l, status_ok, n_steps);
}

/// Blocks [block_begin, block_end) of W lanes each.
template <int W, bool Torque>
void run_blocks(const LgviParams& p, const LgviIO& io, std::size_t block_begin, std::size_t block_end, double h,
                std::int64_t n_steps) {
  for (std::size_t k = block_begin; k < block_end; ++k) run_block<W, Torque>(p, io, k * W, h, n_steps);
}

}  // namespace lgi::batch_kernel::LGI_BATCH_ISA
