// Observed orders in the asymptotic regime, beyond double: the RKMK methods whose h^(p+1) error term
// outweighs the h^p term down to the round-off floor of double and long double (tests/integrators/test_rkmk_family.cpp:
// rkmk_vern9_cayley 9.46 on the skew top and 10.0 on the GNI body, rkmk_dp8_cayley 8.23 on the GNI body, rkmk_vern9
// above 9 with its series kept to ad⁸) run in
// binary128 (boost::multiprecision::float128) or, where even that is too shallow, in 50 digits (Boost's
// cpp_bin_float), with coefficients parsed from the source's decimal text to that precision
// (tableaus::verner9_in<C>, dop853_in<C>), against an independent reference in the same precision
// (Gragg–Bulirsch–Stoer on the embedding, tests/quad_measure.hpp), at steps small enough that the leading term
// dominates; the fit is that of tests/order_measure.hpp (least-squares slope of log error against log h, every
// error > 100× the reference's). Measured (Release, the whole file 6.1 s on one core, 5.0 s of it the 50-digit
// test):
//
//   rkmk_vern9_cayley, skew heavy top, binary128:  9.002 over errors 7.8e-21 … 1.5e-29 (local slopes 9.01 → 9.00,
//                                                  e/h⁹ → 6.92e-7), reference 1.1e-32
//   rkmk_vern9_cayley, GNI free body, 50 digits:   9.096 over errors 3.7e-27 … 7.2e-37 (local slopes 9.30 → 9.02,
//                                                  e/h⁹ 3.70e-9 → 2.84e-9), reference 5.0e-46
//     the same in binary128 (a finding):           9.53 over 8.8e-21 … 4.3e-29 — the terms beyond h⁹ are large
//                                                  (e/h⁹ twice its limit at h = 0.024, 15 % above it at 0.006),
//                                                  and binary128 runs out (reference 8.3e-32) while the local
//                                                  slope is still 9.2
//   rkmk_vern9, skew heavy top, binary128:         9.014 over errors 6.2e-21 … 8.5e-29 (local slopes 9.03 → 9.00)
//   rkmk_vern9, GNI free body, binary128:          9.083 over errors 2.5e-21 … 3.0e-29 (local slopes 9.21 → 9.02)
//   rkmk_vern9, driven damped top, binary128:      9.006 over errors 2.0e-21 … 2.8e-29 (local slopes 9.02 → 9.00)
//   rkmk_dp8_cayley, GNI free body, binary128:     8.002 over 3.5e-17 … 1.1e-25
//   rkmk_dp8_cayley, skew heavy top, binary128:    8.012 over 5.1e-17 … 1.5e-25
//
// Also: the coefficients meet the order conditions to the precision they are parsed in, the two decimal parsers
// agree with each other and with libquadmath, and a control with the double literals run in binary128 shows the
// floor (1.3e-16) that hides the order in double.
#include "gyrostat_case.hpp"
#include "quad_measure.hpp"
#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/core/invariants.hpp>
#include <lgi/integrators/butcher_tableaus.hpp>
#include <lgi/integrators/composition.hpp>
#include <lgi/integrators/gyrostat.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <boost/multiprecision/cpp_int.hpp>
#include <gtest/gtest.h>
#include <quadmath.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

namespace lgi {
namespace {

using test::quad::DoubleQuad;
using test::quad::Fit;
using test::quad::Q;
using test::quad::Reference;
using test::quad::Wide;

// Coefficients in binary128 (GCC's __float128: a literal type, so the tableaus stay constexpr data) for runs in
// binary128; in DoubleQuad (all 40 of Verner's digits) for runs in 50 digits.
template <class P>
using Vern9CayleyQ = Rkmk<tableaus::verner9_in<__float128>, P, -1, LieChart::cayley>;
template <class P>
using Dop853CayleyQ = Rkmk<tableaus::dop853_in<__float128>, P, -1, LieChart::cayley>;
template <class P>
using Vern9CayleyWide = Rkmk<tableaus::verner9_in<DoubleQuad>, P, -1, LieChart::cayley>;
template <class P>
using Vern9Q = Rkmk<tableaus::verner9_in<__float128>, P>;

// The control: Verner's coefficients as the double literals (tableaus::verner9), run in binary128.
inline constexpr auto verner9_double_in_quad = test::quad::with_coefficients<__float128>(tableaus::verner9);
template <class P>
using Vern9CayleyDoubleCoefficients = Rkmk<verner9_double_in_quad, P, -1, LieChart::cayley>;

// The cases of tests/order_measure.hpp: the skew heavy top (non-diagonal J, z0 and k off the principal axes,
// T = 2) and the GNI book's free body (J = diag(2, 1, 2/3), m0 = (cos 1.1, 0, sin 1.1), T = 10). GBS macro steps
// H = 0.1 (test::quad::make_reference).
const FreeBody<double>& gni_body() {
  static const FreeBody<double> p{Vec3<double>(2.0, 1.0, 2.0 / 3).asDiagonal()};
  return p;
}
State<double> gni_state() {
  return {Mat3<double>::Identity(), gni_body().inertia.inverse() * Vec3<double>(std::cos(1.1), 0.0, std::sin(1.1))};
}
const Reference<Q>& skew_reference() {
  static const Reference<Q> r =
      test::quad::make_reference<Q>(test::skew_heavy_top(), test::skew_initial_state(), 2.0, 20);
  return r;
}
const Reference<Q>& gni_reference() {
  static const Reference<Q> r = test::quad::make_reference<Q>(gni_body(), gni_state(), 10.0, 100);
  return r;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// test::quad::observed_order over 12 points at most, with the time it took printed.
template <template <class> class Method, class T, RigidBodyProblem P>
Fit timed_order(const P& problem, const State<double>& x0, double t_end, const Reference<T>& ref, double e_start,
                double e_stop, int declared, const char* what) {
  const auto t0 = std::chrono::steady_clock::now();
  const Fit fit = test::quad::observed_order<Method>(problem, x0, t_end, ref, e_start, e_stop, 12, declared, what);
  std::printf("(%.2f s)\n", seconds_since(t0));
  return fit;
}

// ---- the coefficients -------------------------------------------------------------------------------------

// Largest residual |Σ b_i Φ_i(τ) − 1/γ(τ)| over the trees of each order (rk_order_conditions.hpp's trees):
// Verner 9(8), orders ≤ 9: 4.1e-34 parsed to binary128 (evaluated in binary128), 3.2e-40 parsed to DoubleQuad
// (evaluated in 50 digits: the 40 digits of the source), 1.3e-16 as the double literals; order 10: 1.76e-6 in
// all three (order exactly 9). DOP853, orders ≤ 8: 2.9e-29 parsed to binary128 (dop853.f's 28–30 digits); order
// 9: 2.7e-5. And each binary128 coefficient rounds to the double the compiler made of the same literal.
TEST(QuadOrder, CoefficientsMeetTheOrderConditionsToTheirPrecision) {
  const auto quad = test::quad::order_residuals<Q>(tableaus::verner9_in<__float128>, 16, 10);
  const auto wide = test::quad::order_residuals<Wide>(tableaus::verner9_in<DoubleQuad>, 16, 10);
  const auto dbl = test::quad::order_residuals<Q>(verner9_double_in_quad, 16, 10);
  const auto dop = test::quad::order_residuals<Q>(tableaus::dop853_in<__float128>, 12, 9);
  for (std::size_t k = 0; k < 10; ++k) {
    std::printf("order %2zu: largest residual, Verner 9(8): binary128 %.2e, DoubleQuad (50 digits) %.2e, double "
                "literals %.2e",
                k + 1, quad[k], wide[k], dbl[k]);
    if (k < dop.size()) std::printf("; DOP853 binary128 %.2e", dop[k]);
    std::printf("\n");
  }
  const auto largest = [](const std::vector<double>& r, std::size_t orders) {
    return *std::max_element(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(orders));
  };
  EXPECT_LT(largest(quad, 9), 1e-33);
  EXPECT_LT(largest(wide, 9), 1e-39);
  EXPECT_GT(largest(dbl, 9), 1e-17);
  for (const auto& r : {quad, wide, dbl}) EXPECT_GT(r[9], 1e-6) << "order 10 holds: not order 9 exactly";
  EXPECT_LT(largest(dop, 8), 1e-28);
  EXPECT_GT(dop[8], 1e-6) << "DOP853: order 9 holds";

  const auto& q9 = tableaus::verner9_in<__float128>;
  const auto& d9 = tableaus::verner9;
  const auto& q8 = tableaus::dop853_in<__float128>;
  const auto& d8 = tableaus::dop853;
  int differ = 0, compared = 0;
  const auto same = [&](__float128 q, double d) {
    ++compared;
    differ += static_cast<double>(q) != d;
  };
  for (std::size_t i = 0; i < 26; ++i) {
    same(q9.c[i], d9.c[i]);
    for (std::size_t j = 0; j < 26; ++j) same(q9.a[i][j], d9.a[i][j]);
    for (std::size_t m = 0; m < 9; ++m) same(q9.dense[i][m], d9.dense[i][m]);
  }
  for (std::size_t i = 0; i < 16; ++i) same(q9.e[i], d9.e[i]);
  for (std::size_t i = 0; i < 16; ++i) {
    same(q8.c[i], d8.c[i]);
    for (std::size_t j = 0; j < 16; ++j) same(q8.a[i][j], d8.a[i][j]);
  }
  for (std::size_t i = 0; i < 12; ++i) same(q8.e[i], d8.e[i]);
  std::printf("%d of %d binary128 coefficients round to a different double than the literal\n", differ, compared);
  EXPECT_EQ(differ, 0);
}

// The two parsers against each other and against libquadmath: tableaus::detail::parse_decimal (binary128, two
// roundings) is within one unit in the last place of DoubleQuad's hi (the binary128 nearest to the ≈ 2⁻²²⁰-accurate
// DoubleQuad value) for every coefficient of Verner's tableau (DOP853's tableau computes e3 and its dense weights,
// which DoubleQuad, having no arithmetic, cannot); DoubleQuad's hi equals strtoflt128 (correctly rounded) on three
// literals copied from the source, and parse_decimal is within one unit of it.
TEST(QuadOrder, DecimalParsersAgree) {
  const auto ulps = [](__float128 a, __float128 b) {
    if (a == b) return 0.0;
    int e = 0;
    frexp(Q(b), &e);
    return static_cast<double>(abs(Q(a) - Q(b)) / ldexp(Q(1), e - 113));
  };
  int exact = 0, count = 0;
  double worst = 0;
  const auto compare = [&](__float128 q, const DoubleQuad& w) {
    const double u = ulps(q, w.hi);
    worst = std::max(worst, u);
    exact += u == 0;
    ++count;
  };
  const auto& q9 = tableaus::verner9_in<__float128>;
  const auto& w9 = tableaus::verner9_in<DoubleQuad>;
  for (std::size_t i = 0; i < 26; ++i) {
    compare(q9.c[i], w9.c[i]);
    for (std::size_t j = 0; j < 26; ++j) compare(q9.a[i][j], w9.a[i][j]);
    for (std::size_t m = 0; m < 9; ++m) compare(q9.dense[i][m], w9.dense[i][m]);
  }
  for (std::size_t i = 0; i < 16; ++i) compare(q9.e[i], w9.e[i]);
  std::printf("binary128 parse against DoubleQuad: %d of %d equal, the largest difference %.2f ulp\n", exact, count,
              worst);
  EXPECT_LE(worst, 1.0);
  for (const char* text : {"0.09702435063878044594828361677100617517633", "-13.93734253810777678786523664804936051203",
                           "0.220588235294117647058823529412e-1"}) {
    const __float128 libquadmath = strtoflt128(text, nullptr);
    EXPECT_TRUE(DoubleQuad::from_decimal(text).hi == libquadmath) << text;
    EXPECT_LE(ulps(tableaus::detail::parse_decimal<__float128>(text), libquadmath), 1.0) << text;
  }
}

// ---- Verner 9(8) in Cayley coordinates --------------------------------------------------------------------

const Fit& vern9_cayley_skew_fit() {
  static const Fit fit = test::quad::observed_order<Vern9CayleyQ>(
      test::skew_heavy_top(), test::skew_initial_state(), 2.0, skew_reference(), 1e-20, 1e-28, 12, 9,
      "rkmk_vern9_cayley skew top (binary128)");
  return fit;
}

// The skew heavy top in binary128, errors 1e-20 … 1e-28: 9.002, e/h⁹ settled at 6.92e-7 (within 0.6 % over the
// window). (The long-double fit of e/h⁹ = A + B h over h = 0.13 … 0.33 had put A at 4.4e-7.)
TEST(QuadOrder, Vern9CayleyOnTheSkewHeavyTop) {
  const auto t0 = std::chrono::steady_clock::now();
  const Fit& fit = vern9_cayley_skew_fit();
  std::printf("(%.2f s)\n", seconds_since(t0));
  EXPECT_NEAR(fit.order, 9.0, 0.2);
}

// A torque that reads Ω and t (tests/test_problems.hpp: the skew top damped by −CΩ and driven by a sin(w t)), in 50
// digits. (The long-double fit of tests/integrators/test_state_torque.cpp sees 9.99, its h¹⁰ terms; in binary128
// over the skew top's window, 1e-20 … 1e-28, the local slopes rise from below, 8.60 → 8.92, e/h⁹ still growing by
// 2 % a point: a fit of 8.77. So the window here is the GNI body's, 1e-26 … 1e-36: 8.955, local slopes 8.88 → 8.98,
// e/h⁹ settling at 7.7e-7; the reference's two runs 1.4e-41 apart.)
TEST(QuadOrder, Vern9CayleyOnTheDrivenDampedTop) {
  const auto t0 = std::chrono::steady_clock::now();
  const auto p = test::driven_damped_skew_top();
  const Reference<Wide> ref = test::quad::make_reference<Wide>(p, test::skew_initial_state(), 2.0, 20);
  EXPECT_LT(ref.error, 1e-40);
  const Fit fit = test::quad::observed_order<Vern9CayleyWide>(p, test::skew_initial_state(), 2.0, ref, 1e-26, 1e-36,
                                                              12, 9, "rkmk_vern9_cayley driven damped top (50 digits)",
                                                              250);
  std::printf("(%.2f s)\n", seconds_since(t0));
  EXPECT_NEAR(fit.order, 9.0, 0.2);
}

// The GNI free body in 50 digits. The window starts at errors ≤ 1e-26, where the h⁹ term carries ≥ 3/4 of the
// error (e/h⁹ = 3.70e-9 at h = 0.01 against its limit ≈ 2.84e-9), and runs to 1e-36: 9.096, local slopes 9.30 →
// 9.02. The reference (GBS in 50 digits, two runs 5e-46 apart) and the coefficients (order conditions to 3e-40)
// stay far below; n from 1000 (the runs above the window, n = 2 … 800, are skipped: they cost 5× binary128's).
TEST(QuadOrder, Vern9CayleyOnTheGniFreeBody) {
  const auto t0 = std::chrono::steady_clock::now();
  const Reference<Wide> ref = test::quad::make_reference<Wide>(gni_body(), gni_state(), 10.0, 100);
  EXPECT_LT(ref.error, 1e-40);
  const Fit fit = test::quad::observed_order<Vern9CayleyWide>(gni_body(), gni_state(), 10.0, ref, 1e-26, 1e-36, 12, 9,
                                                              "rkmk_vern9_cayley GNI body (50 digits)", 1000);
  std::printf("(%.2f s)\n", seconds_since(t0));
  EXPECT_NEAR(fit.order, 9.0, 0.2);
  // still converging to 9 at the end of the window
  EXPECT_LT(std::log(fit.error.back() / fit.error[fit.error.size() - 2]) / std::log(fit.h.back() / fit.h[fit.h.size() - 2]),
            9.1);
}

// Finding: binary128 is too shallow for the GNI body. Over the window of the skew top (1e-20 … 1e-28) the fit is
// 9.53, local slopes 9.80 → 9.22: on the free body the terms beyond h⁹ are large against it (e/h⁹ is twice its
// limit 2.84e-9 at h = 0.024, h|Ω(0)| = 0.03, and 15 % above it at h = 0.006, the last point), and 100× the
// binary128 reference's error (8.3e-30) is reached while they still lift the slope above 9.2. The 50-digit test
// above follows it further.
TEST(QuadOrderFindings, Vern9CayleyOnTheGniFreeBodyInBinary128) {
  const auto t0 = std::chrono::steady_clock::now();
  const Fit fit = test::quad::observed_order<Vern9CayleyQ>(gni_body(), gni_state(), 10.0, gni_reference(), 1e-20,
                                                           1e-28, 12, 9, "rkmk_vern9_cayley GNI body (binary128)");
  std::printf("(%.2f s)\n", seconds_since(t0));
  EXPECT_GT(fit.order, 9.3);
  EXPECT_LT(fit.order, 9.8);
  for (std::size_t i = 1; i < fit.error.size(); ++i)  // e/h⁹ falls throughout: the excess over 9 is an h¹⁰ term
    EXPECT_LT(fit.error[i] / std::pow(fit.h[i], 9), fit.error[i - 1] / std::pow(fit.h[i - 1], 9));
}

// ---- Verner 9(8) in the exponential chart ---------------------------------------------------------------

// With the dexp⁻¹ series to ad⁸ (integrators/rkmk.hpp), in binary128 over the skew top's window. Its Bernoulli
// coefficients are formed in the scalar (core/so3.hpp): as doubles they put a floor of ≈ 1e-24 under these runs,
// below which the errors fell like h³ (a fit of 4.6 over this window).

TEST(QuadOrder, Vern9OnTheSkewHeavyTop) {
  const Fit fit = timed_order<Vern9Q>(test::skew_heavy_top(), test::skew_initial_state(), 2.0, skew_reference(), 1e-20,
                                      1e-28, 9, "rkmk_vern9 skew top (binary128)");
  EXPECT_NEAR(fit.order, 9.0, 0.2);
}

TEST(QuadOrder, Vern9OnTheGniFreeBody) {
  const Fit fit = timed_order<Vern9Q>(gni_body(), gni_state(), 10.0, gni_reference(), 1e-20, 1e-28, 9,
                                      "rkmk_vern9 GNI body (binary128)");
  EXPECT_NEAR(fit.order, 9.0, 0.2);
}

TEST(QuadOrder, Vern9OnTheDrivenDampedTop) {
  const auto p = test::driven_damped_skew_top();
  const Reference<Q> ref = test::quad::make_reference<Q>(p, test::skew_initial_state(), 2.0, 20);
  const Fit fit = timed_order<Vern9Q>(p, test::skew_initial_state(), 2.0, ref, 1e-20, 1e-28, 9,
                                      "rkmk_vern9 driven damped top (binary128)");
  EXPECT_NEAR(fit.order, 9.0, 0.2);
}

// ---- DOP853 in Cayley coordinates -------------------------------------------------------------------------

// Errors 1e-16 … 1e-25 (DOP853's 28–30-digit coefficients put a floor near 1e-28 under the GNI body's errors:
// at n = 5012 the error is 5.3e-28 against 4.4e-28 from e/h⁸; the window stops 1000× above it).
TEST(QuadOrder, Dop853CayleyOnTheGniFreeBody) {
  const Fit fit = timed_order<Dop853CayleyQ>(gni_body(), gni_state(), 10.0, gni_reference(), 1e-16, 1e-25, 8,
                                             "rkmk_dp8_cayley GNI body (binary128)");
  EXPECT_NEAR(fit.order, 8.0, 0.2);
}

TEST(QuadOrder, Dop853CayleyOnTheSkewHeavyTop) {
  const Fit fit = timed_order<Dop853CayleyQ>(test::skew_heavy_top(), test::skew_initial_state(), 2.0, skew_reference(),
                                             1e-16, 1e-25, 8, "rkmk_dp8_cayley skew top (binary128)");
  EXPECT_NEAR(fit.order, 8.0, 0.2);
}

// ---- the gyrostat --------------------------------------------------------------------------------------------

// The three-rotor gyrostat of tests/integrators/test_gyrostat.cpp (friction, a motor, gravity, damping), whose
// long-double fit of Verner 9(8) sees its h¹⁰ terms. Reference: GBS (quad_measure.hpp) on (R, m, h) in R^{9+3+6},
// R' = R hat(Ω), (m, h)' = GyrostatDynamics::forcing, Ω = GyrostatDynamics::omega — the problem's data and its
// right-hand side, nothing of the method.
using GQ = Gyrostat<Q>;
using GyrostatVern9Q = GyrostatRkmk<tableaus::verner9_in<__float128>, GQ>;
using GyrostatDop853Q = GyrostatRkmk<tableaus::dop853_in<__float128>, GQ>;
using GyrostatKahanLi8Q = Composition<compositions::kahan_li8, GyrostatLgvi, GQ>;
constexpr double gyrostat_t_end = 2.0;

// R orthogonal to binary128's precision (two Newton steps of the polar decomposition, X ← (X + X⁻ᵀ)/2, from a
// rotation of double's): with RᵀR − I ≈ 1e-16 the laboratory-frame momentum's torque R M reaches the body as
// RᵀR M, and the energy balance would carry a floor of that size.
Mat3<Q> orthonormal(Mat3<Q> X) {
  for (int i = 0; i < 2; ++i) X = (X + Mat3<Q>(X.inverse().transpose())) / Q(2);
  return X;
}
State<Q> gyrostat_start() {
  const State<double> x0 = test::gyrostat_initial_state();
  return {orthonormal(x0.R.cast<Q>()), x0.Omega.cast<Q>()};
}

GyrostatState<Q> gyrostat_gbs(int macro_steps, int k) {
  const GyrostatDynamics<Q> dyn(test::three_rotor_gyrostat().cast<Q>());
  constexpr int N = GQ::max_rotors;
  using V = Eigen::Matrix<Q, 12 + N, 1>;
  const auto f = [&](const Q& t, const V& y) {
    const Mat3<Q> R = Eigen::Map<const Mat3<Q>>(y.data());
    const Vec3<Q> m = y.template segment<3>(9);
    const Eigen::Matrix<Q, N, 1> h = y.template tail<N>();
    V d;
    Eigen::Map<Mat3<Q>>(d.data()) = R * so3::hat(dyn.omega(R, m, h));
    d.template tail<3 + N>() = dyn.forcing(t, R, m, h);
    return d;
  };
  const State<Q> x0 = gyrostat_start();
  const GyrostatState<Q> y0 = dyn.state(x0.R, x0.Omega);
  V y;
  Eigen::Map<Mat3<Q>>(y.data()) = y0.R;
  y.template segment<3>(9) = y0.m;
  y.template tail<N>() = y0.h;
  y = test::quad::gbs_extrapolate<Q>(f, y, gyrostat_t_end, macro_steps, k);
  GyrostatState<Q> r;
  r.R = Eigen::Map<const Mat3<Q>>(y.data());
  r.m = y.template segment<3>(9);
  r.h = y.template tail<N>();
  return r;
}

double gyrostat_distance(const GyrostatState<Q>& a, const GyrostatState<Q>& b) {
  return static_cast<double>(so3::log(Mat3<Q>(a.R.transpose() * b.R)).norm() + (a.m - b.m).norm() + (a.h - b.h).norm());
}

struct GyrostatReference {
  GyrostatState<Q> y;
  double error;
};
const GyrostatReference& gyrostat_reference() {
  static const GyrostatReference r = [] {
    const GyrostatState<Q> a = gyrostat_gbs(20, 12), b = gyrostat_gbs(40, 10);
    std::printf("gyrostat reference over T = %g: GBS (M = 20, k = 12) against (M = 40, k = 10): %.2e\n", gyrostat_t_end,
                gyrostat_distance(a, b));
    return GyrostatReference{a, gyrostat_distance(a, b)};
  }();
  return r;
}

// The LGVI's Newton tolerance at binary128's round-off (the default, 1e-14, is double's).
StepperOptions quad_newton() {
  StepperOptions o;
  o.tolerance = 1e-32;
  return o;
}

template <class S>
GyrostatState<Q> gyrostat_run(long n, std::vector<Q>* power = nullptr) {
  const GQ g = test::three_rotor_gyrostat().cast<Q>();
  S stepper(g, quad_newton());
  const GyrostatDynamics<Q> dyn(g);
  GyrostatState<Q> y = stepper.to_internal(gyrostat_start(), Q(0));
  const Q h = Q(gyrostat_t_end) / Q(n);
  if (power) power->assign(1, test::gyrostat_power(dyn, Q(0), y));
  for (long k = 0; k < n; ++k) {
    EXPECT_EQ(stepper.step(y, Q(k) * h, h), StepStatus::ok);
    if (power) power->push_back(test::gyrostat_power(dyn, Q(k + 1) * h, y));
  }
  return y;
}

// Verner 9(8) RKMK (exp chart) on the gyrostat in binary128: the window of the skew top, errors 1e-20 … 1e-28.
TEST(QuadOrder, Vern9OnTheThreeRotorGyrostat) {
  const auto t0 = std::chrono::steady_clock::now();
  const GyrostatReference& ref = gyrostat_reference();
  EXPECT_LT(ref.error, 1e-31);
  Fit fit;
  long last = 0;
  for (double n_real = 8; n_real < 1e4 && fit.h.size() < 12; n_real *= 1.25) {
    const long n = std::lround(n_real);
    if (n == last) continue;
    last = n;
    const double e = gyrostat_distance(gyrostat_run<GyrostatVern9Q>(n), ref.y);
    if (e > 1e-20) continue;
    fit.n.push_back(static_cast<int>(n));
    fit.h.push_back(gyrostat_t_end / static_cast<double>(n));
    fit.error.push_back(e);
    EXPECT_GT(e, 100 * ref.error) << "n = " << n;
    if (e < 1e-28) break;
  }
  ASSERT_GE(fit.h.size(), 6u);
  fit.order = test::fitted_order(fit.h, fit.error);
  test::quad::print(fit, 9, "rkmk_vern9 gyrostat (binary128)");
  std::printf("rkmk_vern9 gyrostat (binary128): observed order %.3f over errors %.2e ... %.2e (%.2f s)\n", fit.order,
              fit.error.front(), fit.error.back(), seconds_since(t0));
  EXPECT_NEAR(fit.order, 9.0, 0.2);
}

// ---- the energy balance of orders 8 and 9 ------------------------------------------------------------------------

// E(T) − E(0) − W, W the integral of the power of the non-conservative torques along the discrete trajectory: the
// steps' values lie on a smooth curve (the flow of the method's modified equation), so a quadrature of order q on them
// leaves a defect O(h^p) + O(h^q). The 9-point Newton–Cotes rule (q = 10) of tests/integrators/test_state_torque.cpp is
// not enough here (its h¹⁰ term outweighs the methods' own defect down to 1e-22: identical defects for Verner 9(8) and
// DOP853, slope 10.0), so W is Gregory's rule — the trapezoidal sum with end corrections from the differences at both
// ends (Hildebrand, Introduction to Numerical Analysis, 2nd ed., §5.9):
//   ∫ f = h [½ f_0 + f_1 + … + ½ f_n] − h Σ_{k=1}^{m} |G_{k+1}| (∇^k f_n + (−1)^k Δ^k f_0),  error O(h^(m+2)),
// G_j = ∫_0^1 binom(x, j) dx the Gregory coefficients (1/12, 1/24, 19/720, 3/160, … in magnitude), computed exactly in
// rationals (Boost's cpp_rational) and rounded once to binary128; m = 18: q = 20. It has interior weights 1 (no
// cancellation) and needs no step count beyond n ≥ m. Its error is estimated by its last term (the difference from
// the rule with m = 17, an upper estimate for m = 18): a point enters a fit only where that is below 1 % of the defect,
// so that the fitted slope is the method's, not the quadrature's.
constexpr int gregory_terms = 18;
const std::vector<Q>& gregory_coefficients() {  // |G_{k+1}|, k = 0 … m
  static const std::vector<Q> g = [] {
    using boost::multiprecision::cpp_rational;
    std::vector<Q> out;
    std::vector<cpp_rational> p{cpp_rational(1)};  // the coefficients of x(x − 1)…(x − j + 1)/j!, by powers of x
    for (int j = 1; j <= gregory_terms + 1; ++j) {
      std::vector<cpp_rational> next(p.size() + 1, cpp_rational(0));
      for (std::size_t i = 0; i < p.size(); ++i) {
        next[i + 1] += p[i] / j;
        next[i] -= p[i] * (j - 1) / j;
      }
      p = next;
      cpp_rational integral = 0;
      for (std::size_t i = 0; i < p.size(); ++i) integral += p[i] / static_cast<int>(i + 1);
      if (integral < 0) integral = -integral;
      out.push_back(Q(numerator(integral)) / Q(denominator(integral)));
    }
    return out;
  }();
  return g;
}
Q gregory(const std::vector<Q>& f, const Q& h, std::size_t m = gregory_terms) {
  const std::size_t n = f.size() - 1;
  EXPECT_GE(n, m);
  Q sum = (f.front() + f.back()) / Q(2);
  for (std::size_t k = 1; k < n; ++k) sum += f[k];
  std::vector<Q> forward(f.begin(), f.begin() + static_cast<std::ptrdiff_t>(m + 1)),
      backward(f.end() - static_cast<std::ptrdiff_t>(m + 1), f.end());  // Δ^k f_0 = forward[0], ∇^k f_n = backward[m]
  for (std::size_t k = 1; k <= m; ++k) {
    for (std::size_t i = 0; i + k <= m; ++i) forward[i] = forward[i + 1] - forward[i];
    for (std::size_t i = m; i >= k; --i) backward[i] = backward[i] - backward[i - 1];
    const Q correction = backward[m] + (k % 2 == 0 ? forward[0] : Q(-forward[0]));
    sum -= gregory_coefficients()[k] * correction;
  }
  return sum * h;
}

struct BalanceFit {
  std::vector<double> h, defect;
  double order = 0;
};
struct Balance {
  double defect;      // |E(T) − E(0) − W|, W by Gregory's rule with m = 18
  double quadrature;  // |W(m = 18) − W(m = 17)|
};
Balance balance(const Q& E_end, const Q& E0, const std::vector<Q>& power, const Q& h) {
  const Q W = gregory(power, h);
  return {static_cast<double>(abs(E_end - E0 - W)), static_cast<double>(abs(W - gregory(power, h, gregory_terms - 1)))};
}
template <class Defect>
BalanceFit balance_order(const char* what, double t_end, const std::vector<long>& ns, double e_start, double e_stop,
                         Defect defect_after) {
  BalanceFit fit;
  for (const long n : ns) {
    const Balance b = defect_after(n);
    const double d = b.defect;
    std::printf("  %-34s n = %5ld  defect %.3e  (quadrature %.1e)", what, n, d, b.quadrature);
    if (!fit.h.empty()) std::printf("  local slope %.3f", std::log(d / fit.defect.back()) / std::log((t_end / n) / fit.h.back()));
    std::printf("\n");
    if (d > e_start || d < e_stop || !(b.quadrature < 0.01 * d)) continue;
    fit.h.push_back(t_end / static_cast<double>(n));
    fit.defect.push_back(d);
  }
  if (fit.h.size() < 5) {
    ADD_FAILURE() << what << ": " << fit.h.size() << " points in the window";
    return fit;
  }
  fit.order = test::fitted_order(fit.h, fit.defect);
  std::printf("%-36s energy balance: observed order %.3f over defects %.2e ... %.2e\n", what, fit.order,
              fit.defect.front(), fit.defect.back());
  return fit;
}

template <class S>
Balance gyrostat_balance_defect(long n) {
  std::vector<Q> power;
  const GyrostatState<Q> y = gyrostat_run<S>(n, &power);
  const GyrostatDynamics<Q> dyn(test::three_rotor_gyrostat().cast<Q>());
  const State<Q> x0 = gyrostat_start();
  const Q E0 = dyn.energy(dyn.state(x0.R, x0.Omega));
  return balance(dyn.energy(y), E0, power, Q(gyrostat_t_end) / Q(n));
}

template <template <class> class Method>
Balance driven_top_balance_defect(long n) {
  const auto p = test::driven_damped_skew_top().cast<Q>();
  using PQ = std::decay_t<decltype(p)>;
  Method<PQ> stepper(p);
  const Q t_end(2), h = t_end / Q(n);
  State<Q> x = test::skew_initial_state().cast<Q>();
  x.R = orthonormal(x.R);
  const Q E0 = energy(p, x);
  std::vector<Q> power;
  const auto observe = [&](const Q& t, const State<Q>& y) { power.push_back(p.power(t, y.Omega)); };
  EXPECT_EQ(integrate_every(stepper, x, Q(0), h, t_end, 1, observe).status, RunStatus::completed);
  return balance(energy(p, x), E0, power, h);
}

// Verner 9(8) and DOP853 RKMK on the gyrostat (exp chart) and in Cayley coordinates on the driven damped top, and the
// gyrostat LGVI's Kahan–Li 8 composition, whose coefficients exist only as doubles: their sum differs from 1 by
// ≈ 1e-16, so its defect levels off at 3.6e-15 (the power × T × that) from n ≈ 128; its window stops 39× above. Not
// here: the Sofroniou–Spaletta 10 composition, whose defect falls from 1.9e-10 (n = 20) to its floor (1.6e-16, n = 48)
// before Gregory's rule (n ≥ 18) is 100× below it at more than two points.
TEST(QuadOrder, EnergyBalanceOfOrdersEightAndNine) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::vector<long> ns{32, 40, 48, 64, 80, 96, 128, 160, 192, 256, 320, 384};
  EXPECT_NEAR(balance_order("rkmk_vern9 gyrostat", gyrostat_t_end, ns, 1e-18, 1e-30, gyrostat_balance_defect<GyrostatVern9Q>).order,
              9.0, 0.2);
  EXPECT_NEAR(balance_order("rkmk_dp8 gyrostat", gyrostat_t_end, ns, 1e-16, 1e-30, gyrostat_balance_defect<GyrostatDop853Q>).order,
              8.0, 0.2);
  // lgvi_kahan_li8 between 1e-9 and 1e-13: ≥ 39× above its floor (below).
  const std::vector<long> few{20, 24, 28, 32, 36, 40, 44, 48, 52, 56, 64};
  EXPECT_NEAR(balance_order("lgvi_kahan_li8 gyrostat", gyrostat_t_end, few, 1e-9, 1e-13,
                            gyrostat_balance_defect<GyrostatKahanLi8Q>).order,
              8.0, 0.2);
  EXPECT_NEAR(balance_order("rkmk_vern9_cayley driven damped top", 2.0, ns, 1e-18, 1e-30,
                            driven_top_balance_defect<Vern9CayleyQ>).order,
              9.0, 0.2);
  EXPECT_NEAR(balance_order("rkmk_dp8_cayley driven damped top", 2.0, ns, 1e-16, 1e-30,
                            driven_top_balance_defect<Dop853CayleyQ>).order,
              8.0, 0.2);
  std::printf("(%.2f s)\n", seconds_since(t0));
}

// ---- the control: double coefficients -----------------------------------------------------------------------

// The binary128 runs of the skew-top fit again, with Verner's coefficients rounded to double: every error sits
// on a floor of 1.26e-16 … 1.29e-16 (the order conditions hold only to 1.3e-16), the fitted slope is −0.01 —
// the fit above sees the method, not the arithmetic.
TEST(QuadOrderControl, DoubleCoefficientsHideTheOrder) {
  const Fit& fit = vern9_cayley_skew_fit();
  const Fit control = test::quad::errors_at<Vern9CayleyDoubleCoefficients>(
      test::skew_heavy_top(), test::skew_initial_state(), 2.0, skew_reference(), fit.n, 9,
      "rkmk_vern9_cayley skew top, double coefficients");
  EXPECT_LT(std::abs(control.order), 0.5);
  for (const double e : control.error) {
    EXPECT_GT(e, 1e-17);
    EXPECT_LT(e, 1e-15);
  }
}

}  // namespace
}  // namespace lgi
