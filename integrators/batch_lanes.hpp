/// \file
/// lgi/integrators/batch_lanes.hpp — lanes for the batched kernels (batch_lgvi_kernel.hpp, batch_rkmk_kernel.hpp).
///
/// GCC vector extensions (element-wise IEEE operations, no FMA contraction when the translation unit is compiled
/// with -ffp-contract=off): a machine vector MV holds VW doubles — 2 with SSE2 (the x86-64 baseline), 4 when the
/// translation unit is compiled with AVX (integrators/batch_avx2.cpp), 8 with AVX-512F
/// (integrators/batch_avx512.cpp) — and a lane block of W = U·VW bodies is a Pack of U of them. MI holds
/// comparison masks (−1 true, 0 false). Masks are blended with bit operations: generic vectors wider than the
/// machine's are lowered to scalar code for ?: and comparisons, hence blocks are whole machine vectors.
///
/// Self-contained on purpose (no Eigen, no standard-library functions): every function here lives in the
/// namespace named by LGI_BATCH_ISA (baseline, avx2, avx512), one per translation unit, so no inline function
/// compiled for a wider instruction set can be merged by the linker into code that runs on the baseline one.
/// Limits: GCC (or Clang) only — vector extensions, x86 builtins and __builtin_bit_cast.
#pragma once

#include <cstddef>
#include <cstdint>

namespace lgi::batch_kernel {
/// Status codes written per body; equal to lgi::StepStatus (batch_kernels.hpp static_asserts it).
inline constexpr std::uint8_t status_ok = 0, status_not_converged = 1, status_non_finite = 2;

/// A batch in structure-of-arrays form, as every kernel reads and writes it. R[3r + c][i] is R(r, c) of body
/// i; Omega is read at the start and written at the end. status and steps receive the outcome per body; b is the
/// per-body b = m g ℓ, or nullptr (then the kernel's parameters' b).
struct BatchIO {
  double* R[9];
  double* Omega[3];
  std::uint8_t* status;
  std::int64_t* steps;
  const double* b;
  std::size_t n;
};
}  // namespace lgi::batch_kernel

#ifndef LGI_BATCH_ISA
#define LGI_BATCH_ISA baseline
#endif

namespace lgi::batch_kernel::LGI_BATCH_ISA {

#if defined(__AVX512F__)
typedef double MV __attribute__((vector_size(64)));
typedef long MI __attribute__((vector_size(64)));
typedef long long MQ __attribute__((vector_size(64)));
/// vptestmq (AVX-512F): bit l set where lane l of the mask is non-zero.
inline int movemask(const MI& m) {
  return __builtin_ia32_ptestmq512(__builtin_bit_cast(MQ, m), __builtin_bit_cast(MQ, m), 0xff);
}
inline MV sqrt(const MV& a) { return __builtin_ia32_sqrtpd512_mask(a, a, static_cast<unsigned char>(0xff), 4); }  // 4: current rounding mode
#elif defined(__AVX__)
typedef double MV __attribute__((vector_size(32)));
typedef long MI __attribute__((vector_size(32)));
inline int movemask(const MI& m) { return __builtin_ia32_movmskpd256(__builtin_bit_cast(MV, m)); }
inline MV sqrt(const MV& a) { return __builtin_ia32_sqrtpd256(a); }
#else
typedef double MV __attribute__((vector_size(16)));
typedef long MI __attribute__((vector_size(16)));
#if defined(__SSE2__)
inline int movemask(const MI& m) { return __builtin_ia32_movmskpd(__builtin_bit_cast(MV, m)); }
inline MV sqrt(const MV& a) { return __builtin_ia32_sqrtpd(a); }
#else
inline int movemask(const MI& m) { return (m[0] != 0) | (m[1] != 0) << 1; }
inline MV sqrt(const MV& a) { return MV{__builtin_sqrt(a[0]), __builtin_sqrt(a[1])}; }
#endif
#endif
inline constexpr int VW = static_cast<int>(sizeof(MV) / sizeof(double));

template <class M, int U>
struct Pack {
  M x[U];
};
#define LGI_PACK_BINARY(op)                                                              \
  template <class M, int U>                                                              \
  [[gnu::always_inline]] inline Pack<M, U> operator op(const Pack<M, U>& a, const Pack<M, U>& b) { \
    Pack<M, U> r;                                                                        \
    for (int u = 0; u < U; ++u) r.x[u] = a.x[u] op b.x[u];                               \
    return r;                                                                            \
  }                                                                                      \
  template <class M, int U>                                                              \
  [[gnu::always_inline]] inline Pack<M, U> operator op(double a, const Pack<M, U>& b) {  \
    Pack<M, U> r;                                                                        \
    for (int u = 0; u < U; ++u) r.x[u] = a op b.x[u];                                    \
    return r;                                                                            \
  }                                                                                      \
  template <class M, int U>                                                              \
  [[gnu::always_inline]] inline Pack<M, U> operator op(const Pack<M, U>& a, double b) {  \
    Pack<M, U> r;                                                                        \
    for (int u = 0; u < U; ++u) r.x[u] = a.x[u] op b;                                    \
    return r;                                                                            \
  }
LGI_PACK_BINARY(+)
LGI_PACK_BINARY(-)
LGI_PACK_BINARY(*)
LGI_PACK_BINARY(/)
#undef LGI_PACK_BINARY
#define LGI_PACK_COMPARE(op)                                                                      \
  template <int U>                                                                                \
  [[gnu::always_inline]] inline Pack<MI, U> operator op(const Pack<MV, U>& a, const Pack<MV, U>& b) { \
    Pack<MI, U> r;                                                                                \
    for (int u = 0; u < U; ++u) r.x[u] = a.x[u] op b.x[u];                                        \
    return r;                                                                                     \
  }                                                                                               \
  template <int U>                                                                                \
  [[gnu::always_inline]] inline Pack<MI, U> operator op(const Pack<MV, U>& a, double b) {         \
    Pack<MI, U> r;                                                                                \
    for (int u = 0; u < U; ++u) r.x[u] = a.x[u] op b;                                             \
    return r;                                                                                     \
  }
LGI_PACK_COMPARE(<)
LGI_PACK_COMPARE(<=)
LGI_PACK_COMPARE(==)
#undef LGI_PACK_COMPARE
#define LGI_PACK_BITWISE(op)                                                                      \
  template <int U>                                                                                \
  [[gnu::always_inline]] inline Pack<MI, U> operator op(const Pack<MI, U>& a, const Pack<MI, U>& b) { \
    Pack<MI, U> r;                                                                                \
    for (int u = 0; u < U; ++u) r.x[u] = a.x[u] op b.x[u];                                        \
    return r;                                                                                     \
  }
LGI_PACK_BITWISE(&)
LGI_PACK_BITWISE(|)
#undef LGI_PACK_BITWISE
template <int U>
[[gnu::always_inline]] inline Pack<MV, U> operator-(const Pack<MV, U>& a) {
  Pack<MV, U> r;
  for (int u = 0; u < U; ++u) r.x[u] = -a.x[u];
  return r;
}
template <int U>
[[gnu::always_inline]] inline Pack<MI, U> operator~(const Pack<MI, U>& a) {
  Pack<MI, U> r;
  for (int u = 0; u < U; ++u) r.x[u] = ~a.x[u];
  return r;
}
/// out = mask ? a : b lane by lane, as bit operations.
template <int U>
[[gnu::always_inline]] inline void select(Pack<MV, U>& out, const Pack<MI, U>& mask, const Pack<MV, U>& a,
                                          const Pack<MV, U>& b) {
  for (int u = 0; u < U; ++u)
    out.x[u] = __builtin_bit_cast(MV, (mask.x[u] & __builtin_bit_cast(MI, a.x[u])) | (~mask.x[u] & __builtin_bit_cast(MI, b.x[u])));
}
/// |a| (clears the sign bit, as fabs).
template <int U>
[[gnu::always_inline]] inline Pack<MV, U> abs(const Pack<MV, U>& a) {
  Pack<MV, U> r;
  for (int u = 0; u < U; ++u) r.x[u] = __builtin_bit_cast(MV, __builtin_bit_cast(MI, a.x[u]) & (MI{} + 0x7fffffffffffffffL));
  return r;
}
/// √a lane by lane (vsqrtpd: correctly rounded, as std::sqrt).
template <int U>
[[gnu::always_inline]] inline Pack<MV, U> sqrt(const Pack<MV, U>& a) {
  Pack<MV, U> r;
  for (int u = 0; u < U; ++u) r.x[u] = sqrt(a.x[u]);
  return r;
}
template <int U>
[[gnu::always_inline]] inline Pack<MI, U> all_true() {
  Pack<MI, U> r;
  for (int u = 0; u < U; ++u) r.x[u] = MI{} - 1;
  return r;
}
/// Bit l set where lane l of the mask is true.
template <int U>
[[gnu::always_inline]] inline int bits(const Pack<MI, U>& m) {
  int r = 0;
  for (int u = 0; u < U; ++u) r |= movemask(m.x[u]) << (u * VW);
  return r;
}
template <class M, int U>
[[gnu::always_inline]] inline auto lane(const Pack<M, U>& a, int l) {
  return a.x[l / VW][l % VW];
}
template <class M, int U, class T>
[[gnu::always_inline]] inline void set_lane(Pack<M, U>& a, int l, T v) {
  a.x[l / VW][l % VW] = v;
}

}  // namespace lgi::batch_kernel::LGI_BATCH_ISA
