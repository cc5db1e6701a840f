// The RKMK family, measured: every tableau against the Runge–Kutta order conditions; observed order of
// every RKMK method on the free body and on the non-diagonal heavy top against an independent reference;
// R on SO(3) after 10⁶ steps; energy drift (and a test that would catch a method that did not drift);
// steady rotations; Jets against finite differences; generic and reduced torque paths.
#include "figures.hpp"
#include "order_measure.hpp"
#include "rk_order_conditions.hpp"
#include "jet_check.hpp"
#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/core/invariants.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace lgi {
namespace {

using namespace lgi::test;

// ---- order conditions -------------------------------------------------------------------------------

template <class Tab>
std::vector<std::vector<double>> matrix_of(const Tab& tab, int n) {
  std::vector<std::vector<double>> A(static_cast<std::size_t>(n), std::vector<double>(static_cast<std::size_t>(n), 0.0));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = tab.a[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
  return A;
}

// The residuals of the conditions of each order 1..max for weights w (|w|: bounds on the weights' parts, for the
// rounding bound of rk_order_conditions.hpp).
std::vector<test::OrderResidual> residuals(const std::vector<test::RootedTree>& trees,
                                           const std::vector<std::vector<long double>>& phi,
                                           const std::vector<std::vector<long double>>& E, const std::vector<double>& w,
                                           const std::vector<long double>& w_abs, int max_order, long double theta = 1.0L) {
  std::vector<test::OrderResidual> r;
  for (int q = 1; q <= max_order; ++q) r.push_back(test::order_residual(trees, phi, E, w, w_abs, q, theta));
  return r;
}

std::vector<long double> magnitudes(const std::vector<double>& w) {
  std::vector<long double> m;
  for (const double x : w) m.push_back(std::abs(static_cast<long double>(x)));
  return m;
}

// Conditions up to `order` hold to within the rounding of the coefficients to doubles (every residual within
// its bound u B, rk_order_conditions.hpp); some condition of order + 1 fails by more than 1000 times what rounding
// could explain (so the order is exactly the declared one, not higher). The margin is measured against the
// rounding bound rather than a fixed 1e-6: Verner's 8(7) pair, tuned for small error coefficients, has its
// largest order-9 residual at 4.2e-7 (5.7e9 times its bound; DOP853 2.7e-5).
void expect_exact_order(const std::vector<test::OrderResidual>& r, int order, const std::string& what) {
  long double residual = 0, bound = 0, ratio = 0;
  for (int q = 1; q <= order; ++q) {
    const test::OrderResidual& rq = r[static_cast<std::size_t>(q - 1)];
    EXPECT_LE(rq.ratio, 1.0L) << what << ": order-" << q << " conditions, residual " << static_cast<double>(rq.residual)
                              << " beyond the rounding of the coefficients";
    residual = std::max(residual, rq.residual);
    bound = std::max(bound, rq.bound);
    ratio = std::max(ratio, rq.ratio);
  }
  const bool has_next = static_cast<int>(r.size()) > order;
  const test::OrderResidual next = has_next ? r[static_cast<std::size_t>(order)] : test::OrderResidual{};
  if (has_next) {
    EXPECT_GT(next.ratio, 1e3L) << what << ": satisfies the order-" << order + 1 << " conditions too (residual "
                                << static_cast<double>(next.residual) << ")";
  }
  std::printf("%-28s order %d: max residual up to order %d = %.2Le (rounding bound %.1Le, largest ratio %.2Lf), "
              "order %d residual = %.2Le (%.1Le x its bound)\n",
              what.c_str(), order, order, residual, bound, ratio, order + 1, next.residual, next.ratio);
}

template <class Tab>
void check_row_sums(const Tab& tab, int n, const std::string& what) {
  for (int i = 0; i < n; ++i) {
    double sum = 0, magnitude = 0;
    for (int j = 0; j < i; ++j) {
      sum += tab.a[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
      magnitude += std::abs(tab.a[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]);
    }
    // c_i = Σ_j a_ij up to the rounding of the coefficients to doubles (DOP853's rows sum entries up to 43)
    EXPECT_NEAR(sum, tab.c[static_cast<std::size_t>(i)], 1e-15 * (1 + magnitude)) << what << " row " << i;
    for (int j = i; j < n; ++j) EXPECT_EQ(tab.a[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)], 0.0) << what << ": not explicit";
  }
}

template <int S>
void check_plain(const ButcherTableau<S>& tab) {
  const auto trees = test::rooted_trees(tab.order + 1);
  const auto A = matrix_of(tab, S);
  const auto phi = test::elementary_weights(trees, A);
  const auto E = test::elementary_weight_errors(trees, phi, A);
  check_row_sums(tab, S, std::string(tab.name));
  const std::vector<double> b(tab.b.begin(), tab.b.end());
  expect_exact_order(residuals(trees, phi, E, b, magnitudes(b), tab.order + 1), tab.order, std::string(tab.name));
}

TEST(OrderConditions, TreeCounts) {
  const auto trees = test::rooted_trees(10);
  std::vector<int> count(11, 0);
  for (const auto& t : trees) ++count[static_cast<std::size_t>(t.order)];
  EXPECT_EQ(count, (std::vector<int>{0, 1, 1, 2, 4, 9, 20, 48, 115, 286, 719}));  // OEIS A000081
}

TEST(OrderConditions, PlainTableaus) {
  check_plain(tableaus::euler);
  check_plain(tableaus::heun);
  check_plain(tableaus::kutta3);
  check_plain(tableaus::classical_rk4);
  check_plain(tableaus::rule38);
}

template <int S, int SE, int D>
void check_pair(const EmbeddedTableau<S, SE, D>& tab) {
  const std::string name(tab.name);
  const auto trees = test::rooted_trees(tab.order + 1);
  const auto A = matrix_of(tab, SE);
  const auto phi = test::elementary_weights(trees, A);
  const auto E = test::elementary_weight_errors(trees, phi, A);
  check_row_sums(tab, SE, name);
  // the first-same-as-last stage sits at the new point
  for (int j = 0; j < S; ++j) EXPECT_EQ(tab.a[static_cast<std::size_t>(tab.fsal)][static_cast<std::size_t>(j)], tab.b[static_cast<std::size_t>(j)]);
  std::vector<double> b(SE, 0.0), bhat(SE, 0.0), b3(SE, 0.0);
  std::vector<long double> bhat_abs(SE, 0.0L), b3_abs(SE, 0.0L);
  bool second = false;
  for (int i = 0; i < S; ++i) {
    const auto k = static_cast<std::size_t>(i);
    b[k] = tab.b[k];
    bhat[k] = tab.b[k] - tab.e[k];
    b3[k] = tab.b[k] - tab.e3[k];
    bhat_abs[k] = std::abs(static_cast<long double>(tab.b[k])) + std::abs(static_cast<long double>(tab.e[k]));
    b3_abs[k] = std::abs(static_cast<long double>(tab.b[k])) + std::abs(static_cast<long double>(tab.e3[k]));
    second = second || tab.e3[k] != 0;
  }
  expect_exact_order(residuals(trees, phi, E, b, magnitudes(b), tab.order + 1), tab.order, name + " b");
  expect_exact_order(residuals(trees, phi, E, bhat, bhat_abs, tab.order + 1), tab.embedded_order, name + " b-e");
  if (second) expect_exact_order(residuals(trees, phi, E, b3, b3_abs, tab.order + 1), 3, name + " b-e3");
  // The continuous extension: order dense_order at several θ, b(1) = b, b(0) = 0.
  for (const long double theta : {0.1L, 0.37L, 0.5L, 0.83L, 1.0L}) {
    std::vector<double> w(SE, 0.0);
    std::vector<long double> w_abs(SE, 0.0L);
    for (int i = 0; i < SE; ++i) {
      long double p = 0, p_abs = 0;
      for (int m = D - 1; m >= 0; --m) {
        const long double r = tab.dense[static_cast<std::size_t>(i)][static_cast<std::size_t>(m)];
        p = p * theta + r;
        p_abs = p_abs * theta + std::abs(r);
      }
      w[static_cast<std::size_t>(i)] = static_cast<double>(p * theta);
      w_abs[static_cast<std::size_t>(i)] = p_abs * theta;
    }
    const auto r = residuals(trees, phi, E, w, w_abs, tab.dense_order + 1, theta);
    long double residual = 0, bound = 0, ratio = 0;
    for (int q = 1; q <= tab.dense_order; ++q) {
      const test::OrderResidual& rq = r[static_cast<std::size_t>(q - 1)];
      EXPECT_LE(rq.ratio, 1.0L) << name << " dense θ = " << static_cast<double>(theta) << " order " << q << ": residual "
                                << static_cast<double>(rq.residual) << " beyond the rounding of the coefficients";
      residual = std::max(residual, rq.residual);
      bound = std::max(bound, rq.bound);
      ratio = std::max(ratio, rq.ratio);
    }
    if (theta != 1.0L) {
      EXPECT_GT(r[static_cast<std::size_t>(tab.dense_order)].residual, 1e-9L) << name << " dense order is higher?";
    }
    std::printf("%-28s dense θ = %.2f: max residual up to order %d = %.2Le (rounding bound %.1Le, largest ratio %.2Lf), "
                "order %d residual = %.2Le\n",
                name.c_str(), static_cast<double>(theta), tab.dense_order, residual, bound, ratio, tab.dense_order + 1,
                r[static_cast<std::size_t>(tab.dense_order)].residual);
    if (theta == 1.0L) {
      // b(1) = b to 1e-12, or to the rounding of the dense coefficients where that is larger (4 u Σ_m |r_im|:
      // Verner's 8(7) pair, whose coefficients reach 1.35e6, 1.5e-9)
      for (int i = 0; i < SE; ++i) {
        const auto k = static_cast<std::size_t>(i);
        EXPECT_NEAR(w[k], b[k], std::max(1e-12, 4 * 0x1p-53 * static_cast<double>(w_abs[k]))) << name << " b(1) = b, stage " << i;
      }
    }
  }
}

TEST(OrderConditions, EmbeddedPairs) {
  check_pair(tableaus::dormand_prince5);
  check_pair(tableaus::dop853);
  check_pair(tableaus::verner8);
  check_pair(tableaus::verner9);
}

template <template <class> class M>
struct MethodTag {
  template <class P>
  using type = M<P>;
};

template <class Tag>
class RkmkFamily : public ::testing::Test {};
using FamilyMethods = ::testing::Types<MethodTag<RkmkHeun>, MethodTag<Rkmk3>, MethodTag<Rkmk4Rule38>,
                                       MethodTag<RkmkDp5>, MethodTag<RkmkDp8>, MethodTag<Rkmk4>,
                                       MethodTag<Rkmk4Cayley>, MethodTag<RkmkDp5Cayley>, MethodTag<RkmkDp8Cayley>,
                                       MethodTag<RkmkVern9>, MethodTag<RkmkVern9Cayley>>;
TYPED_TEST_SUITE(RkmkFamily, FamilyMethods);

// Verner 9(8) in Cayley coordinates converges faster than h⁹ wherever its errors can be measured in double or
// long double: on the skew top (T = 2, long double) the fit over the window of observed_order is 9.46 and the
// local slopes fall from 9.9 (h|Ω(0)| = 0.45) to 9.3 (0.14), where the errors (1e-15) meet the round-off floor of
// the double coefficients (1.1e-16); on the free bodies (GNI, T = 10; Hairer–Vilmart, T = 2) they stay at 10.0
// from 5e-11 down to that floor. The pair has order 9 exactly (its order-10 residuals reach 1.8e-6,
// OrderConditions), but its order-11 residuals are ≈ 25× its order-10 ones (rms over the trees, scaled by γ:
// 8.9e-2 against 3.6e-3), and in the Cayley chart, with its larger error constants (rkmk.hpp), the terms of the
// global error beyond h⁹ keep the local slopes above 9.2 down to h|Ω(0)| ≈ 0.13 on the skew top (where e/h⁹ is
// 1.37× its limit at h|Ω(0)| = 0.27) and ≈ 0.01 on the GNI body (e/h⁹ twice its limit at h|Ω(0)| = 0.03).
// The order itself is measured beyond double, in tests/integrators/test_quad_order.cpp: 9.002 on the skew top in binary128
// (errors 7.8e-21 … 1.5e-29, e/h⁹ → 6.92e-7) and 9.096 on the GNI body in 50 digits (3.7e-27 … 7.2e-37, local
// slopes 9.30 → 9.02, e/h⁹ → 2.84e-9); the typed tests below defer to those. Kept here as findings: on the skew
// top in long double, e(h)/h⁹ = A + B h fitted over h|Ω(0)| = 0.45 … 0.18 has A > 0 (4.4e-7 + 2.7e-6 h;
// binary128 puts the limit at 6.92e-7, the straight-line fit's A absorbs the higher terms) carrying at least half
// of e at the smallest step (0.55), and e(h)/h¹⁰ grows as h falls (4.0e-6 → 6.1e-6: not order 10).
TEST(RkmkFamilyFindings, Vern9CayleySkewTopInLongDouble) {
  const State<double> x0 = test::skew_initial_state();
  const double T = 2.0;
  std::vector<double> hs, scaled9, scaled10;
  for (const int n : {6, 8, 10, 12, 15}) {
    RkmkVern9Cayley<HeavyTop<L>> stepper(skew_top().cast<L>());
    State<L> x = x0.cast<L>();
    ASSERT_EQ(integrate_to(stepper, x, L(0), L(T) / n, L(T)).status, RunStatus::completed);
    const double h = T / n, e = distance(x, skew_reference().x);
    hs.push_back(h);
    scaled9.push_back(e / std::pow(h, 9));
    scaled10.push_back(e / std::pow(h, 10));
  }
  // least squares e/h⁹ = A + B h
  const double m = static_cast<double>(hs.size());
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < hs.size(); ++i) {
    sx += hs[i];
    sy += scaled9[i];
    sxx += hs[i] * hs[i];
    sxy += hs[i] * scaled9[i];
  }
  const double B = (m * sxy - sx * sy) / (m * sxx - sx * sx), A = (sy - B * sx) / m;
  const double share = A / (A + B * hs.back());
  const double p = observed_order<RkmkVern9Cayley>(skew_top(), x0, T, skew_reference(), "skew top");
  std::printf("rkmk_vern9_cayley skew top: e/h^9 = %.3e + %.3e h over h = %.3g … %.3g (h^9 share at the smallest step "
              "%.2f); e/h^10 from %.3e to %.3e; fit over the standard window %.3f\n",
              A, B, hs.front(), hs.back(), share, scaled10.front(), scaled10.back(), p);
  EXPECT_GT(A, 0.0);
  EXPECT_GT(share, 0.5);
  for (std::size_t i = 1; i < scaled10.size(); ++i) EXPECT_GT(scaled10[i], scaled10[i - 1]) << "e/h^10 at h = " << hs[i];
  EXPECT_GT(p, 9.0);
  EXPECT_LT(p, 9.7);
}

// Verner 9(8) on the GNI free body in long double (see above): from h|Ω(0)| = 1 (the standard window, 0.4, spans
// only four points, 5e-13 … 1e-15, before the floor); local slopes 10.0 throughout. (In 50 digits the slopes
// come down to 9.02 at 7e-37: tests/integrators/test_quad_order.cpp.)
TEST(RkmkFamilyFindings, Vern9CayleyGniFreeBodyInLongDouble) {
  const double p = observed_order<RkmkVern9Cayley>(gni_body(), gni_state(), 10.0, gni_reference(), "free body", 1.0);
  EXPECT_GT(p, 9.8);
  EXPECT_LT(p, 10.3);
}

// The methods whose order shows only beyond double are measured in tests/integrators/test_quad_order.cpp (QuadOrder, built
// where GCC's __float128 and libquadmath are available): Verner 9(8) in both charts on both cases, rkmk_dp8_cayley on
// the free body. In the exponential chart Verner 9(8) keeps its dexp⁻¹ series to ad⁸ (integrators/rkmk.hpp: an
// embedded pair keeps K = p): on the skew top its fit over the double window lies above 9 (9.39, its h¹⁰ terms,
// as in Cayley coordinates), held between 9 − 0.2 and 9.7 here; on the GNI body its errors reach the long-double
// reference's floor within the window (1e-15 at h = 0.14). Its order is measured in binary128 (QuadOrder.Vern9On*).
TYPED_TEST(RkmkFamily, ObservedOrderOnTheSkewHeavyTop) {
  using S = typename TypeParam::template type<HeavyTop<double>>;
  if constexpr (S::chart == LieChart::cayley && S::traits.order == 9)
    GTEST_SKIP() << "measured in binary128: QuadOrder.Vern9CayleyOnTheSkewHeavyTop (9.002)";
  const double p = observed_order<TypeParam::template type>(skew_top(), test::skew_initial_state(), 2.0,
                                                            skew_reference(), "skew top");
  if constexpr (S::chart == LieChart::exp && S::traits.order == 9) {
    EXPECT_GE(p, 9.0 - 0.2);
    EXPECT_LE(p, 9.7);
  } else {
    EXPECT_NEAR(p, S::traits.order, 0.2);
  }
}

TYPED_TEST(RkmkFamily, ObservedOrderOnTheFreeBody) {
  using S = typename TypeParam::template type<FreeBody<double>>;
  if constexpr (S::chart == LieChart::cayley && S::traits.order == 9)
    GTEST_SKIP() << "measured in 50 digits: QuadOrder.Vern9CayleyOnTheGniFreeBody (9.096)";
  if constexpr (S::chart == LieChart::cayley && S::traits.order == 8)
    GTEST_SKIP() << "measured in binary128: QuadOrder.Dop853CayleyOnTheGniFreeBody (8.002)";
  if constexpr (S::chart == LieChart::exp && S::traits.order == 9)
    GTEST_SKIP() << "measured in binary128: QuadOrder.Vern9OnTheGniFreeBody (9.083)";
  const double p = observed_order<TypeParam::template type>(gni_body(), gni_state(), 10.0, gni_reference(), "free body");
  EXPECT_NEAR(p, S::traits.order, 0.2);
}

// On the Hairer–Vilmart free body (J = diag(0.6, 0.8, 1), m0 = (1.8, 0.4, −0.9), T = 2) DOP853 converges
// faster than order 8 over most errors (in double: 9.2 over 1e-5 … 1e-12): the Euler equations are
// quadratic, so only trees whose vertices have at most two children carry elementary differentials, and
// DOP853's order-9 residuals on those trees are ≈ 18× smaller (max 1.5e-6) than on the others (2.7e-5):
// the h⁸ term of the global error is small against h⁹ there. Measured: the order is at least 8.
TEST(RkmkFamilyFindings, HairerVilmartFreeBodyDop853) {
  const auto body = FreeBody<double>::hairer_vilmart();
  const State<double> x0 = test::hairer_vilmart_state(body);
  const Reference ref = make_reference(body, x0, 2.0);
  // h|Ω(0)| up to 1: with 0.4 the errors are below 4e-13 from the first point
  const double p = observed_order<RkmkDp8>(body, x0, 2.0, ref, "HV body", 1.0);
  EXPECT_GT(p, 7.8);
}

// DOP853 in Cayley coordinates on the GNI free body (T = 10): the fit over the test's window is 8.23, and the
// local slopes stay at 8.1 … 8.4 from errors of 1e-11 down to 1e-15 (measured by self-convergence in long
// double, which removes the 1e-15 floor of the double coefficients): the h⁹ term weighs ≈ 20 % at h = 0.1 and
// fades only slowly. On the HV body the same fit gives 8.15 (T = 2) and 8.17 (T = 10), on the skew top 8.17.
// Measured: at least 8, and not far above it in this window; 8.002 in binary128 over errors 3.5e-17 … 1.1e-25
// (QuadOrder.Dop853CayleyOnTheGniFreeBody). On the HV body (T = 2) within 0.2 of 8 already in long double.
TEST(RkmkFamilyFindings, GniFreeBodyDop853Cayley) {
  const double p = observed_order<RkmkDp8Cayley>(gni_body(), gni_state(), 10.0, gni_reference(), "free body");
  EXPECT_GT(p, 7.9);
  EXPECT_LT(p, 8.4);
  const auto body = FreeBody<double>::hairer_vilmart();
  const State<double> x0 = test::hairer_vilmart_state(body);
  const double p_hv = observed_order<RkmkDp8Cayley>(body, x0, 2.0, make_reference(body, x0, 2.0), "HV body");
  EXPECT_NEAR(p_hv, 8.0, 0.2);
}

// ---- long runs: R on SO(3), energy drift ------------------------------------------------------------

struct LongRun {
  std::vector<double> t;
  std::vector<double> energy_error;
  double orthogonality = 0;
  std::int64_t steps = 0;
};

template <class S>
LongRun long_run(const HeavyTop<double>& problem, const State<double>& x0, double h, std::int64_t n, std::int64_t every) {
  S stepper(problem);
  const double E0 = energy(problem, x0);
  LongRun run;
  auto observe = [&](double t, const State<double>& x) {
    run.t.push_back(t);
    run.energy_error.push_back((energy(problem, x) - E0) / std::abs(E0));
    run.orthogonality = std::max(run.orthogonality, so3::orthogonality_error(x.R));
  };
  State<double> x = x0;
  const auto summary = integrate_every(stepper, x, 0.0, h, h * static_cast<double>(n), every, observe);
  EXPECT_EQ(summary.status, RunStatus::completed);
  run.steps = summary.steps;
  return run;
}

double max_abs(const std::vector<double>& v) {
  double m = 0;
  for (const double x : v) m = std::max(m, std::abs(x));
  return m;
}

// The change of the mean (signed) error between the first and the last tenth of the run, relative to the
// largest |error|: ≈ 0 for an error oscillating about a fixed mean, ≈ 0.9 for a linear drift from 0
// (the measure of tests/integrators/test_long_run.cpp).
double mean_shift(const std::vector<double>& err) {
  const std::size_t n = err.size(), tenth = n / 10;
  double first = 0, last = 0;
  for (std::size_t i = 0; i < tenth; ++i) {
    first += err[i];
    last += err[n - tenth + i];
  }
  return std::abs(last - first) / static_cast<double>(tenth) / max_abs(err);
}

// The drift slope of tests/integrators/test_composition.cpp (the measure the symplectic compositions must keep below 0.1):
// log max |energy error| over 64 equal windows of the run (the first left out) against log of the window's
// middle time. ≈ 0 for a bounded error, → 1 for a linear drift, ≈ 0.5 for a random walk.
double drift_slope(const LongRun& run) {
  constexpr int windows = 64;
  const double T = run.t.back();
  std::vector<double> ts, es;
  for (int w = 1; w < windows; ++w) {
    const double a = T * w / windows, b = T * (w + 1) / windows;
    double largest = 0;
    for (std::size_t i = 0; i < run.t.size(); ++i)
      if (run.t[i] > a && run.t[i] <= b) largest = std::max(largest, std::abs(run.energy_error[i]));
    ts.push_back(0.5 * (a + b));
    es.push_back(largest);
  }
  return test::fitted_order(ts, es);
}

// Every RKMK method declares exact_on_group: ‖RᵀR − I‖ after 10⁶ steps (HV heavy top, h = 0.01) is the random walk
// of rounding of one update of R a step (figures.hpp).
TYPED_TEST(RkmkFamily, MillionStepsStayOnSO3) {
  using S = typename TypeParam::template type<HeavyTop<double>>;
  static_assert(S::traits.exact_on_group);
  const auto top = HeavyTop<double>::hairer_vilmart();
  const LongRun run = long_run<S>(top, test::hairer_vilmart_state(top), 0.01, 1'000'000, 1000);
  std::printf("%-10s 1e6 steps h = 0.01: max |RtR - I| = %.3e, final relative energy error %.3e\n", S::traits.name.data(),
              run.orthogonality, run.energy_error.back());
  EXPECT_EQ(run.steps, 1'000'000);
  test::expect_figure("|RtR - I| after 1e6 steps, " + std::string(S::traits.name), run.orthogonality,
                      test::orthogonality_walk_bound(1e6));
}

// Not symplectic: the energy drifts (HV heavy top, h = 0.05, 2·10⁵ steps, T = 10⁴): mean shift ≈ 0.9 and drift
// slope ≈ 1 for every method. The same two measures give ≈ 0 for the LGVI below, so this test can tell a
// drift from none; the slope is the one the symplectic methods' tests hold below 0.1.
TYPED_TEST(RkmkFamily, EnergyDrifts) {
  using S = typename TypeParam::template type<HeavyTop<double>>;
  const auto top = HeavyTop<double>::hairer_vilmart();
  const LongRun run = long_run<S>(top, test::hairer_vilmart_state(top), 0.05, 200'000, 200);
  const double shift = mean_shift(run.energy_error), slope = drift_slope(run);
  std::printf("%-10s h = 0.05, 2e5 steps: final relative energy error %.3e, mean shift %.3f, drift slope %.3f\n",
              S::traits.name.data(), run.energy_error.back(), shift, slope);
  EXPECT_GT(shift, 0.5) << S::traits.name;
  EXPECT_GT(slope, 0.5) << S::traits.name;
}

TEST(RkmkFamilyControl, TheDriftMeasureSeesNoDriftInTheLgvi) {
  const auto top = HeavyTop<double>::hairer_vilmart();
  const LongRun run = long_run<Lgvi<HeavyTop<double>>>(top, test::hairer_vilmart_state(top), 0.05, 200'000, 200);
  const double shift = mean_shift(run.energy_error), slope = drift_slope(run);
  std::printf("lgvi       h = 0.05, 2e5 steps: max relative energy error %.3e, mean shift %.3f, drift slope %.3f\n",
              max_abs(run.energy_error), shift, slope);
  EXPECT_LT(shift, 0.05);
  EXPECT_LT(std::abs(slope), 0.1);
}

// ---- the truncation of the J_r⁻¹ series -----------------------------------------------------------
//
// An RKMK method of order p needs the ad_u^k terms of J_r⁻¹(u)W up to k = p − 2 (rkmk.hpp; an embedded pair
// keeps them to k = p, for its error estimate). Along a step
// u = O(h) and ad_u W = O(h²), so dropping the term k changes a step by O(h^(k+2)) and the global error by
// O(h^(k+1)): the truncation must match the order. Measured on the skew top: with the series cut one non-zero
// term short (K lowered to the previous non-zero Bernoulli term), the observed order falls to k + 1 — which
// shows that the default K is needed and (the tests above) sufficient.
template <class P>
using Rkmk3SeriesK0 = Rkmk<tableaus::kutta3, P, 0>;  // drops ½ ad_u: order 2
template <class P>
using Rkmk4SeriesK1 = Rkmk<tableaus::classical_rk4, P, 1>;  // drops (1/12) ad_u²: order 3
template <class P>
using RkmkDp5SeriesK1 = Rkmk<tableaus::dormand_prince5, P, 1>;  // drops (1/12) ad_u²: order 3
template <class P>
using RkmkDp8SeriesK4 = Rkmk<tableaus::dop853, P, 4>;  // drops (1/30240) ad_u⁶: order 7
template <class P>
using RkmkVern9SeriesK4 = Rkmk<tableaus::verner9, P, 4>;  // drops (1/30240) ad_u⁶: order 7

TEST(RkmkSeriesTruncation, OneTermShortLowersTheOrder) {
  const auto order = [](auto measured, int expected, const char* what) {
    std::printf("%-34s observed %.3f, expected %d\n", what, measured, expected);
    EXPECT_NEAR(measured, expected, 0.2) << what;
  };
  const State<double> x0 = test::skew_initial_state();
  order(observed_order<Rkmk3SeriesK0>(skew_top(), x0, 2.0, skew_reference(), "K=0"), 2, "rkmk3 with K = 0 (needs 1)");
  order(observed_order<Rkmk4SeriesK1>(skew_top(), x0, 2.0, skew_reference(), "K=1"), 3, "rkmk4 with K = 1 (needs 2)");
  order(observed_order<RkmkDp5SeriesK1>(skew_top(), x0, 2.0, skew_reference(), "K=1"), 3, "rkmk_dp5 with K = 1 (needs 2)");
  order(observed_order<RkmkDp8SeriesK4>(skew_top(), x0, 2.0, skew_reference(), "K=4"), 7, "rkmk_dp8 with K = 4 (needs 6)");
  order(observed_order<RkmkVern9SeriesK4>(skew_top(), x0, 2.0, skew_reference(), "K=4"), 7, "rkmk_vern9 with K = 4 (needs 6)");
}

// ---- steady rotation, Jets, torque paths -------------------------------------------------------------

// A free symmetric body spinning about a principal axis: Ω constant, R(t) = R0 exp(tΩ). Every RKMK step in
// the exponential chart gives that exactly (u' = J_r⁻¹(u)Ω = Ω along Ω). In the Cayley chart u' = dcay⁻¹_u Ω =
// (1 + |u|²/4) Ω along Ω: u stays on the axis exactly, but its length 2 tan(t|Ω|/2) is integrated by the
// tableau, with the tableau's local error in the angle — |Δθ| ≤ (h|Ω|)^(p+1) here (h|Ω| ≤ 0.05), plus the
// 4e-16 of rounding the exponential chart is held to.
TYPED_TEST(RkmkFamily, SteadyRotationIsExact) {
  using S = typename TypeParam::template type<FreeBody<double>>;
  FreeBody<double> body{Vec3<double>(2.0, 2.0, 1.0).asDiagonal()};
  const Mat3<double> R0 = so3::exp(Vec3<double>(0.3, -1.1, 0.4));
  for (const Vec3<double>& Omega : {Vec3<double>(0, 0, 5.0), Vec3<double>(3.0, -4.0, 0), Vec3<double>(0.7, 0, 0)}) {
    S stepper(body);
    auto y = stepper.to_internal({R0, Omega}, 0.0);
    ASSERT_EQ(stepper.step(y, 0.0, 0.01), StepStatus::ok);
    const Mat3<double> expected = R0 * so3::exp(Vec3<double>(0.01 * Omega));
    if constexpr (S::chart == LieChart::exp) {
      EXPECT_LT((y.R - expected).cwiseAbs().maxCoeff(), 4e-16) << S::traits.name;
    } else {
      const Vec3<double> turn = so3::log(Mat3<double>(R0.transpose() * y.R));  // θ n
      const Vec3<double> axis = Omega.normalized();
      const double angle_error = std::abs(turn.dot(axis) - 0.01 * Omega.norm());
      std::printf("%-16s steady rotation h|Omega| = %.3f: off-axis %.1e, angle error %.2e (bound %.1e)\n",
                  S::traits.name.data(), 0.01 * Omega.norm(), turn.cross(axis).norm(), angle_error,
                  std::pow(0.01 * Omega.norm(), S::traits.order + 1) + 4e-16);
      EXPECT_LT(turn.cross(axis).norm(), 4e-16) << S::traits.name;
      EXPECT_LE(angle_error, std::pow(0.01 * Omega.norm(), S::traits.order + 1) + 4e-16) << S::traits.name;
    }
    EXPECT_LT((y.Omega - Omega).cwiseAbs().maxCoeff(), 1e-15 * Omega.norm()) << S::traits.name;
  }
}

// Jets through 50 steps: derivatives with respect to Ω0 and b against central differences.
TYPED_TEST(RkmkFamily, JetDerivativesMatchFiniteDifferences) {
  test::expect_heavy_top_jets_match<TypeParam::template type>(0.02, 1.0, 4e-15);
}

// The heavy top seen only through torque(R): stage attitudes R·exp(u) instead of rotated Γ.
struct OpaqueTop {
  using Scalar = double;
  static constexpr std::string_view name = "opaque_top";
  static constexpr bool has_torque = true;
  HeavyTop<double> top;
  Mat3<double> inertia = top.inertia;
  double potential(const Mat3<double>& R) const { return top.potential(R); }
  Vec3<double> torque(const Mat3<double>& R) const { return top.torque(R); }
  static constexpr std::array<std::string_view, 0> invariant_names{};
  std::array<double, 0> invariants(const State<double>&) const { return {}; }
};

TYPED_TEST(RkmkFamily, GenericTorquePathMatchesReducedPath) {
  using SR = typename TypeParam::template type<HeavyTop<double>>;
  using SG = typename TypeParam::template type<OpaqueTop>;
  const auto top = test::skew_heavy_top();
  const OpaqueTop opaque{top, top.inertia};
  State<double> xr = test::skew_initial_state(), xg = xr;
  SR reduced(top);
  SG generic(opaque);
  integrate_to(reduced, xr, 0.0, 0.01, 2.0);
  integrate_to(generic, xg, 0.0, 0.01, 2.0);
  // The double run of the reduced top carries principal axes, the opaque top's the body frame (the RkmkPrincipalAxes
  // tests below): 1.7e-15 … 5.8e-15.
  test::expect_figure(std::string("generic vs reduced torque path over 200 steps, ") + std::string(SR::traits.name),
                      test::state_distance(xr, xg), 2.5e-14);
}

// ---- a non-diagonal J: the state in principal axes (integrators/rkmk.hpp) ----
// In double a top with a non-diagonal J runs with R_p = R Q, Ω_p = QᵀΩ, J = diag(I) and the lever Qᵀ(b z0);
// RKMK is equivariant under a constant change of body frame, so the runs are the body-frame runs up to
// rounding. Jets keep the body frame: their value parts are the reference.
using Jet1 = ceres::Jet<double, 1>;

double difference(const State<double>& a, const State<double>& b) {
  return (a.R - b.R).norm() + (a.Omega - b.Omega).norm();
}

State<double> values(const State<Jet1>& x) {
  State<double> v;
  for (int i = 0; i < 3; ++i) {
    v.Omega(i) = x.Omega(i).a;
    for (int j = 0; j < 3; ++j) v.R(i, j) = x.R(i, j).a;
  }
  return v;
}

template <class P>
using JetOf = decltype(std::declval<const P&>().template cast<Jet1>());

// The largest distance between the double stepper d's run (principal axes) and the Jet stepper j's run (body
// frame) over `steps` steps.
template <class Double, class Jet>
double principal_against_body_frame(Double d, Jet j, const State<double>& x0, double h, int steps) {
  EXPECT_FALSE(d.internal_is_body_frame());
  EXPECT_TRUE(j.internal_is_body_frame());
  auto y = d.to_internal(x0, 0.0);
  auto yj = j.to_internal(x0.cast<Jet1>(), Jet1(0));
  double worst = 0;
  for (int n = 0; n < steps; ++n) {
    EXPECT_EQ(d.step(y, n * h, h), StepStatus::ok);
    EXPECT_EQ(j.step(yj, Jet1(n * h), Jet1(h)), StepStatus::ok);
    worst = std::max(worst, difference(d.to_state(y), values(j.to_state(yj))));
  }
  return worst;
}

template <template <class> class Method, class P>
double principal_against_body_frame(const P& problem, const State<double>& x0, double h, int steps) {
  return principal_against_body_frame(Method<P>(problem), Method<JetOf<P>>(problem.template cast<Jet1>()), x0, h,
                                      steps);
}

// The negative control of the comparison: RKMK4 whose internal frame is wrong by F at the edges of the run —
// (R, Ω) enters as (R Q F, Fᵀ Qᵀ Ω) and leaves through the inverse, while its steps use J = diag(I) and the lever
// Qᵀv of the true principal axes Q.
template <class P>
struct MisframedRkmk4 : Rkmk4<P> {
  Mat3<double> F;
  MisframedRkmk4(const P& problem, const Mat3<double>& frame_error) : Rkmk4<P>(problem), F(frame_error) {}
  State<double> to_internal(const State<double>& x, double t) const {
    State<double> y = Rkmk4<P>::to_internal(x, t);
    return {Mat3<double>(y.R * F), Vec3<double>(F.transpose() * y.Omega)};
  }
  State<double> to_state(const State<double>& y) const {
    return Rkmk4<P>::to_state({Mat3<double>(y.R * F.transpose()), Vec3<double>(F * y.Omega)});
  }
};

template <template <class> class Method, class P>
void adaptive_principal_against_body_frame(const char* name, const P& problem, const State<double>& x0, double h,
                                           double estimate_bound) {
  StepperOptions o;
  o.rtol = o.atol = 1e-8;
  Method<P> d(problem, o);
  Method<JetOf<P>> j(problem.template cast<Jet1>(), o);
  typename Method<P>::Dense dd;
  typename Method<JetOf<P>>::Dense dj;
  const auto y0 = d.to_internal(x0, 0.0);
  const auto yj0 = j.to_internal(x0.cast<Jet1>(), Jet1(0));
  auto y1 = y0;
  auto yj1 = yj0;
  double ed = 0, ej = 0;
  ASSERT_EQ(d.attempt(y0, 0.0, h, y1, ed, dd), StepStatus::ok);
  ASSERT_EQ(j.attempt(yj0, Jet1(0), Jet1(h), yj1, ej, dj), StepStatus::ok);
  const double step_diff = difference(d.to_state(y1), values(j.to_state(yj1)));
  const double dense_diff =
      difference(d.to_state(d.dense_output(dd, 0.37)), values(j.to_state(j.dense_output(dj, Jet1(0.37)))));
  std::printf("%-18s principal axes against the body frame, one step h = %g: state %.2e, error estimate %.6g "
              "against %.6g, dense output at 0.37 %.2e\n", name, h, step_diff, ed, ej, dense_diff);
  // A few ulps of O(1) numbers (6.0e-16 … 1.2e-15): held to 18.
  test::expect_figure(std::string("principal axes vs body frame, one adaptive step, ") + name, step_diff, 4e-15);
  test::expect_figure(std::string("principal axes vs body frame, dense output, ") + name, dense_diff, 4e-15);
  // The estimate's Ω part is scaled component-wise (atol + rtol|Ω_k|) in principal axes, not in the body frame:
  // the same size, not the same number (|ratio − 1| 2e-10 … 5.2e-5 by pair; `estimate_bound` ≈ 4× each).
  test::expect_figure(std::string("principal axes vs body frame, |error estimate ratio - 1|, ") + name,
                      std::abs(ed / ej - 1), estimate_bound);
}

// A heavy top whose torque was changed but whose lever was inherited: the lever no longer describes it.
struct MislabelledTop : HeavyTop<double> {
  Vec3<double> reduced_torque(const Vec3<double>& Gamma) const { return 2.0 * HeavyTop<double>::reduced_torque(Gamma); }
};

TEST(RkmkPrincipalAxes, StepsEqualTheBodyFrameStepsToRounding) {
  const auto& top = skew_top();
  const State<double> x0 = test::skew_initial_state();
  const FreeBody<double> body{top.inertia};
  const double e4 = principal_against_body_frame<Rkmk4>(top, x0, 0.01, 200);
  const double e4b = principal_against_body_frame<Rkmk4>(body, x0, 0.01, 200);
  const double e4c = principal_against_body_frame<Rkmk4Cayley>(top, x0, 0.01, 200);
  const double e8 = principal_against_body_frame<RkmkDp8>(top, x0, 0.05, 200);
  const double e9c = principal_against_body_frame<RkmkVern9Cayley>(top, x0, 0.05, 200);
  std::printf("principal axes against the body frame, largest state difference over 200 steps: rkmk4 %.2e (free "
              "body %.2e), rkmk4_cayley %.2e, rkmk_dp8 %.2e, rkmk_vern9_cayley %.2e\n", e4, e4b, e4c, e8, e9c);
  test::expect_figure("principal axes vs body frame over 200 steps, rkmk4", e4, 2e-14);
  test::expect_figure("principal axes vs body frame over 200 steps, rkmk4, free body", e4b, 1.2e-14);
  test::expect_figure("principal axes vs body frame over 200 steps, rkmk4_cayley", e4c, 3e-14);
  test::expect_figure("principal axes vs body frame over 200 steps, rkmk_dp8", e8, 4.5e-14);
  test::expect_figure("principal axes vs body frame over 200 steps, rkmk_vern9_cayley", e9c, 3.5e-14);
}

// Negative controls: the same comparison fails a run in principal axes reflected (F = diag(1, 1, −1), det Q F = −1:
// the axes Eigen's eigensolver may return when PrincipalAxes drops its determinant fix; the cross products of the
// equations change sign) and in axes turned by 1e-9 rad (the eigenvectors of a J wrong at 1e-9).
TEST(RkmkPrincipalAxes, AWrongFrameFailsTheComparison) {
  const auto& top = skew_top();
  const State<double> x0 = test::skew_initial_state();
  const Rkmk4<HeavyTop<Jet1>> jet(top.cast<Jet1>());
  const double reflected = principal_against_body_frame(
      MisframedRkmk4<HeavyTop<double>>(top, Vec3<double>(1, 1, -1).asDiagonal()), jet, x0, 0.01, 200);
  const double turned = principal_against_body_frame(
      MisframedRkmk4<HeavyTop<double>>(top, so3::exp(Vec3<double>(1e-9, 0, 0))), jet, x0, 0.01, 200);
  const double right = principal_against_body_frame(
      MisframedRkmk4<HeavyTop<double>>(top, Mat3<double>::Identity()), jet, x0, 0.01, 200);
  std::printf("rkmk4 in principal axes against the body frame over 200 steps: reflected axes %.2e, axes turned by "
              "1e-9 %.2e, the true axes through the same wrapper %.2e\n", reflected, turned, right);
  EXPECT_GT(reflected, 1e-2);
  EXPECT_GT(turned, 1e-10);
  EXPECT_LT(right, 2e-14);  // the bound of StepsEqualTheBodyFrameStepsToRounding
}

TEST(RkmkPrincipalAxes, AdaptiveStepsAndDenseOutputAgree) {
  const auto& top = skew_top();
  const State<double> x0 = test::skew_initial_state();
  adaptive_principal_against_body_frame<RkmkDp5>("rkmk_dp5", top, x0, 0.1, 8e-10);
  adaptive_principal_against_body_frame<RkmkDp8Cayley>("rkmk_dp8_cayley", top, x0, 0.2, 5e-8);
  adaptive_principal_against_body_frame<RkmkVern9>("rkmk_vern9", top, x0, 0.2, 2.5e-4);
  adaptive_principal_against_body_frame<RkmkVern9Cayley>("rkmk_vern9_cayley", top, x0, 0.2, 1.6e-4);
}

TEST(RkmkPrincipalAxes, DiagonalInertiaKeepsTheBodyFrame) {
  const FreeBody<double> body{Vec3<double>(2.0, 1.0, 2.0 / 3).asDiagonal()};
  EXPECT_TRUE(Rkmk4<FreeBody<double>>(body).internal_is_body_frame());
  EXPECT_TRUE(Rkmk4<HeavyTop<double>>(HeavyTop<double>::hairer_vilmart()).internal_is_body_frame());
}

TEST(RkmkPrincipalAxes, ALeverThatDisagreesWithTheTorqueIsRefused) {
  const MislabelledTop bad{skew_top()};
  try {
    Rkmk4<MislabelledTop> s(bad);
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "lgi::Rkmk: the problem's reduced_torque_lever() does not match reduced_torque()");
  }
}

}  // namespace
}  // namespace lgi
