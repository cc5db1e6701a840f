/// \file
/// lgi/integrators/batch_rkmk_kernel.hpp — the vectorised lane blocks of the batched RKMK4 (see batch_rkmk.hpp).
///
/// Computes, for W bodies at once (one "lane block"), exactly the operations of `Rkmk4<HeavyTop<double>>`::step
/// (integrators/rkmk.hpp with the classical RK4 tableau; the heavy top is a ReducedAttitudeProblem, so the stages
/// rotate Γ = Rᵀk instead of forming attitudes) and of `Rkmk4<FreeBody<double>>`::step (Torque = false: no Γ, no
/// stage exponentials) for a diagonal inertia tensor J = diag(I):
///
/// ~~~{.unparsed}
///   Γ = Rᵀk;  U₀ = Ω,  V₀ = J⁻¹((JΩ) × Ω + b Γ × z0)
///   stage i = 1, 2, 3 (a₁₀ = a₂₁ = ½, a₃₂ = 1):
///     u = (0 + a U_{i−1}) h,  W = Ω + h (0 + a V_{i−1}),
///     U_i = W + ½ u × W + (1/12) u × (u × W)                     (J_r⁻¹ series truncated after ad²)
///     Γ_i = Γ − A u × Γ + B u × (u × Γ),  (A, B) = exp_coefficients(u)      (exp(u)ᵀ Γ)
///     V_i = J⁻¹((JW) × W + b Γ_i × z0)
///   u = (((0 + b₀U₀) + b₁U₁) + b₂U₂) + b₃U₃,  likewise dΩ with V;  (A, B) = exp_coefficients(hu),
///   R_{n+1} = R + R (A hat(hu) + B hat(hu)²),  Ω_{n+1} = Ω + h dΩ,  committed where all of it is finite.
/// ~~~
///
/// exp_coefficients (core/so3.hpp) lane by lane: θ² = (w₀² + w₁²) + w₂²; θ² < 1e-2: the Taylor polynomials of
/// core/trig.hpp; θ² < 2: B by core/trig.hpp's series exp_series_B, A = √(B (2 − θ² B)); θ ≤ π: A = sin θ/θ,
/// B = 2 (sin(θ/2)/θ)² with core/trig.hpp's polynomial sin, the same templates as the scalar code instantiated on
/// the lane packs; θ > π or not finite: the lane calls back into
/// so3::exp_coefficients itself (Rkmk4Params::exp_coefficients, compiled in the caller's, baseline, translation
/// unit), which uses libm. Each branch is evaluated only when a lane needs it, on benign inputs in the other
/// lanes (no spurious overflow or invalid operation where floating-point traps are on).
///
/// Each scalar expression is written in the order in which Eigen 3.4 evaluates the single-body code on x86-64
/// with SSE2 and no FMA contraction (as in batch_lgvi_kernel.hpp: 3-term dots ((x₀ + x₁) + x₂), R·(F − I) rows
/// 0 and 1 ((p₀ + p₁) + p₂) and row 2 p₀ + (p₁ + p₂), cross products (a₁b₂ − a₂b₁, a₂b₀ − a₀b₂, a₀b₁ − a₁b₀),
/// sums u += c U starting from an exact 0, which turns −0 into +0). tests/integrators/test_batch.cpp checks the
/// outcome bit for bit against the single-body stepper.
///
/// RKMK4 is explicit: a lane fails only when its new state is not finite (status non_finite). It is then written
/// out with its last good state and replaced by a benign body (R = I, Ω = 0, b = 0), so it neither slows nor
/// disturbs the other lanes.
///
/// Self-contained on purpose, like batch_lgvi_kernel.hpp (no Eigen, no standard-library functions; core/trig.hpp
/// is templates and constants only, instantiated here on this ISA's lane types): integrators/batch_avx2.cpp and
/// batch_avx512.cpp compile this header for AVX2 and AVX-512 in their own namespaces.
#pragma once

#include "../core/trig.hpp"

#include "batch_lanes.hpp"

#include <cstddef>
#include <cstdint>

namespace lgi::batch_kernel {

/// What every body of the batch shares: the diagonal of J and of `Inertia<double>`::J_inv, the heavy top's k, z0
/// and default b, the tableau's non-zero entries (batch_rkmk.hpp checks the tableau's pattern), and the scalar
/// exp_coefficients for lanes the polynomials do not cover.
struct Rkmk4Params {
  double J[3], J_inv[3];
  double k[3], z0[3];
  double b;
  double a10, a21, a32;
  double b0, b1, b2, b3;
  void (*exp_coefficients)(const double* w, double* AB);  ///< AB = (A, B) of so3::exp_coefficients(w)
};

using Rkmk4IO = BatchIO;  ///< batch_lanes.hpp

}  // namespace lgi::batch_kernel


namespace lgi::batch_kernel::LGI_BATCH_ISA {

/// Every lane set to v.
template <int U>
[[gnu::always_inline]] inline Pack<MV, U> splat(double v) {
  Pack<MV, U> r;
  for (int u = 0; u < U; ++u) r.x[u] = MV{} + v;
  return r;
}

/// Horner as so3::detail::horner: r = c[N−1]; r = r x + c[k].
template <int U, int N>
[[gnu::always_inline]] inline Pack<MV, U> horner_from_top(const Pack<MV, U>& x, const double (&c)[N]) {
  Pack<MV, U> r = x * c[N - 1] + c[N - 2];
  for (int k = N - 3; k >= 0; --k) r = r * x + c[k];
  return r;
}

/// trig::sin_0_pi on lanes x ∈ [0, π]: both pieces' kernels, then a blend (each lane gets the operations of the
/// scalar branch it would take).
template <int U>
[[gnu::always_inline]] inline Pack<MV, U> sin_0_pi(const Pack<MV, U>& x) {
  using V = Pack<MV, U>;
  const Pack<MI, U> low = x <= trig::pio4, mid = ~low & (x <= trig::three_pio4);
  V rs, ys;
  select(rs, low, x, V(trig::pi_hi - x));
  select(ys, low, splat<U>(0.0), splat<U>(trig::pi_lo));
  const V s = trig::sin_kernel(rs, ys);
  const V c = trig::cos_kernel(V(x - trig::pio2_hi), -trig::pio2_lo);
  V r;
  select(r, mid, c, s);
  return r;
}

/// (A, B) of so3::exp_coefficients(w) lane by lane (see the header).
template <int U>
[[gnu::always_inline]] inline void exp_coefficients(const Rkmk4Params& p, const Pack<MV, U>& w0, const Pack<MV, U>& w1,
                                                    const Pack<MV, U>& w2, Pack<MV, U>& A, Pack<MV, U>& B) {
  using V = Pack<MV, U>;
  using I = Pack<MI, U>;
  constexpr int all = (1 << (U * VW)) - 1;
  const V t2 = (w0 * w0 + w1 * w1) + w2 * w2;
  const I small = t2 < trig::exp_taylor_theta2;
  const int small_bits = bits(small);
  if (small_bits == all) [[likely]] {
    A = horner_from_top(t2, trig::exp_taylor_A);
    B = horner_from_top(t2, trig::exp_taylor_B);
    return;
  }
  const V one = splat<U>(1.0);
  if (small_bits != 0) {
    V x;
    select(x, small, t2, V{});
    A = horner_from_top(x, trig::exp_taylor_A);
    B = horner_from_top(x, trig::exp_taylor_B);
  }
  V theta2;
  select(theta2, small, one, t2);
  const I series = ~small & (t2 < trig::exp_series_theta2);
  const int series_bits = bits(series);
  if (series_bits != 0) {
    V x;
    select(x, series, t2, one);
    const V Bs = horner_from_top(x, trig::exp_series_B);
    select(A, series, V(sqrt(V(Bs * V(2.0 - x * Bs)))), A);
    select(B, series, Bs, B);
    if ((small_bits | series_bits) == all) return;
  }
  const V theta = sqrt(theta2);
  const I poly = ~(small | series) & (theta <= trig::max_argument);  // false for NaN
  if (bits(poly) != 0) {
    V x;
    select(x, poly, theta, one);
    const V s = sin_0_pi(V(x / 2.0)) / x;
    select(A, poly, V(sin_0_pi(x) / x), A);
    select(B, poly, V(2.0 * s * s), B);
  }
  const int rest = ~(small_bits | series_bits | bits(poly)) & all;
  if (rest != 0) [[unlikely]] {
    for (int l = 0; l < U * VW; ++l)
      if (rest >> l & 1) {
        const double w[3] = {lane(w0, l), lane(w1, l), lane(w2, l)};
        double AB[2];
        p.exp_coefficients(w, AB);
        set_lane(A, l, AB[0]);
        set_lane(B, l, AB[1]);
      }
  }
}

/// One block of W lanes, bodies first … first + W − 1 (lanes past io.n are benign padding), n_steps steps.
template <int W, bool Torque>
void rkmk4_block(const Rkmk4Params& p, const Rkmk4IO& io, std::size_t first, double h, std::int64_t n_steps) {
  static_assert(W % VW == 0, "lane block width: a multiple of the machine vector's");
  constexpr int U = W / VW;
  using V = Pack<MV, U>;
  using I = Pack<MI, U>;

  // (R, Ω) of the lanes in two buffers, S[cur] the current state (as in batch_lgvi_kernel.hpp).
  V S[2][12], b;  // R(r, c) at [3r + c], Ω at [9 + j]
  int cur = 0;
  bool live[W];
  const int all_lanes = (1 << W) - 1;
  const double J0 = p.J[0], J1 = p.J[1], J2 = p.J[2];
  const double iJ0 = p.J_inv[0], iJ1 = p.J_inv[1], iJ2 = p.J_inv[2];
  const double k0 = p.k[0], k1 = p.k[1], k2 = p.k[2], z0 = p.z0[0], z1 = p.z0[1], z2 = p.z0[2];

  const auto benign = [&](int l) {
    for (int e = 0; e < 12; ++e) set_lane(S[cur][e], l, (e < 9 && e % 4 == 0) ? 1.0 : 0.0);
    set_lane(b, l, 0.0);
    live[l] = false;
  };
  const auto write_out = [&](int l, std::uint8_t status, std::int64_t steps) {
    const std::size_t i = first + static_cast<std::size_t>(l);
    for (int e = 0; e < 9; ++e) io.R[e][i] = lane(S[cur][e], l);
    for (int j = 0; j < 3; ++j) io.Omega[j][i] = lane(S[cur][9 + j], l);
    io.status[i] = status;
    io.steps[i] = steps;
  };
  // V = J⁻¹((JW) × W + M), M = b Γ × z0 (Torque) — Rkmk::acceleration with HeavyTop::reduced_torque.
  const auto acceleration = [&](const V* Wv, const V* G, V* out) {
    const V a0 = J0 * Wv[0], a1 = J1 * Wv[1], a2 = J2 * Wv[2];
    V x0 = a1 * Wv[2] - a2 * Wv[1];
    V x1 = a2 * Wv[0] - a0 * Wv[2];
    V x2 = a0 * Wv[1] - a1 * Wv[0];
    if constexpr (Torque) {
      x0 = x0 + b * (G[1] * z2 - G[2] * z1);
      x1 = x1 + b * (G[2] * z0 - G[0] * z2);
      x2 = x2 + b * (G[0] * z1 - G[1] * z0);
    } else {
      (void)G;
    }
    out[0] = iJ0 * x0;
    out[1] = iJ1 * x1;
    out[2] = iJ2 * x2;
  };
  const auto cross = [](const V* a, const V* c, V* out) {
    out[0] = a[1] * c[2] - a[2] * c[1];
    out[1] = a[2] * c[0] - a[0] * c[2];
    out[2] = a[0] * c[1] - a[1] * c[0];
  };

  int alive = 0;
  for (int l = 0; l < W; ++l) {
    const std::size_t i = first + static_cast<std::size_t>(l);
    if (i >= io.n) {
      benign(l);
      continue;
    }
    for (int e = 0; e < 9; ++e) set_lane(S[cur][e], l, io.R[e][i]);
    for (int j = 0; j < 3; ++j) set_lane(S[cur][9 + j], l, io.Omega[j][i]);
    set_lane(b, l, io.b ? io.b[i] : p.b);
    live[l] = true;
    ++alive;
  }

  const double a_stage[3] = {p.a10, p.a21, p.a32};
  for (std::int64_t n = 0; n < n_steps && alive > 0; ++n) {
    V* const R = S[cur];
    const V* const Om = R + 9;
    V* const q = S[cur ^ 1];
    V G[3]{};  // Γ = Rᵀk (zero and never read without Torque)
    if constexpr (Torque) {
      G[0] = (R[0] * k0 + R[3] * k1) + R[6] * k2;
      G[1] = (R[1] * k0 + R[4] * k1) + R[7] * k2;
      G[2] = (R[2] * k0 + R[5] * k1) + R[8] * k2;
    }
    V Us[4][3], Vs[4][3];
    for (int j = 0; j < 3; ++j) Us[0][j] = Om[j];
    acceleration(Om, G, Vs[0]);
    for (int i = 1; i < 4; ++i) {
      const double a = a_stage[i - 1];
      V u[3], Wv[3], w[3];
      for (int j = 0; j < 3; ++j) {
        u[j] = (0.0 + a * Us[i - 1][j]) * h;
        Wv[j] = Om[j] + h * (0.0 + a * Vs[i - 1][j]);
      }
      // U_i = J_r⁻¹ series: r = W; w = u × W; r += ½ w; w = u × w; r += (1/12) w
      cross(u, Wv, w);
      V r[3];
      for (int j = 0; j < 3; ++j) r[j] = Wv[j] + 0.5 * w[j];
      V w2[3];
      cross(u, w, w2);
      for (int j = 0; j < 3; ++j) Us[i][j] = r[j] + (1.0 / 12) * w2[j];
      if constexpr (Torque) {
        V A, B;
        exp_coefficients(p, u[0], u[1], u[2], A, B);
        const V nA = -A;
        V wv[3], cw[3], Gi[3];
        cross(u, G, wv);
        cross(u, wv, cw);
        for (int j = 0; j < 3; ++j) Gi[j] = (G[j] + nA * wv[j]) + B * cw[j];
        acceleration(Wv, Gi, Vs[i]);
      } else {
        acceleration(Wv, G, Vs[i]);
      }
    }
    // Update: weighted sums from an exact 0, then R + R (exp(hu) − I), Ω + h dΩ.
    V hu[3], dO[3];
    for (int j = 0; j < 3; ++j) {
      const V su = (((0.0 + p.b0 * Us[0][j]) + p.b1 * Us[1][j]) + p.b2 * Us[2][j]) + p.b3 * Us[3][j];
      dO[j] = (((0.0 + p.b0 * Vs[0][j]) + p.b1 * Vs[1][j]) + p.b2 * Vs[2][j]) + p.b3 * Vs[3][j];
      hu[j] = h * su;
    }
    V A, B;
    exp_coefficients(p, hu[0], hu[1], hu[2], A, B);
    // so3::rodrigues_increment(hu, A, B)
    const V bx = B * hu[0], by = B * hu[1], bz = B * hu[2];
    const V bxx = bx * hu[0], byy = by * hu[1], bzz = bz * hu[2];
    const V bxy = bx * hu[1], bxz = bx * hu[2], byz = by * hu[2];
    const V ax = A * hu[0], ay = A * hu[1], az = A * hu[2];
    const V D00 = -(byy + bzz), D01 = bxy - az, D02 = bxz + ay;
    const V D10 = bxy + az, D11 = -(bxx + bzz), D12 = byz - ax;
    const V D20 = bxz - ay, D21 = byz + ax, D22 = -(bxx + byy);
    for (int i = 0; i < 2; ++i) {
      const V a0 = R[3 * i], a1 = R[3 * i + 1], a2 = R[3 * i + 2];
      q[3 * i + 0] = R[3 * i + 0] + ((a0 * D00 + a1 * D10) + a2 * D20);
      q[3 * i + 1] = R[3 * i + 1] + ((a0 * D01 + a1 * D11) + a2 * D21);
      q[3 * i + 2] = R[3 * i + 2] + ((a0 * D02 + a1 * D12) + a2 * D22);
    }
    q[6] = R[6] + (R[6] * D00 + (R[7] * D10 + R[8] * D20));
    q[7] = R[7] + (R[6] * D01 + (R[7] * D11 + R[8] * D21));
    q[8] = R[8] + (R[6] * D02 + (R[7] * D12 + R[8] * D22));
    for (int j = 0; j < 3; ++j) q[9 + j] = Om[j] + h * dO[j];
    // All finite (commit): x − x is 0 for finite x and NaN for ±∞ and NaN, and a sum of zeros is 0.
    V zero = (q[0] - q[0]) + (q[1] - q[1]);
    for (int e = 2; e < 12; ++e) zero = zero + (q[e] - q[e]);
    const I ok = zero == zero;
    if (bits(ok) == all_lanes) [[likely]] {
      cur ^= 1;
    } else {  // failing lanes keep their state
      for (int e = 0; e < 12; ++e) select(q[e], ok, q[e], R[e]);
      cur ^= 1;
      for (int l = 0; l < W; ++l)
        if (live[l] && lane(ok, l) == 0) {
          write_out(l, status_non_finite, n);
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
void rkmk4_blocks(const Rkmk4Params& p, const Rkmk4IO& io, std::size_t block_begin, std::size_t block_end, double h,
                  std::int64_t n_steps) {
  for (std::size_t k = block_begin; k < block_end; ++k) rkmk4_block<W, Torque>(p, io, k * W, h, n_steps);
}

}  // namespace lgi::batch_kernel::LGI_BATCH_ISA
