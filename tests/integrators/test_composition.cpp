// Symmetric compositions of the LGVI and of kick + DMV, measured: the coefficient sets (symmetric, Σγ = 1,
// the odd-power order conditions Σγ^(2k+1) = 0), observed orders 4–10 on a free symmetric body (exact
// solution) and on the skew heavy top (long-double reference; orders 8 and 10 of kick + DMV also in long
// double), the two bases' compositions the same maps, time symmetry (step(h) then step(−h) returns), energy
// bounded over long runs with m·k and R on SO(3) to round-off (and a non-symplectic negative control that
// the same test flags), Jets against finite differences.
#include "figures.hpp"
#include "jet_check.hpp"
#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/core/invariants.hpp>
#include <lgi/integrators/commutator_free.hpp>
#include <lgi/integrators/composition.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>
#include <lgi/problems/lagrange_top.hpp>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace lgi {
namespace {

// ---- the coefficient sets as data -------------------------------------------------------------------

// Σγ^k in long double.
template <class C>
long double power_sum(const C& c, int k) {
  long double s = 0;
  for (const long double g : c.gamma) s += std::pow(g, k);
  return s;
}

template <class C>
void check_coefficients(const C& c, long double digits_tolerance) {
  SCOPED_TRACE(std::string(c.name));
  for (std::size_t i = 0; i < c.stages; ++i) EXPECT_EQ(c.gamma[i], c.gamma[c.stages - 1 - i]) << "symmetric";
  EXPECT_LT(std::abs(power_sum(c, 1) - 1.0L), 1e-18L) << "Σγ = 1";
  // The one-vertex trees of HLW Fig. V.3.3: Σγ^(2k+1) = 0 for 2k + 1 < order (a necessary part of the
  // order conditions; the full set is tested by the observed orders below). The tolerance reflects the
  // digits published (26 for most sets, 15 for Yoshida's order 8) times the size of the γ^(2k+1).
  long double largest = 0;
  for (const long double g : c.gamma) largest = std::max(largest, std::abs(g));
  for (int k = 3; k < c.order; k += 2) {
    const long double tol = digits_tolerance * static_cast<long double>(c.stages) * std::pow(largest, k);
    EXPECT_LT(std::abs(power_sum(c, k)), tol) << "Σγ^" << k << " = " << static_cast<double>(power_sum(c, k));
  }
  // The next power does not vanish: the set is not of a higher order by accident.
  EXPECT_GT(std::abs(power_sum(c, c.order + 1)), 1e-6L);
}

TEST(CompositionCoefficients, SymmetricConsistentAndOddPowersVanish) {
  check_coefficients(compositions::yoshida4, 1e-18L);
  check_coefficients(compositions::suzuki4, 1e-18L);
  check_coefficients(compositions::yoshida6, 1e-18L);
  check_coefficients(compositions::kahan_li6, 1e-18L);
  check_coefficients(compositions::yoshida8, 1e-15L);
  check_coefficients(compositions::kahan_li8, 1e-18L);
  check_coefficients(compositions::sofroniou_spaletta10, 1e-18L);
  EXPECT_EQ(compositions::kahan_li8.stages, 17u);
  EXPECT_EQ(compositions::sofroniou_spaletta10.stages, 35u);
}

TEST(CompositionCoefficients, TraitsComeFromBaseAndCoefficients) {
  using S = LgviKahanLi8<HeavyTop<double>>;
  EXPECT_EQ(S::traits.name, "lgvi_kahan_li8");
  EXPECT_EQ(S::traits.order, 8);
  EXPECT_TRUE(S::traits.symplectic && S::traits.symmetric && S::traits.exact_on_group && S::traits.preserves_momentum);
  EXPECT_FALSE(S::traits.explicit_method);
  EXPECT_EQ(S::traits.options, Lgvi<HeavyTop<double>>::traits.options);
  EXPECT_EQ(LgviSofroniouSpaletta10<FreeBody<double>>::traits.name, "lgvi_sofroniou_spaletta10");
  EXPECT_NE(S::traits.reference.find("Kahan"), std::string_view::npos);
  static_assert(Stepper<LgviYoshida4<HeavyTop<double>>>);
  using D = SplitDmvSofroniouSpaletta10<HeavyTop<double>>;
  EXPECT_EQ(D::traits.name, "split_dmv_sofroniou_spaletta10");
  EXPECT_EQ(D::traits.order, 10);
  EXPECT_EQ(D::traits.free_body_order, 0);
  EXPECT_TRUE(D::traits.symplectic && D::traits.symmetric && D::traits.exact_on_group && D::traits.preserves_momentum);
  EXPECT_EQ(SplitDmvYoshida4<FreeBody<double>>::traits.order, 4);
}

// ---- compositions of kick + DMV -------------------------------------------------------------------------

// Kick + DMV and the LGVI are one map (NUMERICS.md), so their compositions agree to round-off (different
// solvers, coordinates and rounding: principal axes, quaternion, fixed point vs body frame, matrix, Newton).
TEST(SplitDmvCompositions, SameMapsAsTheLgviCompositions) {
  const auto top = test::skew_heavy_top();
  const State<double> x0 = test::skew_initial_state();
  const auto distance_after = [&]<class A, class B>(A a, B b) {
    State<double> xa = x0, xb = x0;
    EXPECT_EQ(integrate_to(a, xa, 0.0, 0.05, 5.0).status, RunStatus::completed);
    EXPECT_EQ(integrate_to(b, xb, 0.0, 0.05, 5.0).status, RunStatus::completed);
    return test::state_distance(xa, xb);
  };
  const double d4 = distance_after(SplitDmvYoshida4<HeavyTop<double>>(top), LgviYoshida4<HeavyTop<double>>(top));
  const double d8 = distance_after(SplitDmvKahanLi8<HeavyTop<double>>(top), LgviKahanLi8<HeavyTop<double>>(top));
  const double d10 = distance_after(SplitDmvSofroniouSpaletta10<HeavyTop<double>>(top),
                                    LgviSofroniouSpaletta10<HeavyTop<double>>(top));
  std::printf("split_dmv_* vs lgvi_* after 100 steps of h = 0.05: yoshida4 %.2e, kahan_li8 %.2e, "
              "sofroniou_spaletta10 %.2e\n", d4, d8, d10);
  EXPECT_LT(d4, 1e-13);
  EXPECT_LT(d8, 1e-13);
  EXPECT_LT(d10, 1e-13);
}

// Orders 8 and 10 in long double (the problems cast to long double: every method is a template on the
// scalar), against a long-double reference far below the errors fitted: classical RK4 on the embedding
// (all nine entries of R and Ω, a different method and coordinates), Richardson-extrapolated from 20000 and
// 40000 steps over T = 2; its error is estimated by the same construction from 40000 and 80000 steps and
// printed. On the skew heavy top (non-diagonal J) and on the Hairer–Vilmart free body. In double the errors
// of these methods reach round-off within three or four points.
using L = long double;
template <class P>
State<L> rk4_richardson_ld(const P& p, const State<L>& x0, L T, int n) {
  const auto rk4 = [&](int steps) {
    const Mat3<L> J = p.inertia, J_inv = J.inverse();
    struct Y {
      Mat3<L> R;
      Vec3<L> W;
    };
    const auto f = [&](const Y& y) {
      return Y{y.R * so3::hat(y.W), J_inv * Vec3<L>((J * y.W).cross(y.W) + body_torque(p, L(0), y.R))};
    };
    const auto axpy = [](const Y& y, L a, const Y& k) { return Y{y.R + a * k.R, y.W + a * k.W}; };
    Y y{x0.R, x0.Omega};
    const L h = T / steps;
    for (int i = 0; i < steps; ++i) {
      const Y k1 = f(y), k2 = f(axpy(y, h / 2, k1)), k3 = f(axpy(y, h / 2, k2)), k4 = f(axpy(y, h, k3));
      y.R += (h / 6) * (k1.R + 2 * k2.R + 2 * k3.R + k4.R);
      y.W += (h / 6) * (k1.W + 2 * k2.W + 2 * k3.W + k4.W);
    }
    return State<L>{y.R, y.W};
  };
  const State<L> a = rk4(n), b = rk4(2 * n);
  return {(16 * b.R - a.R) / 15, (16 * b.Omega - a.Omega) / 15};
}
double distance_ld(const State<L>& a, const State<L>& b) {
  return static_cast<double>((a.R - b.R).norm() + (a.Omega - b.Omega).norm());
}

template <template <class> class M, class P>
double observed_order_ld(const char* label, const P& problem, const State<double>& x0_d, const std::vector<int>& ns) {
  using PL = rebind_problem_t<P, L>;
  const PL p = problem.template cast<L>();
  const State<L> x0 = x0_d.cast<L>();
  const L T = 2;
  const State<L> ref = rk4_richardson_ld(p, x0, T, 20000);
  const double ref_error = distance_ld(ref, rk4_richardson_ld(p, x0, T, 40000));
  EXPECT_LT(ref_error, 1e-16);
  std::vector<double> hs, errors;
  for (const int n : ns) {
    M<PL> stepper(p);
    State<L> x = x0;
    EXPECT_EQ(integrate_to(stepper, x, L(0), T / n, T).status, RunStatus::completed);
    hs.push_back(static_cast<double>(T / n));
    errors.push_back(distance_ld(x, ref));
    EXPECT_GT(errors.back(), 1e3 * ref_error) << "error too close to the reference's own";
  }
  const double order = test::fitted_order(hs, errors);
  std::printf("%s %s (long double): observed order %.3f, errors %.3e (n = %d) .. %.3e (n = %d), reference error "
              "%.1e\n",
              std::string(M<PL>::traits.name).c_str(), label, order, errors.front(), ns.front(), errors.back(),
              ns.back(), ref_error);
  return order;
}

TEST(SplitDmvCompositions, OrdersEightAndTenInLongDouble) {
  const auto top = test::skew_heavy_top();
  const auto body = FreeBody<double>::hairer_vilmart();
  // Step counts in the asymptotic range (|Ω(0)| = 1.4 on the skew top, 3.3 on the free body)
  // with every error above 1e3 times the reference's.
  const std::vector<int> n8_top{10, 12, 16, 20, 24, 32}, n10_top{6, 7, 8, 10, 12};
  const std::vector<int> n8_free{24, 32, 40, 48, 64, 80}, n10_free{12, 14, 16, 20, 24};
  EXPECT_NEAR(observed_order_ld<SplitDmvKahanLi8>("skew heavy top", top, test::skew_initial_state(), n8_top), 8.0, 0.2);
  EXPECT_NEAR(
      observed_order_ld<SplitDmvSofroniouSpaletta10>("skew heavy top", top, test::skew_initial_state(), n10_top), 10.0,
      0.2);
  EXPECT_NEAR(observed_order_ld<SplitDmvKahanLi8>("free body", body, test::hairer_vilmart_state(body), n8_free), 8.0,
              0.2);
  EXPECT_NEAR(
      observed_order_ld<SplitDmvSofroniouSpaletta10>("free body", body, test::hairer_vilmart_state(body), n10_free),
      10.0, 0.2);
}

// ---- observed orders ---------------------------------------------------------------------------------

// The free symmetric body J = Q diag(I, I, I3) Qᵀ: elementary exact solution, evaluated in long double
// (see tests/integrators/test_commutator_free.cpp, which also checks it against the long-double RK4 reference).
struct SymmetricBody {
  Mat3<double> Q = so3::exp(Vec3<double>(0.3, -0.2, 0.5));
  double I = 0.8, I3 = 1.3;
  FreeBody<double> problem() const {
    FreeBody<double> p{Q * Vec3<double>(I, I, I3).asDiagonal() * Q.transpose()};
    p.inertia = (0.5 * (p.inertia + p.inertia.transpose())).eval();
    return p;
  }
  State<double> initial() const { return {so3::exp(Vec3<double>(0.2, 0.1, -0.4)), Vec3<double>(0.9, -0.5, 1.2)}; }
  State<double> exact(double t_) const {
    const Mat3<L> q = Q.cast<L>();
    const State<double> x0 = initial();
    const Vec3<L> w = q.transpose() * x0.Omega.cast<L>();
    const L i = I, i3 = I3, t = t_;
    const Vec3<L> M(i * w(0), i * w(1), i3 * w(2));
    const L lambda = (i3 - i) * w(2) / i;
    const Mat3<L> Rp = x0.R.cast<L>() * q * so3::exp(Vec3<L>((t / i) * M)) *
                       so3::exp(Vec3<L>(-lambda * t * Vec3<L>::UnitZ()));
    const Vec3<L> wt = so3::exp(Vec3<L>(lambda * t * Vec3<L>::UnitZ())) * w;
    return {Mat3<L>(Rp * q.transpose()).cast<double>(), Vec3<L>(q * wt).cast<double>()};
  }
};

// Per method: step counts over T = 4 (free body) and T = 2 (skew heavy top), chosen in the asymptotic range
// and with every error above 1e-13 (double round-off over these runs is ≈ 1e-15; the references' own
// errors are below 1e-16).
template <template <class> class Method>
struct Steps;
template <>
struct Steps<LgviYoshida4> {
  static inline const std::vector<int> free{80, 160, 320, 640}, top{40, 80, 160, 320, 640};
};
template <>
struct Steps<LgviSuzuki4> {
  static inline const std::vector<int> free{40, 80, 160, 320, 640}, top{20, 40, 80, 160, 320};
};
template <>
struct Steps<LgviYoshida6> {
  static inline const std::vector<int> free{32, 48, 64, 96, 128}, top{24, 32, 48, 64, 96};
};
template <>
struct Steps<LgviKahanLi6> {
  static inline const std::vector<int> free{24, 32, 48, 64, 96}, top{16, 24, 32, 48, 64};
};
template <>
struct Steps<LgviYoshida8> {
  static inline const std::vector<int> free{96, 128, 192, 256}, top{24, 32, 48, 64, 96};
};
template <>
struct Steps<LgviKahanLi8> {
  static inline const std::vector<int> free{20, 24, 32, 48, 64}, top{10, 12, 16, 20, 24, 32};
};
template <>
struct Steps<LgviSofroniouSpaletta10> {
  static inline const std::vector<int> free{10, 12, 16, 20, 24}, top{6, 8, 10, 12};
};
// Kick + DMV is the LGVI's map: its compositions take the same step counts.
template <>
struct Steps<SplitDmvYoshida4> : Steps<LgviYoshida4> {};
template <>
struct Steps<SplitDmvSuzuki4> : Steps<LgviSuzuki4> {};
template <>
struct Steps<SplitDmvKahanLi6> : Steps<LgviKahanLi6> {};
template <>
struct Steps<SplitDmvKahanLi8> : Steps<LgviKahanLi8> {};
template <>
struct Steps<SplitDmvSofroniouSpaletta10> : Steps<LgviSofroniouSpaletta10> {};

template <template <class> class M, class P>
double observed_order(const char* label, const P& problem, const State<double>& x0, double T, const State<double>& ref,
                      const std::vector<int>& ns) {
  std::vector<double> hs, errors;
  for (const int n : ns) {
    M<P> stepper(problem);
    State<double> x = x0;
    EXPECT_EQ(integrate_to(stepper, x, 0.0, T / n, T).status, RunStatus::completed);
    hs.push_back(T / n);
    errors.push_back(test::state_distance(x, ref));
    EXPECT_GT(errors.back(), 1e-13) << "error too close to round-off or to the reference's own";
  }
  const double p = test::fitted_order(hs, errors);
  std::printf("%s %s: observed order %.3f, errors %.3e (n = %d) .. %.3e (n = %d)\n", std::string(M<P>::traits.name).c_str(), label, p,
              errors.front(), ns.front(), errors.back(), ns.back());
  return p;
}

template <class C>
class CompositionTest : public ::testing::Test {};
template <template <class> class Method>
struct Tag {
  template <class P>
  using type = Method<P>;
  using steps = Steps<Method>;
};
using Compositions = ::testing::Types<Tag<LgviYoshida4>, Tag<LgviSuzuki4>, Tag<LgviYoshida6>, Tag<LgviKahanLi6>,
                                      Tag<LgviYoshida8>, Tag<LgviKahanLi8>, Tag<LgviSofroniouSpaletta10>,
                                      Tag<SplitDmvYoshida4>, Tag<SplitDmvSuzuki4>, Tag<SplitDmvKahanLi6>,
                                      Tag<SplitDmvKahanLi8>, Tag<SplitDmvSofroniouSpaletta10>>;
TYPED_TEST_SUITE(CompositionTest, Compositions);

TYPED_TEST(CompositionTest, ObservedOrderOnTheFreeBody) {
  const SymmetricBody body;
  const int order = TypeParam::template type<FreeBody<double>>::traits.order;
  const double p = observed_order<TypeParam::template type>("free body", body.problem(), body.initial(), 4.0,
                                                            body.exact(4.0), TypeParam::steps::free);
  EXPECT_NEAR(p, order, 0.2);
}

TYPED_TEST(CompositionTest, ObservedOrderOnTheSkewHeavyTop) {
  const auto top = test::skew_heavy_top();
  const State<double> x0 = test::skew_initial_state();
  static const State<double> ref = test::reference_solution(top, x0, 2.0, 100000);
  ASSERT_LT(test::state_distance(ref, test::reference_solution(top, x0, 2.0, 50000)), 1e-15);
  const int order = TypeParam::template type<HeavyTop<double>>::traits.order;
  const double p = observed_order<TypeParam::template type>("skew heavy top", top, x0, 2.0, ref, TypeParam::steps::top);
  EXPECT_NEAR(p, order, 0.2);
}

// ---- time symmetry -------------------------------------------------------------------------------------

// Ψ_{−h} ∘ Ψ_h = id: one step forward and one back return to the start to round-off (the LGVI's Newton
// tolerance is 1e-14). CF4, not symmetric, does not (negative control: the same check fails by O(h⁵)).
template <class S>
double back_and_forth(double h) {
  const auto top = test::skew_heavy_top();
  S stepper(top);
  const State<double> x0 = test::skew_initial_state();
  auto y = stepper.to_internal(x0, 0.0);
  EXPECT_EQ(stepper.step(y, 0.0, h), StepStatus::ok);
  EXPECT_EQ(stepper.step(y, h, -h), StepStatus::ok);
  return test::state_distance(stepper.to_state(y), x0);
}

TYPED_TEST(CompositionTest, StepBackwardsReturnsToTheStart) {
  using S = typename TypeParam::template type<HeavyTop<double>>;
  const double d = back_and_forth<S>(0.1);
  std::printf("%s: |step(-h) o step(h) - id| = %.3e at h = 0.1\n", std::string(S::traits.name).c_str(), d);
  EXPECT_LT(d, 1e-13);
}

TEST(CompositionSymmetry, NegativeControlCf4IsNotSymmetric) {
  const double d = back_and_forth<Cf4<HeavyTop<double>>>(0.1);
  std::printf("cf4: |step(-h) o step(h) - id| = %.3e at h = 0.1\n", d);
  EXPECT_GT(d, 1e-8);
}

// ---- long runs: energy bounded, m·k and R to round-off --------------------------------------------------

struct LongRun {
  double drift_slope;       // slope of log(max |energy error| in a window) against log t, equal windows
  double energy;            // largest relative energy error
  double momentum;          // largest |m·k − m·k(0)| / |m|
  double orthogonality;     // largest ‖RᵀR − I‖ over the run
  double orthogonality_1e6; // largest ‖RᵀR − I‖ over the first 10⁶ steps
};

// n steps of h on the Hairer–Vilmart heavy top, sampled every n/20000 steps. The drift slope fits
// log max|ΔE| over 64 equal windows of the run (the first left out) against log of the window's middle
// time: ≈ 0 for a bounded error, → 1 for a linear drift, ≈ 0.5 for a random walk. (Windows of growing
// length would bias a bounded quasi-periodic error upwards: a longer window sees more extreme phases —
// measured 0.12–0.15 with doubling windows on runs whose equal-window slope is 0.000.)
template <template <class> class Method>
LongRun long_run(double h, std::int64_t n) {
  const auto problem = HeavyTop<double>::hairer_vilmart();
  const State<double> x0 = test::hairer_vilmart_state(problem);
  const double E0 = energy(problem, x0), mk0 = problem.invariants(x0)[0];
  const double m0 = spatial_momentum(problem.inertia, x0).norm();
  const double T = h * static_cast<double>(n);
  constexpr int windows = 64;
  std::vector<double> window_max(windows, 0.0);
  LongRun r{0, 0, 0, 0, 0};
  auto observe = [&](double t, const State<double>& x) {
    const double e = std::abs(energy(problem, x) - E0) / std::abs(E0);
    r.energy = std::max(r.energy, e);
    r.momentum = std::max(r.momentum, std::abs(problem.invariants(x)[0] - mk0) / m0);
    const double orth = so3::orthogonality_error(x.R);
    r.orthogonality = std::max(r.orthogonality, orth);
    if (t <= h * 1e6 * (1 + 1e-12)) r.orthogonality_1e6 = std::max(r.orthogonality_1e6, orth);
    const int k = std::min(windows - 1, static_cast<int>(t / T * windows));
    window_max[static_cast<std::size_t>(k)] = std::max(window_max[static_cast<std::size_t>(k)], e);
  };
  Method<HeavyTop<double>> stepper(problem);
  State<double> x = x0;
  const auto summary = integrate_every(stepper, x, 0.0, h, T, std::max<std::int64_t>(1, n / 20000), observe);
  EXPECT_EQ(summary.status, RunStatus::completed);
  std::vector<double> ts, es;
  for (int k = 1; k < windows; ++k) {
    ts.push_back((k + 0.5) * T / windows);
    es.push_back(window_max[static_cast<std::size_t>(k)]);
  }
  r.drift_slope = test::fitted_order(ts, es);
  std::printf("%s %lld steps h=%g (t = %g): energy drift slope %.3f, max rel. energy error %.3e, max m.k error / |m| "
              "%.3e, max |RtR-I| %.3e (first 1e6 steps %.3e)\n",
              std::string(Method<HeavyTop<double>>::traits.name).c_str(), static_cast<long long>(n), h, T,
              r.drift_slope, r.energy, r.momentum, r.orthogonality, r.orthogonality_1e6);
  return r;
}

// No drift, m·k to round-off, and ‖RᵀR − I‖ the random walk of R's updates (figures.hpp): each stage of a
// composition of the LGVI updates R, so n steps are n·stages updates. A composition of split_dmv carries a unit
// quaternion, normalised at every stage, whose R is within a few ε of SO(3) however long the run: held to 32 ε.
enum class Attitude { matrix, quaternion };
template <template <class> class Method>
void expect_geometric(const LongRun& r, std::int64_t n, Attitude attitude = Attitude::matrix) {
  using M = Method<HeavyTop<double>>;
  const std::string name(M::traits.name);
  const double stages = static_cast<double>(M::coefficients.stages);
  const double eps = std::numeric_limits<double>::epsilon();
  EXPECT_LT(std::abs(r.drift_slope), 0.1);
  test::expect_figure("m.k error / |m| over a long run, " + name, r.momentum, 5e-13);
  const bool quaternion = attitude == Attitude::quaternion;
  test::expect_figure("|RtR - I| after min(n, 1e6) steps, " + name, r.orthogonality_1e6,
                      quaternion ? 32 * eps : test::orthogonality_walk_bound(std::min(1e6, static_cast<double>(n)) * stages));
  test::expect_figure("|RtR - I| after " + std::to_string(n) + " steps, " + name, r.orthogonality,
                      quaternion ? 32 * eps : test::orthogonality_walk_bound(static_cast<double>(n) * stages));
}

// 10⁷ steps (the horizon) for the cheapest composition, 10⁶ for Kahan–Li 8 and 3·10⁵ for the
// 35-stage order-10 set (17·10⁶ and 10.5·10⁶ LGVI steps): the test-time budget. Steps are chosen so that the
// energy error (1e-9 .. 1e-5) stands far above the round-off random walk (≈ 1e-13 after these runs).
TEST(CompositionLongRun, Yoshida4TenMillionSteps) {
  expect_geometric<LgviYoshida4>(long_run<LgviYoshida4>(0.02, 10'000'000), 10'000'000);
}
TEST(CompositionLongRun, SplitDmvYoshida4TenMillionSteps) {
  expect_geometric<SplitDmvYoshida4>(long_run<SplitDmvYoshida4>(0.02, 10'000'000), 10'000'000, Attitude::quaternion);
}
TEST(CompositionLongRun, KahanLi8MillionSteps) {
  expect_geometric<LgviKahanLi8>(long_run<LgviKahanLi8>(0.1, 1'000'000), 1'000'000);
}
TEST(CompositionLongRun, SofroniouSpaletta10) {
  expect_geometric<LgviSofroniouSpaletta10>(long_run<LgviSofroniouSpaletta10>(0.2, 300'000), 300'000);
}

// Negative control: CF4 (order 4, not symplectic) over the same kind of run drifts; the slope test flags
// it and its m·k wanders far above round-off.
TEST(CompositionLongRun, NegativeControlCf4Drifts) {
  const LongRun r = long_run<Cf4>(0.05, 1'000'000);
  EXPECT_GT(r.drift_slope, 0.5);
  EXPECT_GT(r.momentum, 1e-9);
  test::expect_figure("|RtR - I| after 1e6 steps, cf4 (two exponentials a step)", r.orthogonality,
                      test::orthogonality_walk_bound(2e6));
}

// ---- Jets --------------------------------------------------------------------------------------------

// Derivatives of the state after 25 steps with respect to Ω0 and b, carried by ceres::Jet through every
// sub-step (the LGVI's Newton solve converges the derivative part too), against central differences.
TYPED_TEST(CompositionTest, JetDerivativesMatchFiniteDifferences) {
  // The central differences' rounding, measured 1.4e-9 … 2.8e-9 (compositions of the LGVI), 6.5e-10 … 1.5e-9 (of DMV).
  const bool lgvi = std::string_view(TypeParam::template type<HeavyTop<double>>::traits.name).starts_with("lgvi");
  test::expect_heavy_top_jets_match<TypeParam::template type>(0.04, 1.0, 8e-15, lgvi ? 7e-9 : 3.2e-9);
}

// ---- compositions of the Lagrange top's splitting (lagrange_split) -------------------------------------

static_assert(Stepper<LagrangeSplitKahanLi8<LagrangeTop<double>>>);
static_assert(!Stepper<LagrangeSplitKahanLi8<HeavyTop<double>>> && Stepper<LgviKahanLi8<HeavyTop<double>>>,
              "compositions of lagrange_split are steppers only where lagrange_split is one");

// A Lagrange top with a tilted k and a tilted start (test_problem_library.cpp's), and the fast top.
LagrangeTop<double> tilted_lagrange_top() {
  return LagrangeTop<double>::make(1.3, 0.7, 2.1, Vec3<double>(0.3, -0.5, 0.81).normalized());
}
State<double> lagrange_state() { return {so3::exp(Vec3<double>(0.5, -0.3, 0.2)), Vec3<double>(0.6, -0.8, 3.0)}; }

TEST(LagrangeSplitCompositions, OrdersInLongDouble) {
  const LagrangeTop<double> top = tilted_lagrange_top();
  const State<double> x0 = lagrange_state();
  EXPECT_NEAR(observed_order_ld<LagrangeSplitYoshida4>("tilted lagrange top", top, x0, {40, 56, 80, 112, 160}), 4.0, 0.2);
  EXPECT_NEAR(observed_order_ld<LagrangeSplitKahanLi6>("tilted lagrange top", top, x0, {16, 20, 24, 32, 40, 48}), 6.0,
              0.2);
  EXPECT_NEAR(observed_order_ld<LagrangeSplitKahanLi8>("tilted lagrange top", top, x0, {10, 12, 16, 20, 24, 32}), 8.0,
              0.2);
  // Order 10 on a faster start (larger errors): the window between the pre-asymptotic steps (local slopes 12,
  // 15, 8.5 for n = 5 … 8) and the reference's floor (1e3× its error, n ≈ 12) is n = 8 … 11, local slopes 10.1,
  // 10.0, 10.0 (a self-convergence run in long double continues 10.1, 10.4 to n = 14 before its own floor).
  const State<double> fast{x0.R, Vec3<double>(1.5, -2.0, 4.0)};
  EXPECT_NEAR(observed_order_ld<LagrangeSplitSofroniouSpaletta10>("faster lagrange top", top, fast, {8, 9, 10, 11}),
              10.0, 0.2);
}

// The point of these methods: every sub-step turns the body about its symmetry axis exactly, so the step is
// set by the slow motions. On the fast Lagrange top (Ω3 = 150 rad/s, T = 2) Kahan–Li 8 at h = 0.05 — 7.5 rad
// of spin per step, where an explicit Runge–Kutta method is unstable — meets 1e-8 against a long-double
// reference; the LGVI's composition with the same coefficients cannot take that step at all.
TEST(LagrangeSplitCompositions, FastTopAtStepsLongerThanTheSpinPeriod) {
  const LagrangeTop<double> top = LagrangeTop<double>::fast_top();
  const State<double> x0 = LagrangeTop<double>::fast_top_state();
  const LagrangeTop<L> top_ld = top.cast<L>();
  const State<L> ref = rk4_richardson_ld(top_ld, x0.cast<L>(), L(2), 160000);
  const double ref_error = distance_ld(ref, rk4_richardson_ld(top_ld, x0.cast<L>(), L(2), 320000));
  const auto error = [&](auto stepper, double h) {
    State<double> x = x0;
    EXPECT_EQ(integrate_to(stepper, x, 0.0, h, 2.0).status, RunStatus::completed);
    return distance_ld(x.cast<L>(), ref);
  };
  const double e_split = error(LagrangeSplitKahanLi8<LagrangeTop<double>>(top), 0.05);
  std::printf("fast Lagrange top, T = 2, h = 0.05: lagrange_split_kahan_li8 error %.2e (reference %.1e)\n", e_split,
              ref_error);
  EXPECT_LT(ref_error, 1e-12);
  EXPECT_LT(e_split, 1e-8);
  // the LGVI's composition with the same coefficients cannot take this step: its implicit equation has no
  // solution once h|Ω| > 1 (lgvi.hpp)
  LgviKahanLi8<LagrangeTop<double>> lgvi(top);
  State<double> x = x0;
  EXPECT_NE(integrate_to(lgvi, x, 0.0, 0.05, 2.0).status, RunStatus::completed);
}

// Symplectic and symmetric: step(−h) ∘ step(h) = id; over 10⁶ steps energy bounded, m·k to round-off and
// m_ψ = I3 Ω3 bit for bit in the stepped state (no sub-step touches Π3).
TEST(LagrangeSplitCompositions, SymmetricAndConservative) {
  using S = LagrangeSplitKahanLi8<LagrangeTop<double>>;
  const LagrangeTop<double> top = tilted_lagrange_top();
  const State<double> x0 = lagrange_state();
  S stepper(top);
  auto y = stepper.to_internal(x0, 0.0);
  ASSERT_EQ(stepper.step(y, 0.0, 0.1), StepStatus::ok);
  ASSERT_EQ(stepper.step(y, 0.1, -0.1), StepStatus::ok);
  const double back = test::state_distance(stepper.to_state(y), x0);
  std::printf("lagrange_split_kahan_li8: |step(-h) o step(h) - id| = %.2e at h = 0.1\n", back);
  EXPECT_LT(back, 1e-14);

  const double E0 = energy(top, x0);
  const auto inv0 = top.invariants(x0);
  double max_dE = 0, max_dmk = 0, max_orth = 0;
  std::vector<double> t, e;
  State<double> x = x0;
  const auto observe = [&](double tt, const State<double>& z) {
    const double dE = std::abs(energy(top, z) - E0) / std::abs(E0);
    max_dE = std::max(max_dE, dE);
    max_orth = std::max(max_orth, so3::orthogonality_error(z.R));
    max_dmk = std::max(max_dmk, std::abs(top.invariants(z)[0] - inv0[0]) / spatial_momentum(top.inertia, x0).norm());
    if (tt > 0) t.push_back(tt), e.push_back(dE);
  };
  // h = 0.3 (h|Ω0| = 1.0): the energy error (≈ 1e-9) stands far above the round-off random walk
  const auto summary = integrate_every(stepper, x, 0.0, 0.3, 3e5, 1000, observe);
  ASSERT_EQ(summary.status, RunStatus::completed);
  // drift: largest error in the last tenth against the first tenth of the run
  double first = 0, last = 0;
  for (std::size_t i = 0; i < e.size() / 10; ++i) first = std::max(first, e[i]), last = std::max(last, e[e.size() - 1 - i]);
  std::printf("lagrange_split_kahan_li8, 1e6 steps h = 0.3: energy %.2e (first tenth %.2e, last %.2e), m.k %.2e, "
              "|R^T R - I| %.2e, m_psi %.17g -> %.17g\n", max_dE, first, last, max_dmk, max_orth, inv0[1],
              top.invariants(x)[1]);
  EXPECT_LT(last, 2 * first);
  test::expect_figure("m.k error / |m| over 1e6 steps, lagrange_split_kahan_li8", max_dmk, 1e-12);
  // Its attitude is a unit quaternion, renormalised every step (lagrange_split.hpp): within a few ε of SO(3).
  test::expect_figure("|RtR - I| over 1e6 steps, lagrange_split_kahan_li8", max_orth,
                      32 * std::numeric_limits<double>::epsilon());
  EXPECT_EQ(x.Omega.z() * top.inertia(2, 2), inv0[1]);
}

}  // namespace
}  // namespace lgi
