// Adaptive RKMK, measured: the global error follows the tolerance (within 10× across 1e-4 … 1e-12), the
// number of steps falls with the tolerance as the error estimate's order predicts, dense output on the
// group has the continuous extension's order, output times cost no extra steps, and failure (tolerance
// beyond round-off, non-finite torques, step budget) is a status with a finite state.
#include "figures.hpp"
#include "fp_traps.hpp"
#include "order_measure.hpp"
#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/integrators/adaptive.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace lgi {
namespace {

using namespace lgi::test;

static_assert(AdaptiveStepper<RkmkDp5<HeavyTop<double>>>);
static_assert(AdaptiveStepper<RkmkDp8<HeavyTop<double>>>);
static_assert(AdaptiveStepper<RkmkDp8<FreeBody<ceres::Jet<double, 2>>>>);
static_assert(AdaptiveStepper<RkmkVern9<HeavyTop<double>>>);
static_assert(AdaptiveStepper<RkmkVern9Cayley<FreeBody<ceres::Jet<double, 2>>>>);
static_assert(!AdaptiveStepper<Rkmk4<HeavyTop<double>>>);

StepperOptions tolerances(double tol) {
  StepperOptions o;
  o.rtol = tol;
  o.atol = tol;
  return o;
}

// The skew heavy top: its state at `count` equally spaced times up to T from the long-double RK4 reference
// (h = T/(160000 T), error estimated from the run with half the steps).
struct Track {
  std::vector<double> times;
  std::vector<State<L>> states;
  double reference_error = 0;
};
Track make_track(double T, int count) {
  Track tr;
  const int n = static_cast<int>(160'000 * T);
  const auto fine = rk4_embedding_long_double_track(skew_top(), test::skew_initial_state(), T, n, count);
  const auto coarse = rk4_embedding_long_double_track(skew_top(), test::skew_initial_state(), T, n / 2, count);
  for (int i = 0; i < count; ++i) {
    const auto k = static_cast<std::size_t>(i);
    tr.times.push_back(T * (i + 1) / count);
    tr.states.push_back(fine[k]);
    tr.reference_error = std::max(tr.reference_error, distance(fine[k], coarse[k]) / 15);
  }
  std::printf("reference to T = %g (long-double RK4): estimated error %.1e\n", T, tr.reference_error);
  EXPECT_LT(tr.reference_error, 1e-16);
  return tr;
}
const Track& track_2() {
  static const Track t = make_track(2.0, 8);  // t = 0.25, 0.5, …, 2
  return t;
}
const Track& track_10() {
  static const Track t = make_track(10.0, 10);  // t = 1, 2, …, 10
  return t;
}

struct AdaptiveRun {
  AdaptiveSummary summary;
  double final_error = 0;  // at T (landed on by a step)
  double max_error = 0;    // over all output times (dense output before T)
};

template <template <class> class Method>
AdaptiveRun run_skew(const Track& track, double tol, double h0 = 0.01, const AdaptiveOptions& options = {}) {
  Method<HeavyTop<double>> stepper(skew_top(), tolerances(tol));
  State<double> x = test::skew_initial_state();
  AdaptiveRun run;
  std::size_t i = 0;
  auto observe = [&](double t, const State<double>& xt) {
    if (t == 0) return;
    EXPECT_EQ(t, track.times[i]);
    run.max_error = std::max(run.max_error, distance(xt.cast<L>(), track.states[i]));
    ++i;
  };
  run.summary = integrate_adaptive(stepper, x, 0.0, h0, std::span<const double>(track.times), observe, options);
  EXPECT_EQ(run.summary.status, RunStatus::completed);
  EXPECT_EQ(i, track.times.size());
  run.final_error = distance(x.cast<L>(), track.states.back());
  return run;
}

// Acceptance: the global error at every output time (dense output on the group between steps) within 10×
// of the tolerance, rtol = atol = tol = 1e-4 … 1e-12, over T = 2 (the horizon of the order tests). Each pair is
// held to ≈ 4× its own largest error/tol (`bound`), and Verner's pairs, whose error falls far below tol until
// round-off takes over at 1e-11, also over tol = 1e-4 … 1e-10 (`bound_to_1e10`).
template <template <class> class Method>
void meets_tolerance(const char* name, double bound, double bound_to_1e10 = 10) {
  double worst = 0, worst_to_1e10 = 0;
  for (int e = 4; e <= 12; ++e) {
    const double tol = std::pow(10.0, -e);
    const AdaptiveRun run = run_skew<Method>(track_2(), tol);
    std::printf("%s T = 2, tol %.0e: accepted %4lld rejected %2lld, max error over t = 0.25 … 2: %.2e (%.3f tol)\n", name,
                tol, static_cast<long long>(run.summary.accepted), static_cast<long long>(run.summary.rejected),
                run.max_error, run.max_error / tol);
    EXPECT_LE(run.max_error, 10 * tol) << name << " tol " << tol;
    worst = std::max(worst, run.max_error / tol);
    if (e <= 10) worst_to_1e10 = std::max(worst_to_1e10, run.max_error / tol);
  }
  test::expect_figure(std::string("global error / tol over T = 2, tol = 1e-4 ... 1e-12, ") + name, worst, bound);
  if (bound_to_1e10 < 10)
    test::expect_figure(std::string("global error / tol over T = 2, tol = 1e-4 ... 1e-10, ") + name, worst_to_1e10,
                        bound_to_1e10);
}

TEST(Adaptive, Dp5MeetsTheTolerance) { meets_tolerance<RkmkDp5>("rkmk_dp5", 10); }
TEST(Adaptive, Dp8MeetsTheTolerance) { meets_tolerance<RkmkDp8>("rkmk_dp8", 6); }
TEST(Adaptive, Dp5CayleyMeetsTheTolerance) { meets_tolerance<RkmkDp5Cayley>("rkmk_dp5_cayley", 6); }
TEST(Adaptive, Dp8CayleyMeetsTheTolerance) { meets_tolerance<RkmkDp8Cayley>("rkmk_dp8_cayley", 6); }
TEST(Adaptive, Vern9MeetsTheTolerance) { meets_tolerance<RkmkVern9>("rkmk_vern9", 1, 0.1); }
TEST(Adaptive, Vern9CayleyMeetsTheTolerance) { meets_tolerance<RkmkVern9Cayley>("rkmk_vern9_cayley", 0.5, 0.045); }

// Over T = 10 the steps grow in number and the error per step adds up: the number of accepted steps falls
// with the tolerance as tol^(−1/k) (k = the estimate's order: 5 for DP5, 8 for DOP853), fitted over the
// asymptotic range tol = 1e-6 … 1e-12 (the fit over 1e-4 … 1e-12 is printed too: at 1e-4 DOP853 takes 13
// steps over T = 10, far from asymptotic), and the global error stays proportional to the tolerance (its ratio
// to tol varies by less than 10× over tol = 1e-6 … 1e-12).
// Finding: over this longer horizon DP5's error exceeds 10× tol — 33 … 46× (DOP853: 2 … 7×): error-per-step
// control bounds the local error (scaled RMS ≤ 1, with sc = atol + rtol|y| ≈ 2 tol per component), and on
// this top the local errors of 40 … 600 steps add up and grow. The ratio is asserted below 60 (DP5) and 10
// (DOP853, Verner 9(8)), so that a regression of the controller shows; the 10× acceptance holds over T = 2 (above).
// The step size is compared with the fixed-step order through the median accepted step, not the count: the
// count carries a fixed overhead — the ramp from h0 = 0.01 and the landing on T — that weighs 10 % of Verner
// 9(8)'s 19 steps at tol 1e-6 and 3 % of its 67 at 1e-12 and flattens its count slope to −0.091 (−0.095 counting
// only the steps after t = 1), where its median step goes as tol^0.0995; DOP853: count −0.109, median 0.115.
// (Verner 9(8)'s estimate behaves like h^9.5 at these steps, h = 0.14 … 0.55 — local slopes 9.1 … 10.4 along the
// trajectory —, its fixed-step error like h^9.3: the h^10 terms are still large there.)
template <template <class> class Method>
double median_step(double tol) {
  Method<HeavyTop<double>> stepper(skew_top(), tolerances(tol));
  State<double> x = test::skew_initial_state();
  std::vector<double> t;
  AdaptiveOptions every_step;
  every_step.every = 1;
  const double T[] = {10.0};
  integrate_adaptive(stepper, x, 0.0, 0.01, std::span<const double>(T),
                     [&](double ti, const State<double>&) { t.push_back(ti); }, every_step);
  std::vector<double> h;
  for (std::size_t i = 1; i < t.size(); ++i) h.push_back(t[i] - t[i - 1]);
  std::nth_element(h.begin(), h.begin() + static_cast<std::ptrdiff_t>(h.size() / 2), h.end());
  return h[h.size() / 2];
}

// Returns the largest error/tol over t = 1 … 10 at each tol = 1e-4 … 1e-12.
template <template <class> class Method>
std::vector<double> steps_follow_the_order(const char* name, double max_ratio, double max_spread = 10.0) {
  std::vector<double> tols, steps, ratios, medians, each_ratio;
  double worst_ratio = 0;
  for (int e = 4; e <= 12; ++e) {
    const double tol = std::pow(10.0, -e);
    const AdaptiveRun run = run_skew<Method>(track_10(), tol);
    std::printf("%s T = 10, tol %.0e: accepted %4lld rejected %2lld, error at T: %.2e (%.2f tol), max over t = 1 … "
                "10: %.2e (%.2f tol)\n",
                name, tol, static_cast<long long>(run.summary.accepted), static_cast<long long>(run.summary.rejected),
                run.final_error, run.final_error / tol, run.max_error, run.max_error / tol);
    tols.push_back(tol);
    steps.push_back(static_cast<double>(run.summary.accepted));
    medians.push_back(median_step<Method>(tol));
    if (e >= 6) ratios.push_back(run.max_error / tol);
    each_ratio.push_back(run.max_error / tol);
    worst_ratio = std::max(worst_ratio, run.max_error / tol);
  }
  const double slope_all = test::fitted_order(tols, steps);
  const std::vector<double> tols6(tols.begin() + 2, tols.end()), steps6(steps.begin() + 2, steps.end());
  const double slope = test::fitted_order(tols6, steps6);
  const std::vector<double> medians6(medians.begin() + 2, medians.end());
  const double slope_median = test::fitted_order(tols6, medians6);
  const double k = Method<HeavyTop<double>>::control_order;
  const double spread = *std::max_element(ratios.begin(), ratios.end()) / *std::min_element(ratios.begin(), ratios.end());
  // The method's effective order at these step sizes: fixed steps h = T/N with the N the adaptive runs took
  // (tol 1e-6 … 1e-12), error at T against the reference. Where the step count follows the error behaviour,
  // steps ∝ tol^(−1/p_eff).
  std::vector<double> hs, errors;
  for (std::size_t i = 2; i < steps.size(); ++i) {
    Method<HeavyTop<double>> fixed(skew_top());
    State<double> x = test::skew_initial_state();
    const double h = 10.0 / steps[i];
    integrate_to(fixed, x, 0.0, h, 10.0);
    hs.push_back(h);
    errors.push_back(distance(x.cast<L>(), track_10().states.back()));
  }
  const double p_eff = test::fitted_order(hs, errors);
  std::printf("%s: accepted steps ∝ tol^%.4f over 1e-6 … 1e-12 (tol^%.4f over 1e-4 … 1e-12), median step ∝ "
              "tol^%.4f; predicted by the estimate's order −1/%d = %.4f, by the fixed-step order at the same steps "
              "(h = %.3g … %.3g: %.2f) %.4f; error/tol spread over 1e-6 … 1e-12: %.2f, largest error/tol %.1f\n",
              name, slope, slope_all, slope_median, static_cast<int>(k), -1.0 / k, hs.front(), hs.back(), p_eff,
              -1.0 / p_eff, spread, worst_ratio);
  EXPECT_NEAR(slope, -1.0 / k, 0.2 / k) << name;
  EXPECT_NEAR(slope_median, 1.0 / p_eff, 0.1 / p_eff) << name;
  EXPECT_LT(spread, max_spread) << name;
  EXPECT_LT(worst_ratio, max_ratio) << name;
  return each_ratio;
}

TEST(Adaptive, Dp5StepsFollowItsOrder) { steps_follow_the_order<RkmkDp5>("rkmk_dp5", 60); }
TEST(Adaptive, Dp8StepsFollowItsOrder) { steps_follow_the_order<RkmkDp8>("rkmk_dp8", 10); }
TEST(Adaptive, Dp5CayleyStepsFollowItsOrder) { steps_follow_the_order<RkmkDp5Cayley>("rkmk_dp5_cayley", 60); }
// The Cayley pair's global error over T = 10 is up to 13.0× tol (measured; the exponential chart's 2 … 7×): the
// same finding as above with larger error constants. Guarded at 20 so that a regression shows.
TEST(Adaptive, Dp8CayleyStepsFollowItsOrder) { steps_follow_the_order<RkmkDp8Cayley>("rkmk_dp8_cayley", 20); }
// Verner 9(8) in the exponential chart keeps its dexp⁻¹ series to ad⁸ (integrators/rkmk.hpp), a term the error estimate
// cannot see. Cut at ad⁶, that term held the error at T near 1.0 … 3.0 tol from 1e-9 to 1e-12 (1.40, 2.05, 2.46, 2.99);
// kept, it falls to 0.46 … 0.83 tol there (2.5 … 6.5× less); from 1e-4 to 1e-7, where the steps' own error dominates,
// the two agree within 15 % (1e-8: 1.18 against 1.58). Its errors then fall faster than tol (the fixed-step order at
// these steps is 9.8 against the estimate's 9: error/tol ∝ tol^−0.11, 4.5× over 1e-6 … 1e-12), and with 19 steps at
// 1e-6 (5.2 tol) the spread is 11.2: held below 15 here, and the tight tolerances below 1.
TEST(Adaptive, Vern9StepsFollowItsOrder) {
  const std::vector<double> ratio = steps_follow_the_order<RkmkVern9>("rkmk_vern9", 10, 15);
  for (int e = 9; e <= 12; ++e) EXPECT_LT(ratio[static_cast<std::size_t>(e - 4)], 1.0) << "tol 1e-" << e;
}
TEST(Adaptive, Vern9CayleyStepsFollowItsOrder) { steps_follow_the_order<RkmkVern9Cayley>("rkmk_vern9_cayley", 10); }

// Dense output on the group has the continuous extension's order q: one step of size h from the exact
// initial state, read at θ = 1/2, is off the exact solution by O(h^(q+1)) (4 for DP5 → 5; 7 for DOP853 → 8),
// while the step itself is off by O(h^(p+1)). DOP853 runs in long double (its dense errors reach 1e-16).
// The dense attitude stays on SO(3) to round-off. It is R0 Q (1 + R0 Q Δ) Qᵀ: the step runs in principal axes
// (the skew top's J is not diagonal; Q orthogonal), and Δ = F − I, F = exp or cay of the interpolated u (|u| ≤ 0.15
// in the double runs). Each rounded product adds 2‖δR‖_F to ‖RᵀR − I‖_F (first order), and the first-order bound is
//   ‖RᵀR − I‖_F ≤ ‖R0ᵀR0 − I‖_F + 2 · 2 · 9u                the frames R0 Q and R_p Qᵀ (3-term dot products of unit
//                                                              rows and columns: ≤ 3u an entry, u = ε/2)
//                + 2u(√3 + 3√3 ‖Δ‖_F) + 0.5ε + 0.2ε        the update R_p + R_p Δ (‖Δ‖_F ≤ 0.22), Δ's entries and its
//                                                              coefficients ((2B − A² − θ²B²)·√2 θ²)
//              = ‖R0ᵀR0 − I‖_F + 21.6ε
// (a long-double run rounded to double: 2u√3 ≈ 1.7ε instead of the update's terms). Both sides are evaluated in long
// double, so that the measurement adds nothing of its own (in double RᵀR − I carries ≈ ε an entry); the largest
// excess measured is printed.
inline double orthogonality_error_exact(const Mat3<double>& R) {
  return static_cast<double>(so3::orthogonality_error(Mat3<L>(R.cast<L>())));
}

template <template <class> class Method, class T>
void dense_order(const char* name, int dense_order_q, std::initializer_list<double> steps) {
  using P = HeavyTop<T>;
  const State<double> x0 = test::skew_initial_state();
  Method<P> stepper(skew_top().cast<T>(), tolerances(1e-6));
  std::vector<double> hs, mid, end;
  const double e0 = orthogonality_error_exact(x0.R);
  double worst_added = 0;  // the dense attitudes' ‖RᵀR − I‖ above the initial attitude's (e0), in ε
  for (const double h : steps) {
    typename Method<P>::Dense d;
    State<T> x1;
    double err = 0;
    // attempt and dense_output work on the stepper's internal state (principal axes for this J: rkmk.hpp)
    ASSERT_EQ(stepper.attempt(stepper.to_internal(x0.cast<T>(), T(0)), T(0), T(h), x1, err, d), StepStatus::ok);
    x1 = stepper.to_state(x1);
    const State<T> xm = stepper.to_state(stepper.dense_output(d, T(0.5)));
    const State<L> ref_mid = rk4_embedding_long_double(skew_top(), x0, h / 2, 20000);
    const State<L> ref_end = rk4_embedding_long_double(skew_top(), x0, h, 40000);
    hs.push_back(h);
    mid.push_back(distance(xm.template cast<L>(), ref_mid));
    end.push_back(distance(x1.template cast<L>(), ref_end));
    const double e = orthogonality_error_exact(Mat3<double>(xm.R.template cast<double>()));
    worst_added = std::max(worst_added, (e - e0) / std::numeric_limits<double>::epsilon());
    EXPECT_LT(e, e0 + 21.6 * std::numeric_limits<double>::epsilon())
        << name << ", h = " << h << ": initial attitude's defect " << e0;
  }
  const double q = test::fitted_order(hs, mid), p = test::fitted_order(hs, end);
  std::printf("%s: dense output at θ = 1/2: local error ∝ h^%.3f (%.2e … %.2e; dense order %d); step end ∝ h^%.3f "
              "(order %d); ‖RᵀR − I‖ at most %.2f ε above the initial attitude's\n",
              name, q, mid.front(), mid.back(), dense_order_q, p, Method<HeavyTop<double>>::traits.order, worst_added);
  EXPECT_NEAR(q, dense_order_q + 1, 0.2) << name;
}

TEST(Adaptive, DenseOutputOrderDp5) {
  static_assert(tableaus::dormand_prince5.dense_order == 4);
  dense_order<RkmkDp5, double>("rkmk_dp5", 4, {0.1, 0.07, 0.05, 0.035, 0.025, 0.018, 0.0125});
}
TEST(Adaptive, DenseOutputOrderDp8) {
  static_assert(tableaus::dop853.dense_order == 7);
  dense_order<RkmkDp8, long double>("rkmk_dp8", 7, {0.3, 0.25, 0.2, 0.16, 0.13, 0.1, 0.08, 0.065});
}
// In Cayley coordinates the continuous extension is applied to u the same way (R_n cay(u(θh))): same orders.
TEST(Adaptive, DenseOutputOrderCayley) {
  dense_order<RkmkDp5Cayley, double>("rkmk_dp5_cayley", 4, {0.1, 0.07, 0.05, 0.035, 0.025, 0.018, 0.0125});
  // DOP853-Cayley over h = 0.3 … 0.065 fits 8.22 (pre-asymptotic at the large steps): measured from h = 0.2 down
  dense_order<RkmkDp8Cayley, long double>("rkmk_dp8_cayley", 7, {0.2, 0.16, 0.13, 0.1, 0.08, 0.065, 0.05});
}

// Verner 9(8)'s order-9 interpolant, measured like DOP853's (long double, θ = 1/2), cannot show its h^10: from
// h = 0.6 to 0.25 its local error falls like h^12.2 (exponential chart) and h^11.1 (Cayley), from 1e-8 to 2e-13 —
// faster than h^10, the order-10 error terms still dominated by higher ones — and from h ≈ 0.16 on it sits on a
// floor proportional to h, 5.3e-14 h: the interpolant's coefficients (up to 1.07e4) rounded to doubles leave its
// first condition Σ_i b_i(1/2) = 1/2 off by r₁ = 2.0e-14 (tests/integrators/test_rkmk_family.cpp, OrderConditions), and
// h r₁ (U₁, V₁) = h r₁ (Ω₀, Ω₀') is that floor. Measured here: the slope above the floor (at least the h^10 of an
// order-9 interpolant) and the floor itself, err/h at h ≤ 0.065 against |r₁| (|Ω₀| + |Ω₀'|) within 5 %.
// (DOP853's r₁ at 1/2 is 1.4e-15: its floor, 1.4e-16 at h = 0.04, lies below the window it is measured in.)
template <template <class> class Method>
void dense_floor(const char* name) {
  using P = HeavyTop<L>;
  const State<double> x0 = test::skew_initial_state();
  Method<P> stepper(skew_top().cast<L>(), tolerances(1e-6));
  std::vector<double> hs, errors, small_h;
  for (double h = 0.6; h > 0.03; h /= 1.25) {
    typename Method<P>::Dense d;
    State<L> x1;
    double err = 0;
    ASSERT_EQ(stepper.attempt(stepper.to_internal(x0.cast<L>(), L(0)), L(0), L(h), x1, err, d), StepStatus::ok);
    const double e = distance(stepper.to_state(stepper.dense_output(d, L(0.5))),
                              rk4_embedding_long_double(skew_top(), x0, h / 2, 20000));
    if (h >= 0.245) {
      hs.push_back(h);
      errors.push_back(e);
    }
    if (h <= 0.065) small_h.push_back(e / h);
  }
  // r₁ = Σ_i b_i(1/2) − 1/2 of the double coefficients, in long double; (Ω₀, Ω₀') of the first stage
  long double r1 = -0.5L;
  for (const auto& row : tableaus::verner9.dense) {
    long double p = 0;
    for (int m = tableaus::verner9.dense_degree - 1; m >= 0; --m) p = p * 0.5L + row[static_cast<std::size_t>(m)];
    r1 += p * 0.5L;
  }
  const auto top = skew_top();
  const Vec3<double> W = x0.Omega;
  const Vec3<double> dW = top.inertia.inverse() * Vec3<double>((top.inertia * W).cross(W) + top.torque(x0.R));
  const double floor = std::abs(static_cast<double>(r1)) * (W.norm() + dW.norm());
  const double q = test::fitted_order(hs, errors);
  std::printf("%s: dense output at θ = 1/2: local error ∝ h^%.3f over h = %.3g … %.3g (%.2e … %.2e); below h = 0.065 "
              "err/h = %.3e … %.3e, |r1| (|W0| + |W0'|) = %.3e (r1 = %.2Le)\n",
              name, q, hs.front(), hs.back(), errors.front(), errors.back(), small_h.front(), small_h.back(), floor, r1);
  EXPECT_GT(q, 10 - 0.2) << name;
  for (const double f : small_h) EXPECT_NEAR(f, floor, 0.05 * floor) << name;
}

TEST(AdaptiveFindings, DenseOutputVern9PreAsymptoticThenRoundingFloor) {
  static_assert(tableaus::verner9.dense_order == 9);
  dense_floor<RkmkVern9>("rkmk_vern9");
  dense_floor<RkmkVern9Cayley>("rkmk_vern9_cayley");
}

// Output times are read from the dense output: asking for 100 of them changes neither the steps taken nor
// the final state (bit for bit), and every output is on SO(3) to round-off.
TEST(Adaptive, OutputTimesCostNoSteps) {
  const double T = 10;
  std::vector<double> many;
  for (int i = 1; i <= 100; ++i) many.push_back(0.1 * i - 0.0371);
  many.push_back(T);
  const double end_only[] = {T};
  RkmkDp5<HeavyTop<double>> a(skew_top(), tolerances(1e-8)), b(skew_top(), tolerances(1e-8));
  State<double> xa = test::skew_initial_state(), xb = xa;
  double worst_orthogonality = 0;
  int outputs = 0;
  const auto sa = integrate_adaptive(a, xa, 0.0, 0.01, std::span<const double>(end_only));
  const auto sb = integrate_adaptive(b, xb, 0.0, 0.01, std::span<const double>(many), [&](double, const State<double>& x) {
    ++outputs;
    worst_orthogonality = std::max(worst_orthogonality, so3::orthogonality_error(x.R));
  });
  EXPECT_EQ(sa.accepted, sb.accepted);
  EXPECT_EQ(sa.rejected, sb.rejected);
  EXPECT_EQ(xa.R, xb.R);
  EXPECT_EQ(xa.Omega, xb.Omega);
  EXPECT_EQ(outputs, 102);  // t = 0, the 100 times, T
  EXPECT_LT(worst_orthogonality, 1e-14);
  EXPECT_LT(sb.accepted, 150);  // ≈ 100 steps: outputs are not steps
  std::printf("rkmk_dp5 tol 1e-8: %lld accepted steps with or without 100 output times\n",
              static_cast<long long>(sb.accepted));
}

// options.every = N: an output after every N-th accepted step, besides the requested times.
TEST(Adaptive, EveryNAcceptedSteps) {
  RkmkDp5<HeavyTop<double>> stepper(skew_top(), tolerances(1e-8));
  State<double> x = test::skew_initial_state();
  const double times[] = {10.0};
  std::vector<double> seen;
  AdaptiveOptions options;
  options.every = 7;
  const auto s = integrate_adaptive(stepper, x, 0.0, 0.01, std::span<const double>(times),
                                    [&](double t, const State<double>&) { seen.push_back(t); }, options);
  EXPECT_EQ(static_cast<std::int64_t>(seen.size()), 1 + s.accepted / 7 + (s.accepted % 7 != 0 ? 1 : 0));
  EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
  EXPECT_EQ(seen.back(), 10.0);
}

// A huge first step is rejected and retried; the run still meets the tolerance.
TEST(Adaptive, RejectedStepsRecover) {
  const AdaptiveRun run = run_skew<RkmkDp5>(track_2(), 1e-8, /*h0=*/1.5);
  std::printf("rkmk_dp5 h0 = 1.5: %lld rejected, %lld accepted, max error %.2e\n",
              static_cast<long long>(run.summary.rejected), static_cast<long long>(run.summary.accepted), run.max_error);
  EXPECT_GE(run.summary.rejected, 1);
  EXPECT_LE(run.max_error, 10 * 1e-8);
}

// A step-size floor the tolerance cannot live with: the controller drives h down to it and the run ends
// with a status, the state the last accepted one, finite.
TEST(Adaptive, StepSizeFloorIsAStatus) {
  RkmkDp5<HeavyTop<double>> stepper(skew_top(), tolerances(1e-12));
  State<double> x = test::skew_initial_state();
  const double times[] = {1.0};
  AdaptiveOptions options;
  options.h_min = 0.1;  // tol 1e-12 needs h ≈ 0.015
  const auto s = integrate_adaptive(stepper, x, 0.0, 0.2, std::span<const double>(times), NoObserver{}, options);
  EXPECT_EQ(s.status, RunStatus::step_failed);
  EXPECT_EQ(s.step_status, StepStatus::step_size_underflow);
  EXPECT_TRUE(is_finite(x));
  EXPECT_LT(s.t, 1.0);
  std::printf("h_min 0.1, tol 1e-12: %s after %lld accepted, %lld rejected steps at t = %.3g\n",
              std::string(to_string(s.step_status)).c_str(), static_cast<long long>(s.accepted),
              static_cast<long long>(s.rejected), s.t);
}

// A torque that turns NaN at t = 0.5: every trial step across it is rejected, h shrinks to its floor, the
// run ends there with status non_finite and the last finite state — never a NaN.
struct PoisonedTop {
  using Scalar = double;
  static constexpr std::string_view name = "poisoned_top";
  static constexpr bool has_torque = true;
  HeavyTop<double> top = test::skew_heavy_top();
  Mat3<double> inertia = top.inertia;
  double potential(const Mat3<double>& R) const { return top.potential(R); }
  Vec3<double> torque(const double& t, const Mat3<double>& R) const {
    return t > 0.5 ? Vec3<double>::Constant(std::numeric_limits<double>::quiet_NaN()) : top.torque(R);
  }
  static constexpr std::array<std::string_view, 0> invariant_names{};
  std::array<double, 0> invariants(const State<double>&) const { return {}; }
};

TEST(Adaptive, NonFiniteTorqueIsAStatus) {
  const test::FpTrapsOff traps_off;  // the torque is NaN on purpose: the controller must see it as a status
  RkmkDp5<PoisonedTop> stepper(PoisonedTop{}, tolerances(1e-8));
  State<double> x = test::skew_initial_state();
  const double times[] = {1.0};
  const auto s = integrate_adaptive(stepper, x, 0.0, 0.01, std::span<const double>(times));
  EXPECT_EQ(s.status, RunStatus::step_failed);
  EXPECT_EQ(s.step_status, StepStatus::non_finite);
  EXPECT_TRUE(is_finite(x));
  EXPECT_NEAR(s.t, 0.5, 1e-6);
}

// The step budget ends a run with RunStatus::stopped.
TEST(Adaptive, StepBudgetIsAStatus) {
  RkmkDp8<HeavyTop<double>> stepper(skew_top(), tolerances(1e-10));
  State<double> x = test::skew_initial_state();
  const double times[] = {10.0};
  AdaptiveOptions options;
  options.max_steps = 5;
  const auto s = integrate_adaptive(stepper, x, 0.0, 0.01, std::span<const double>(times), NoObserver{}, options);
  EXPECT_EQ(s.status, RunStatus::stopped);
  EXPECT_EQ(s.accepted + s.rejected, 5);
  EXPECT_TRUE(is_finite(x));
}

// Bad arguments are exceptions before anything runs.
TEST(Adaptive, BadArguments) {
  RkmkDp5<HeavyTop<double>> no_tolerance(skew_top());
  State<double> x = test::skew_initial_state();
  const double times[] = {1.0};
  EXPECT_THROW(integrate_adaptive(no_tolerance, x, 0.0, 0.01, std::span<const double>(times)), std::invalid_argument);
  // below round-off: rejected like DOPRI5 does (rtol ≥ 10 ε); measured without the check, rtol = atol = 1e-22
  // "succeeded" with 1e5 steps of h ≈ 1e-5, the estimate blind to the round-off of the solution itself
  RkmkDp5<HeavyTop<double>> beyond(skew_top(), tolerances(1e-22));
  EXPECT_THROW(integrate_adaptive(beyond, x, 0.0, 0.01, std::span<const double>(times)), std::invalid_argument);
  RkmkDp5<HeavyTop<double>> stepper(skew_top(), tolerances(1e-8));
  EXPECT_THROW(integrate_adaptive(stepper, x, 0.0, -0.01, std::span<const double>(times)), std::invalid_argument);
  const double backwards[] = {1.0, 0.5};
  EXPECT_THROW(integrate_adaptive(stepper, x, 0.0, 0.01, std::span<const double>(backwards)), std::invalid_argument);
}

// Jets through an adaptive run: the step sizes follow the values (the derivative of the trajectory for the
// chosen step sequence). Against central differences, which also see the steps move with the data, the
// two agree to the order of the tolerance's effect (1e-10 here): 1e-6.
template <template <class> class Method>
void jets_through_an_adaptive_run(double h0) {
  using Jet = ceres::Jet<double, 3>;
  const auto problem = test::skew_heavy_top();
  const State<double> x0 = test::skew_initial_state();
  const double times[] = {1.0, 2.0};
  Method<HeavyTop<Jet>> jet_stepper(problem.cast<Jet>(), tolerances(1e-10));
  State<Jet> xj = x0.cast<Jet>();
  for (int i = 0; i < 3; ++i) xj.Omega[i].v[i] = 1;
  const Jet jt[] = {Jet(1.0), Jet(2.0)};
  const auto sj = integrate_adaptive(jet_stepper, xj, Jet(0), Jet(h0), std::span<const Jet>(jt));
  ASSERT_EQ(sj.status, RunStatus::completed);
  const auto run = [&](const Vec3<double>& d) {
    Method<HeavyTop<double>> stepper(problem, tolerances(1e-10));
    State<double> x = x0;
    x.Omega += d;
    integrate_adaptive(stepper, x, 0.0, h0, std::span<const double>(times));
    return x;
  };
  const State<double> plain = run(Vec3<double>::Zero());
  // The same steps: the double run carries this J's principal axes and the Jet run the body frame (rkmk.hpp), so
  // the two agree to the rounding of the frame change (≤ 1.1e-14 over 200 fixed steps, RkmkPrincipalAxes; 1.3e-14
  // here), where a different step sequence would move Ω by ≈ the tolerance, 1e-10.
  for (int r = 0; r < 3; ++r) EXPECT_NEAR(xj.Omega[r].a, plain.Omega[r], 1e-13);
  const double eps = 1e-6;
  double largest = 0;
  for (int j = 0; j < 3; ++j) {
    const State<double> plus = run(eps * Vec3<double>::Unit(j)), minus = run(-eps * Vec3<double>::Unit(j));
    for (int r = 0; r < 3; ++r) {
      const double fd = (plus.Omega[r] - minus.Omega[r]) / (2 * eps);
      largest = std::max(largest, std::abs(fd));
      EXPECT_NEAR(xj.Omega[r].v[j], fd, 1e-6);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(xj.R(r, c).v[j], (plus.R(r, c) - minus.R(r, c)) / (2 * eps), 1e-6);
    }
  }
  EXPECT_GT(largest, 0.1);
}

TEST(Adaptive, JetsThroughAnAdaptiveRun) { jets_through_an_adaptive_run<RkmkDp8>(0.01); }
// Verner 9(8) from h0 = 0.2: from 0.01 its first estimates (≈ 1e-9 of the tolerance) are round-off, which the Jet run
// computes differently in the last bit (ceres divides by multiplying with the reciprocal), so the two runs choose
// different step sequences (t after 12 steps 1.867 against 1.904) and end 1.2e-14 apart; from 0.2 the
// sequences agree to 4e-6 and the values to 1e-16.
TEST(Adaptive, JetsThroughAnAdaptiveRunVern9) {
  jets_through_an_adaptive_run<RkmkVern9>(0.2);
  jets_through_an_adaptive_run<RkmkVern9Cayley>(0.2);
}

}  // namespace
}  // namespace lgi
