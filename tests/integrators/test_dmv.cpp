// The discrete Moser–Veselov flows of integrators/free_body_flows.hpp inside the Strang splitting of
// integrators/splitting.hpp, measured: preprocessed DMV orders 4, 6, 8, 10 on the free body (in long
// double, against a long-double reference far below the errors), order 2 with gravity, kick + DMV equal
// to the LGVI (the same map, NUMERICS.md), Newton and substeps where the fixed point fails (h|Ω| = 3),
// Jets against finite differences.
#include "fp_traps.hpp"
#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/core/invariants.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/splitting.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace lgi {
namespace {

using L = long double;

// Classical RK4 on (R, Ω) ∈ R^{3×3} × R³ in long double, Richardson-extrapolated from n and 2n steps
// ((16 y_{2n} − y_n)/15, error O(h⁵)): a different method and coordinates from every DMV flow. With
// n = 20000 over T = 2 it agrees with the n = 40000 one to 5e-17 (checked below).
template <class P>
State<L> reference_ld(const P& p, const State<L>& x0, L T, int n) {
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

L distance_ld(const State<L>& a, const State<L>& b) { return (a.R - b.R).norm() + (a.Omega - b.Omega).norm(); }

State<L> hv_state_ld(const Mat3<L>& J) { return {Mat3<L>::Identity(), J.inverse() * Vec3<L>(1.8L, 0.4L, -0.9L)}; }

// Observed order of Method on problem p over the step counts ns, in long double (solver tolerance 1e-18).
template <template <class> class Method, class P>
double observed_order_ld(const P& p, const State<L>& x0, const std::vector<int>& ns, L T, const State<L>& ref,
                         double ref_error, std::vector<double>* errors_out = nullptr) {
  StepperOptions options;
  options.tolerance = 1e-18;
  std::vector<double> hs, errors;
  for (const int n : ns) {
    Method<P> stepper(p, options);
    State<L> x = x0;
    EXPECT_EQ(integrate_to(stepper, x, L(0), T / n, T).status, RunStatus::completed);
    hs.push_back(static_cast<double>(T / n));
    errors.push_back(static_cast<double>(distance_ld(x, ref)));
    EXPECT_GT(errors.back(), 50 * ref_error) << "error too close to the reference's own";
  }
  if (errors_out) *errors_out = errors;
  return test::fitted_order(hs, errors);
}

template <template <class> class M>
struct Tag {
  template <class P>
  using type = M<P>;
};

template <class TagT>
class PreprocessedDmvOrder : public ::testing::Test {};
using Preprocessed = ::testing::Types<Tag<SplitDmv4>, Tag<SplitDmv6>, Tag<SplitDmv8>, Tag<SplitDmv10>>;
TYPED_TEST_SUITE(PreprocessedDmvOrder, Preprocessed);

// Acceptance: preprocessed DMV shows orders 4–10 on the free body. The Hairer–Vilmart body and momentum,
// T = 2, in long double against the extrapolated long-double RK4 (5e-17).
TYPED_TEST(PreprocessedDmvOrder, FreeBodyOrderInLongDouble) {
  using S = typename TypeParam::template type<FreeBody<L>>;
  const FreeBody<L> body = FreeBody<L>::hairer_vilmart();
  const L T = 2;
  const State<L> ref = reference_ld(body, hv_state_ld(body.inertia), T, 20000);
  const double ref_error =
      static_cast<double>(distance_ld(ref, reference_ld(body, hv_state_ld(body.inertia), T, 40000)));
  ASSERT_LT(ref_error, 2e-16);
  // The free-body order is the trait free_body_order (order = 2 holds with a torque: SkewHeavyTopOrderTwo).
  static_assert(S::traits.order == 2 && S::traits.free_body_order >= 4);
  const int order = S::traits.free_body_order;
  // Step counts (ratio √2) in the asymptotic range and above the reference's error.
  const std::vector<int> ns = order == 4    ? std::vector<int>{20, 28, 40, 56, 80, 113, 160}
                              : order == 6  ? std::vector<int>{20, 28, 40, 56, 80, 113, 160}
                              : order == 8  ? std::vector<int>{14, 20, 28, 40, 56}
                                            : std::vector<int>{10, 14, 20, 28, 40};
  std::vector<double> errors;
  const double p =
      observed_order_ld<TypeParam::template type>(body, hv_state_ld(body.inertia), ns, T, ref, ref_error, &errors);
  std::printf("%s on the free body (long double): observed order %.3f (declared free-body order %d), errors %.3e .. "
              "%.3e, reference error %.1e\n",
              S::traits.name.data(), p, order, errors.front(), errors.back(), ref_error);
  EXPECT_NEAR(p, order, 0.2);

  // The same body with its principal axes rotated by Q = exp(0.3, −0.5, 0.7): a non-diagonal J, so the
  // flow runs in principal axes found by the (long-double) eigensolver. Same motion in principal axes
  // (body momentum Q m0), so the errors must be those above (the distance is invariant under R → R Qᵀ).
  const Mat3<L> Q = so3::exp(Vec3<L>(0.3L, -0.5L, 0.7L));
  FreeBody<L> rotated{Mat3<L>(Q * body.inertia * Q.transpose())};
  rotated.inertia = (L(0.5) * (rotated.inertia + rotated.inertia.transpose())).eval();
  const State<L> x0_r{Mat3<L>::Identity(), rotated.inertia.inverse() * (Q * Vec3<L>(1.8L, 0.4L, -0.9L))};
  const State<L> ref_r = reference_ld(rotated, x0_r, T, 20000);
  const std::vector<double> errors_diagonal = errors;
  const double p_r = observed_order_ld<TypeParam::template type>(rotated, x0_r, ns, T, ref_r, ref_error, &errors);
  std::printf("%s on the free body, non-diagonal J (long double): observed order %.3f, errors %.3e .. %.3e\n",
              S::traits.name.data(), p_r, errors.front(), errors.back());
  EXPECT_NEAR(p_r, order, 0.2);
  // (to 1 %, plus the 1e-16 of long-double round-off and reference error that the smallest errors carry)
  for (std::size_t i = 0; i < errors.size(); ++i)
    EXPECT_NEAR(errors[i], errors_diagonal[i], 1e-2 * errors_diagonal[i] + 1e-16);
}

// With gravity the splitting is of order 2 (declared so for a torqued problem), measured on the skew
// heavy top (non-diagonal J: principal axes internally) in double against the shared long-double RK4.
TYPED_TEST(PreprocessedDmvOrder, SkewHeavyTopOrderTwo) {
  using S = typename TypeParam::template type<HeavyTop<double>>;
  static_assert(S::traits.order == 2);
  const auto top = test::skew_heavy_top();
  const State<double> x0 = test::skew_initial_state();
  const double T = 2.0;
  const State<double> ref = test::reference_solution(top, x0, T, 40000);
  const double ref_error = test::state_distance(ref, test::reference_solution(top, x0, T, 20000)) / 15;
  ASSERT_LT(ref_error, 1e-15);
  std::vector<double> hs, errors;
  for (int n = 50; n <= 800; n *= 2) {
    S stepper(top);
    State<double> x = x0;
    ASSERT_EQ(integrate_to(stepper, x, 0.0, T / n, T).status, RunStatus::completed);
    hs.push_back(T / n);
    errors.push_back(test::state_distance(x, ref));
    EXPECT_GT(errors.back(), 1e3 * ref_error);
  }
  const double p = test::fitted_order(hs, errors);
  std::printf("%s on the skew heavy top: observed order %.3f (declared 2), errors %.3e .. %.3e, reference error %.1e\n",
              S::traits.name.data(), p, errors.front(), errors.back(), ref_error);
  EXPECT_NEAR(p, 2.0, 0.2);
}

// Negative control for the order test: a deliberately wrong coefficient (the order-4 coefficient s_1,0
// halved) drops the observed order of the order-4 method to 2 — the test can fail.
TEST(PreprocessedDmv, WrongCoefficientLosesTheOrder) {
  const FreeBody<L> body = FreeBody<L>::hairer_vilmart();
  const L T = 2;
  const State<L> ref = reference_ld(body, hv_state_ld(body.inertia), T, 20000);
  StepperOptions options;
  options.tolerance = 1e-18;
  std::vector<double> hs, errors;
  for (int n : {20, 40, 80, 160}) {
    PreprocessedDmv<L, 2> flow(body.inertia.diagonal(), options);
    flow.coefficients().s[1][0] *= 0.5L;
    Quaternion<L> q;
    Vec3<L> Pi = Vec3<L>(1.8L, 0.4L, -0.9L);
    for (int i = 0; i < n; ++i) ASSERT_EQ(flow(q, Pi, T / n), StepStatus::ok);
    const State<L> x{quat::to_matrix(q), Pi.cwiseQuotient(body.inertia.diagonal())};
    hs.push_back(static_cast<double>(T / n));
    errors.push_back(static_cast<double>(distance_ld(x, ref)));
  }
  const double p = test::fitted_order(hs, errors);
  std::printf("order-4 preprocessed DMV with s_1,0 halved: observed order %.3f\n", p);
  EXPECT_LT(p, 2.3);
}

// Kick + DMV is the LGVI's map (NUMERICS.md): the two implementations (principal axes + quaternion +
// fixed point, body frame + matrix + Newton) agree to round-off, on the diagonal Hairer–Vilmart top and on
// the skew top with non-diagonal J.
TEST(SplitDmv, SameMapAsLgvi) {
  for (const bool skew : {false, true}) {
    const HeavyTop<double> top = skew ? test::skew_heavy_top() : HeavyTop<double>::hairer_vilmart();
    const State<double> x0 = skew ? test::skew_initial_state() : test::hairer_vilmart_state(top);
    State<double> a = x0, b = x0;
    Lgvi<HeavyTop<double>> lgvi(top);
    SplitDmv<HeavyTop<double>> split(top);
    integrate_to(lgvi, a, 0.0, 0.01, 10.0);
    integrate_to(split, b, 0.0, 0.01, 10.0);
    const double d = test::state_distance(a, b);
    std::printf("kick+DMV vs LGVI after 1000 steps (%s): %.3e; sweeps beyond the predicted ones %lld, Newton "
                "fallbacks %lld\n",
                skew ? "skew top" : "HV top", d, static_cast<long long>(split.flow().counters().extra_sweeps),
                static_cast<long long>(split.flow().counters().fallbacks));
    EXPECT_LT(d, 1e-12);
    EXPECT_EQ(split.flow().counters().fallbacks, 0);  // h|Ω| ≈ 0.03: the fixed point converges alone
    // and the change from the other solver is far below the method's error (≈ 1e-4 at h = 0.01)
  }
}

// Hairer's plain fixed-point iteration, exactly as in the authors' code (predictor, then 50 sweeps, no
// convergence test that could stop a divergence): the negative control for the acceptance below.
Vec3<double> plain_fixed_point(const Vec3<double>& Pi, double h, const Vec3<double>& I) {
  const test::FpTrapsOff traps_off;  // diverges on purpose: overflow, then ∞ − ∞
  const Vec3<double> w = 0.5 * h * Pi.cwiseQuotient(I);
  const Vec3<double> r((I(1) - I(2)) / I(0), (I(2) - I(0)) / I(1), (I(0) - I(1)) / I(2));
  double c0 = w(0) + r(0) * w(1) * w(2), c1 = w(1) + r(1) * c0 * w(2), c2 = w(2) + r(2) * c0 * c1;
  for (int i = 0; i < 50; ++i) {
    const double a = 1 + c0 * c0 + c1 * c1 + c2 * c2;
    c0 = a * w(0) + r(0) * c1 * c2;
    c1 = a * w(1) + r(1) * c0 * c2;
    c2 = a * w(2) + r(2) * c0 * c1;
  }
  return {c0, c1, c2};
}

// Acceptance: DMV with Newton stays finite and bounded at h|Ω| = 3 where the plain fixed point fails.
// At h|Ω| = 3 the DMV equation itself has no solution for the Hairer–Vilmart body (|hΠ| = 1.92 exceeds
// the ≈ 1.08 that (2/α)|Ic + c × Ic| can reach), so the flow takes ⌈h|Π|/min I⌉ = 4 substeps, each
// solved by the fixed point with Newton taking over; the plain fixed point gives NaN at the first step.
TEST(SplitDmv, FiniteAndBoundedAtLargeSteps) {
  const FreeBody<double> body = FreeBody<double>::hairer_vilmart();
  const State<double> x0 = test::hairer_vilmart_state(body);
  const double E0 = energy(body, x0);
  for (const double hw : {1.5, 3.0}) {
    const double h = hw / x0.Omega.norm();
    const Vec3<double> c = plain_fixed_point(body.inertia.diagonal().cwiseProduct(x0.Omega), h, body.inertia.diagonal());
    EXPECT_FALSE(c.allFinite()) << "plain fixed point at h|Omega| = " << hw << ": " << c.transpose();
    // What keeps the flow finite is the substepping (the equation has no solution at the full step); at the
    // substep size the plain fixed point converges too (50 sweeps), Newton only converges faster there.
    const Vec3<double> Pi0 = body.inertia.diagonal().cwiseProduct(x0.Omega);
    const int m = dmv_substeps(Pi0, h, body.inertia.diagonal().minCoeff());
    const Vec3<double> cs = plain_fixed_point(Pi0, h / m, body.inertia.diagonal());
    std::printf("h|Omega| = %.1f: plain fixed point at the full step %s; at the substep h/%d: %s\n", hw,
                c.allFinite() ? "finite" : "NaN", m, cs.allFinite() ? "finite" : "NaN");

    SplitDmv<FreeBody<double>> stepper(body);
    State<double> x = x0;
    double worst = 0;
    const auto summary = integrate_every(stepper, x, 0.0, h, 10000 * h, 1, [&](double, const State<double>& y) {
      worst = std::max(worst, std::abs(energy(body, y) - E0) / E0);
    });
    const auto& k = stepper.flow().counters();
    std::printf("DMV at h|Omega| = %.1f: %lld steps, max rel. energy error %.3e, |RtR-I| %.2e, substeps %lld, "
                "Newton fallbacks %lld, Newton updates %lld\n",
                hw, static_cast<long long>(summary.steps), worst, so3::orthogonality_error(x.R),
                static_cast<long long>(k.substeps), static_cast<long long>(k.fallbacks),
                static_cast<long long>(k.newton));
    ASSERT_EQ(summary.status, RunStatus::completed);
    EXPECT_TRUE(is_finite(x));
    EXPECT_LT(worst, 1e-12);  // DMV keeps the free body's energy exactly (to round-off)
    EXPECT_LT(so3::orthogonality_error(x.R), 1e-13);
    EXPECT_GT(k.fallbacks, 0);  // Newton did take over
  }
  // A fast heavy top (|Ω| ≈ 95, h = 3/|Ω|): the whole splitting finite, energy bounded over 10⁴ steps.
  const HeavyTop<double> top = HeavyTop<double>::hairer_vilmart();
  const State<double> fast{Mat3<double>::Identity(), 30.0 * test::hairer_vilmart_state(top).Omega};
  const double h = 3.0 / fast.Omega.norm();
  const double E0top = energy(top, fast);
  SplitDmv<HeavyTop<double>> stepper(top);
  State<double> x = fast;
  std::vector<double> err;
  const auto summary = integrate_every(stepper, x, 0.0, h, 20000 * h, 10, [&](double, const State<double>& y) {
    err.push_back(std::abs(energy(top, y) - E0top) / E0top);
  });
  ASSERT_EQ(summary.status, RunStatus::completed);
  EXPECT_TRUE(is_finite(x));
  const std::size_t tenth = err.size() / 10;
  const double first = *std::max_element(err.begin() + 1, err.begin() + static_cast<std::ptrdiff_t>(tenth));
  const double last = *std::max_element(err.end() - static_cast<std::ptrdiff_t>(tenth), err.end());
  std::printf("fast heavy top at h|Omega| = 3: %lld steps, max rel. energy error first/last tenth %.3e / %.3e\n",
              static_cast<long long>(summary.steps), first, last);
  EXPECT_LT(last, 1.5 * first);  // bounded: no growth from the first tenth of the run to the last
  EXPECT_LT(last, 1e-2);
}

// On a principal axis the DMV equation has no solution once h|Ω| > 1 (sin φ = h|Ω|, lgvi.hpp); the
// substep rule h|Π|/min I > 1 always fires first there (h|Π| = h|Ω| I_axis ≥ h|Ω| min I), so the flow
// stays solvable: a prolate body spun about its largest axis at h|Ω| = 1.02 takes 2 substeps. And when
// Newton is cut short (max_iterations = 1 where the fixed point stalls) the step reports not_converged
// and leaves the state untouched, never NaN.
TEST(SplitDmv, SubstepsOnAnAxisAndFailureIsAStatus) {
  const FreeBody<double> prolate{Vec3<double>(1.0, 1.0, 1.9).asDiagonal()};
  SplitDmv<FreeBody<double>> s2(prolate);
  auto y2 = s2.to_internal({Mat3<double>::Identity(), Vec3<double>(0, 0, 100.0)}, 0.0);
  EXPECT_EQ(s2.step(y2, 0.0, 0.0102), StepStatus::ok);
  EXPECT_EQ(s2.flow().counters().substeps, 2);
  EXPECT_NEAR(s2.to_state(y2).Omega(2), 100.0, 1e-12);

  const FreeBody<double> body = FreeBody<double>::hairer_vilmart();
  SplitDmv<FreeBody<double>> one(body, StepperOptions{.tolerance = 1e-14, .max_iterations = 1});
  const State<double> x0 = test::hairer_vilmart_state(body);
  auto y = one.to_internal(x0, 0.0);
  const auto before = y;
  EXPECT_EQ(one.step(y, 0.0, 0.9 / x0.Omega.norm()), StepStatus::not_converged);
  EXPECT_EQ(y.q.w, before.q.w);
  EXPECT_EQ(y.q.v, before.q.v);
  EXPECT_EQ(y.Pi, before.Pi);
}

// The quaternion update of the DMV flow, vectorised for double with GCC's vector extensions
// (quat::multiply_increment), against the scalar code of every other scalar type: the same operations in
// the same order, so the same bits, for unit and slightly non-unit q and c from 1e-8 to 1. (With a
// compiler without the vector path both calls run the scalar code.)
TEST(SplitDmv, VectorQuaternionUpdateEqualsScalarBitForBit) {
  std::mt19937_64 rng(20261124);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto bits = [](double x) { return std::bit_cast<std::uint64_t>(x); };
  int differing = 0;
  for (int i = 0; i < 100000; ++i) {
    Quaternion<double> q;
    q.w = u(rng);
    q.v = Vec3<double>(u(rng), u(rng), u(rng));
    const double n = std::sqrt(q.w * q.w + q.v.squaredNorm()) * (1 + 1e-12 * u(rng));
    q.w /= n;
    q.v /= n;
    const double scale = std::pow(10.0, -4.0 * (u(rng) + 1.0));  // 1e-8 … 1
    const Vec3<double> c = scale * Vec3<double>(u(rng), u(rng), u(rng));
    const double a = 1 + c.squaredNorm();
    Quaternion<double> vec = q, sca = q;
    quat::multiply_increment(vec, c(0), c(1), c(2), a);
    quat::detail::multiply_increment_scalar(sca, c(0), c(1), c(2), a);
    differing += bits(vec.w) != bits(sca.w) || bits(vec.v(0)) != bits(sca.v(0)) ||
                 bits(vec.v(1)) != bits(sca.v(1)) || bits(vec.v(2)) != bits(sca.v(2));
  }
  EXPECT_EQ(differing, 0);
}

// The heavy top through its reduced_torque_lever (the splitting's torque: one cross product with b Qᵀz0)
// and the same top with the lever hidden (the torque through reduced_torque): the same steps to round-off,
// on the HV top and on the skew top with a non-unit gravity axis (|a| = 2 scales the internal frame).
struct HeavyTopWithoutLever {
  using Scalar = double;
  static constexpr std::string_view name = "heavy_top";
  static constexpr bool has_torque = true;
  HeavyTop<double> top;
  Mat3<double> inertia;
  double potential(const Mat3<double>& R) const { return top.potential(R); }
  Vec3<double> torque(const Mat3<double>& R) const { return top.torque(R); }
  const Vec3<double>& reduced_axis() const { return top.reduced_axis(); }
  Vec3<double> reduced_torque(const Vec3<double>& Gamma) const { return top.reduced_torque(Gamma); }
  static constexpr std::array<std::string_view, 1> invariant_names{"momentum_k"};
  std::array<double, 1> invariants(const State<double>& x) const { return top.invariants(x); }
};

TEST(SplitDmv, TorqueLeverGivesTheSameSteps) {
  HeavyTop<double> skew = test::skew_heavy_top();
  skew.k *= 2;
  const HeavyTop<double> hv = HeavyTop<double>::hairer_vilmart();
  for (const bool is_skew : {false, true}) {
    const HeavyTop<double>& top = is_skew ? skew : hv;
    const HeavyTopWithoutLever plain{top, top.inertia};
    static_assert(ReducedAttitudeProblem<HeavyTopWithoutLever>);
    SplitDmv<HeavyTop<double>> a(top);
    SplitDmv<HeavyTopWithoutLever> b(plain);
    State<double> xa = is_skew ? test::skew_initial_state() : test::hairer_vilmart_state(top), xb = xa;
    ASSERT_EQ(integrate_to(a, xa, 0.0, 0.01, 10.0).status, RunStatus::completed);
    ASSERT_EQ(integrate_to(b, xb, 0.0, 0.01, 10.0).status, RunStatus::completed);
    const double d = test::state_distance(xa, xb);
    std::printf("kick+DMV, torque through the lever vs through reduced_torque, 1000 steps: %.2e\n", d);
    EXPECT_LT(d, 1e-13);
  }
}

// A lever that does not describe reduced_torque (a derived problem that changed the torque but inherited
// the lever) is refused when the splitting is built, not integrated.
struct HeavyTopWithWrongLever : HeavyTop<double> {
  Vec3<double> reduced_torque(const Vec3<double>& Gamma) const { return 2 * HeavyTop<double>::reduced_torque(Gamma); }
  Vec3<double> torque(const Mat3<double>& R) const { return reduced_torque(Vec3<double>(R.transpose() * k)); }
};

TEST(SplitDmv, InconsistentTorqueLeverIsRefused) {
  HeavyTopWithWrongLever top;
  static_cast<HeavyTop<double>&>(top) = HeavyTop<double>::hairer_vilmart();
  EXPECT_THROW(SplitDmv<HeavyTopWithWrongLever>{top}, std::invalid_argument);
}

// Jets through every DMV splitting: derivatives of the state after 50 steps with respect to Ω0, b and the
// off-diagonal inertia entry J01 (non-diagonal skew top: principal axes by perturbation for Jets), against
// central differences.
template <class TagT>
class DmvJets : public ::testing::Test {};
using AllDmv = ::testing::Types<Tag<SplitDmv>, Tag<SplitDmv4>, Tag<SplitDmv10>>;
TYPED_TEST_SUITE(DmvJets, AllDmv);

TYPED_TEST(DmvJets, DerivativesMatchFiniteDifferences) {
  using Jet = ceres::Jet<double, 5>;  // ∂/∂Ω0 (3), ∂/∂b, ∂/∂J01
  using SJ = typename TypeParam::template type<HeavyTop<Jet>>;
  using SD = typename TypeParam::template type<HeavyTop<double>>;
  const auto problem = test::skew_heavy_top();
  const State<double> x0 = test::skew_initial_state();
  const double h = 0.02, T = 1.0;
  auto jp = problem.cast<Jet>();
  jp.b.v[3] = 1;
  jp.inertia(0, 1).v[4] = 1;
  jp.inertia(1, 0).v[4] = 1;
  State<Jet> xj = x0.cast<Jet>();
  for (int i = 0; i < 3; ++i) xj.Omega[i].v[i] = 1;
  SJ js(jp);
  ASSERT_EQ(integrate_to(js, xj, Jet(0), Jet(h), Jet(T)).status, RunStatus::completed);
  const auto run = [&](const Vec3<double>& dOmega, double db, double dJ) {
    auto p = problem;
    p.b += db;
    p.inertia(0, 1) += dJ;
    p.inertia(1, 0) += dJ;
    State<double> x = x0;
    x.Omega += dOmega;
    SD s(p);
    integrate_to(s, x, 0.0, h, T);
    return x;
  };
  const double eps = 1e-6;
  double largest = 0;
  for (int j = 0; j < 5; ++j) {
    const Vec3<double> d = j < 3 ? Vec3<double>(eps * Vec3<double>::Unit(j)) : Vec3<double>::Zero();
    const State<double> plus = run(d, j == 3 ? eps : 0, j == 4 ? eps : 0);
    const State<double> minus = run(-d, j == 3 ? -eps : 0, j == 4 ? -eps : 0);
    for (int r = 0; r < 3; ++r) {
      const double fd = (plus.Omega[r] - minus.Omega[r]) / (2 * eps);
      largest = std::max(largest, std::abs(fd));
      EXPECT_NEAR(xj.Omega[r].v[j], fd, 1e-7) << SD::traits.name << " dOmega" << r << "/dp" << j;
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(xj.R(r, c).v[j], (plus.R(r, c) - minus.R(r, c)) / (2 * eps), 1e-7)
            << SD::traits.name << " dR/dp" << j;
    }
  }
  EXPECT_GT(largest, 0.1);
  const State<double> plain = run(Vec3<double>::Zero(), 0, 0);
  for (int r = 0; r < 3; ++r) EXPECT_NEAR(xj.Omega[r].a, plain.Omega[r], 1e-13);
}

}  // namespace
}  // namespace lgi
