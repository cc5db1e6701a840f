/// \file
/// lgi/core/trig.hpp — a deterministic polynomial sin and cos on [0, π], written with + − × only.
///
/// Why: libm's sin is a scalar call that no compiler vectorises bit-identically (GCC fuses sin and cos into a
/// scalar sincos), so a kernel that steps many bodies at once in vector lanes (integrators/batch_rkmk.hpp)
/// could not reproduce a single-body exp. Written here once as + − × on doubles, the same operations give the
/// same bits in a scalar, a Jet's value part and a vector lane: core/so3.hpp's exp_coefficients uses sin_0_pi
/// for rotation angles √2 ≤ θ ≤ π (A = sin θ/θ, B = 2 (sin(θ/2)/θ)², the formulas it used with libm) and the
/// series exp_series_B below, and the batch kernels evaluate the same kernels, reduction and series on their lane
/// types.
///
/// ~~~{.unparsed}
///   sin_kernel(x, y) = sin(x + y) = x + x³ P(x²) + y (1 − x²/2),  cos_kernel(x, y) = 1 − x²/2 + x⁴ Q(x²) − x y
///   for |x + y| ≤ π/4, the reduced argument carried as two doubles (fdlibm's k_sin.c and k_cos.c, FreeBSD msun)
///     P, Q: Chebyshev approximations of degree 6 and 5 in r² on [0, 1.0001 (π/4)²] (mpmath.chebyfit at 200 bits),
///     rounded to double; relative error of P 5.7e-17 and of Q 5.8e-17 with the rounded coefficients (exactly
///     evaluated over 4001 points), i.e. < 0.06 ulp of sin and < 0.002 ulp of cos. Evaluated as fdlibm does, so
///     that the final sum adds small corrections to the exact leading term (about ½ ulp plus their error).
///   sin_0_pi(x), x ∈ [0, π] (fdlibm's reduction by quadrant, here only three pieces, with a two-double π):
///     x ≤ π/4:        sin_kernel(x, 0)
///     x ≤ 3π/4:       cos_kernel(x − (π/2)_hi, −(π/2)_lo)        the heads are exact differences (Sterbenz)
///     otherwise:      sin_kernel(π_hi − x, π_lo)
///   cos_0_pi(x) likewise.
/// ~~~
///
/// Accuracy, checked against long double over 10⁶ + 1 evenly spaced points (tests/core/test_so3.cpp,
/// TrigPolynomial*): sin_0_pi < 0.8 ulp and cos_0_pi < 0.9 ulp on [0, π]; exp's coefficients on θ ∈ [√2, π]
/// with this sin: A = sin θ/θ < 1.5 ulp, B = 2 (sin(θ/2)/θ)² < 3.4 ulp (B's formula squares, so doubles, the
/// error of sin(θ/2)/θ); on [0.1, √2) by the series: A < 1.5 ulp, B < 0.9 ulp. The measured figures, and glibc's
/// for comparison: docs/findings.md.
///
/// Scalars: any T with T·double, T + double, double − T, T·T (double, ceres::Jet, the batch kernels' lane
/// packs). Branches read the value part of a Jet. The coefficients are doubles, so the result is only
/// double-accurate: so3::exp_coefficients uses it for double-valued scalars alone (long double keeps sinl).
/// Only templates and constant data here, nothing else, and no includes: the batch kernels' translation units
/// compiled for AVX2/AVX-512 include this header, and an inline non-template function compiled there could be
/// merged by the linker into baseline code. They instantiate the kernels on their own lane types (distinct symbols
/// per instruction set) and never on double.
#pragma once

/// The deterministic polynomial sin and cos on [0, π] of this header, and their constants.
namespace lgi::trig {

/// sin r = r + r³ Σ sin_coefficients[k] r^(2k), |r| ≤ π/4.
inline constexpr double sin_coefficients[7] = {-0x1.5555555555555p-3, 0x1.1111111111110p-7,  -0x1.a01a01a019937p-13,
                                               0x1.71de3a54607a5p-19, -0x1.ae64541295cdfp-26, 0x1.61217ee5cca1bp-33,
                                               -0x1.ab17bdcbd3414p-41};
/// The same without the first coefficient (fdlibm's R in S1 + z R).
inline constexpr double sin_tail[6] = {0x1.1111111111110p-7,  -0x1.a01a01a019937p-13, 0x1.71de3a54607a5p-19,
                                       -0x1.ae64541295cdfp-26, 0x1.61217ee5cca1bp-33, -0x1.ab17bdcbd3414p-41};
/// cos r = 1 − r²/2 + r⁴ Σ cos_coefficients[k] r^(2k), |r| ≤ π/4.
inline constexpr double cos_coefficients[6] = {0x1.5555555555555p-5,   -0x1.6c16c16c16967p-10, 0x1.a01a019f4e9b4p-16,
                                               -0x1.27e4fa17bf139p-22, 0x1.1eeb68cd22f56p-29,  -0x1.907d8f29fe831p-37};

///@{
/// π/4, 3π/4 (the pieces' bounds: any doubles near them would do, both sides use these), and π and π/2 as
/// two doubles each (_hi rounded to nearest, _lo the rest to 2⁻¹⁰⁷).
inline constexpr double pio4 = 0x1.921fb54442d18p-1, three_pio4 = 0x1.2d97c7f3321d2p+1;
inline constexpr double pio2_hi = 0x1.921fb54442d18p+0, pio2_lo = 0x1.1a62633145c07p-54;
inline constexpr double pi_hi = 0x1.921fb54442d18p+1, pi_lo = 0x1.1a62633145c07p-53;
///@}

/// The largest argument of sin_0_pi and cos_0_pi: π rounded down to double (= pi_hi).
inline constexpr double max_argument = pi_hi;

///@{
/// exp's coefficients A = sin θ/θ and B = (1 − cos θ)/θ² below θ² = exp_taylor_theta2 (core/so3.hpp): their
/// Taylor polynomials in θ², exact to < 1e-18 relative there. Here so that the batch kernels use the same data.
inline constexpr double exp_taylor_theta2 = 1e-2;
inline constexpr double exp_taylor_A[6] = {1.0, -1.0 / 6, 1.0 / 120, -1.0 / 5040, 1.0 / 362880, -1.0 / 39916800};
inline constexpr double exp_taylor_B[6] = {0.5,           -1.0 / 24,     1.0 / 720,
                                           -1.0 / 40320, 1.0 / 3628800, -1.0 / 479001600};
///@}

///@{
/// exp's coefficient B = (1 − cos θ)/θ² = Σ_k (−1)^k θ^(2k)/(2k + 2)! for exp_taylor_theta2 ≤ θ² < exp_series_theta2
/// (core/so3.hpp): its Taylor polynomial to θ¹⁸, whose remainder is < 2⁻⁵⁸ B there; A follows from B as
/// √(B (2 − θ² B)) (= sin θ/θ, since B (2 − θ² B) = (1 − cos θ)(1 + cos θ)/θ²).
inline constexpr double exp_series_theta2 = 2;
inline constexpr double exp_series_B[10] = {
    1.0 / 2,         -1.0 / 24,          1.0 / 720,           -1.0 / 40320,           1.0 / 3628800,
    -1.0 / 479001600, 1.0 / 87178291200, -1.0 / 20922789888000, 1.0 / 6402373705728000, -1.0 / 2432902008176640000};
///@}

namespace detail {
template <class T>
constexpr double value(const T& x) {
  if constexpr (requires { x.a; })
    return value(x.a);  // ceres::Jet
  else
    return static_cast<double>(x);
}
}  // namespace detail

/// Horner: c[0] + c[1] z + … + c[N−1] z^(N−1), from the top (r = c[N−1] z + c[N−2], r = r z + c[k]).
template <class T, int N>
T horner(const T& z, const double (&c)[N]) {
  static_assert(N >= 2);
  T r = z * c[N - 1] + c[N - 2];
  for (int k = N - 3; k >= 0; --k) r = r * z + c[k];
  return r;
}

/// sin(x + y) for |x + y| ≤ π/4, x + y a reduced argument carried as two doubles (y = 0 when x is exact):
/// fdlibm's k_sin, x − ((z (y/2 − v R) − y) − v S1) with z = x², v = z x, P = S1 + z R.
template <class T, class Y>
T sin_kernel(const T& x, const Y& y) {
  const T z = x * x;
  const T v = z * x;
  const T r = horner(z, sin_tail);
  return x - ((z * (0.5 * y - v * r) - y) - v * sin_coefficients[0]);
}

/// cos(x + y) for |x + y| ≤ π/4: fdlibm's k_cos, w + (((1 − w) − hz) + (z² Q − x y)) with z = x², hz = z/2,
/// w = 1 − hz (1 − hz's rounding error is added back).
template <class T, class Y>
T cos_kernel(const T& x, const Y& y) {
  const T z = x * x;
  const T hz = z * 0.5;
  const T w = 1.0 - hz;
  return w + (((1.0 - w) - hz) + ((z * z) * horner(z, cos_coefficients) - x * y));
}

/// sin x for x ∈ [0, π] (x ≤ max_argument). The reduced arguments x − π/2 = (x − (π/2)_hi) − (π/2)_lo and
/// π − x = (π_hi − x) + π_lo go to the kernels as (head, tail); the heads are exact differences (Sterbenz).
template <class T>
T sin_0_pi(const T& x) {
  const double v = detail::value(x);
  if (v <= pio4) return sin_kernel(x, 0.0);
  if (v <= three_pio4) return cos_kernel(T(x - pio2_hi), -pio2_lo);
  return sin_kernel(T(pi_hi - x), pi_lo);
}

/// cos x for x ∈ [0, π] (x ≤ max_argument).
template <class T>
T cos_0_pi(const T& x) {
  const double v = detail::value(x);
  if (v <= pio4) return cos_kernel(x, 0.0);
  if (v <= three_pio4) return -sin_kernel(T(x - pio2_hi), -pio2_lo);
  return -cos_kernel(T(pi_hi - x), pi_lo);
}

}  // namespace lgi::trig
