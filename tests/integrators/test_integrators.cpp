// Integrators, measured: observed convergence order against the declared one, exact steady rotation,
// Jets through every integrator against finite differences, implicit-step failure as a status.
#include "figures.hpp"
#include "jet_check.hpp"
#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <ceres/jet.h>
#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <array>
#include <numbers>
#include <string_view>
#include <vector>

namespace lgi {
namespace {

template <template <class> class Method>
struct MethodTag {
  template <class P>
  using type = Method<P>;
};

template <class Tag>
class IntegratorTest : public ::testing::Test {};
using Methods = ::testing::Types<MethodTag<LieEuler>, MethodTag<Lgvi>, MethodTag<Rkmk4>>;
TYPED_TEST_SUITE(IntegratorTest, Methods);

// The observed order, fitted over a step-halving sequence on the skew heavy top (non-diagonal J, z0
// and k off the principal axes) against the long-double RK4 reference, is the declared order ± 0.2.
TYPED_TEST(IntegratorTest, ObservedOrderMatchesDeclared) {
  using S = typename TypeParam::template type<HeavyTop<double>>;
  const auto problem = test::skew_heavy_top();
  const State<double> x0 = test::skew_initial_state();
  const double T = 2.0;
  const State<double> ref = test::reference_solution(problem, x0, T, 40000);
  // The reference is converged far below the errors measured here: compare with half its steps.
  const double ref_error = test::state_distance(ref, test::reference_solution(problem, x0, T, 20000));
  ASSERT_LT(ref_error, 1e-14);

  // Step counts put each method in its asymptotic range, errors well above the reference's.
  const int order = S::traits.order;
  const int n0 = order == 1 ? 400 : order == 2 ? 50 : 20;
  std::vector<double> hs, errors;
  for (int n = n0; n <= 16 * n0; n *= 2) {
    S stepper(problem);
    State<double> x = x0;
    const auto summary = integrate_to(stepper, x, 0.0, T / n, T);
    ASSERT_EQ(summary.status, RunStatus::completed);
    hs.push_back(T / n);
    errors.push_back(test::state_distance(x, ref));
    ASSERT_GT(errors.back(), 1e3 * ref_error) << "error too close to the reference's own";
  }
  const double p = test::fitted_order(hs, errors);
  this->RecordProperty("observed_order", std::to_string(p));
  std::printf("%s: observed order %.3f (declared %d), errors %.3e .. %.3e\n", S::traits.name.data(), p, order,
              errors.front(), errors.back());
  EXPECT_NEAR(p, order, 0.2) << S::traits.name << ": errors from " << errors.front() << " to " << errors.back();
}

// A free symmetric body spinning about a principal axis has Ω constant. RKMK methods then step exactly
// R·exp(hΩ) (u' = J_r⁻¹(u)Ω = Ω along Ω). The LGVI is the discrete Moser–Veselov map: it rotates by
// asin(h|Ω|) about Ω per step — its time reparametrisation (McLachlan & Zanna 2005) — and that is what
// it must give exactly. Ω is preserved by all.
TYPED_TEST(IntegratorTest, SteadyRotationIsExact) {
  using S = typename TypeParam::template type<FreeBody<double>>;
  FreeBody<double> body{Vec3<double>(2.0, 2.0, 1.0).asDiagonal()};
  const Mat3<double> R0 = so3::exp(Vec3<double>(0.3, -1.1, 0.4));
  const double h = 0.01;
  for (const Vec3<double>& Omega : {Vec3<double>(0, 0, 5.0), Vec3<double>(3.0, -4.0, 0), Vec3<double>(0.7, 0, 0)}) {
    S stepper(body);
    auto y = stepper.to_internal({R0, Omega}, 0.0);
    ASSERT_EQ(stepper.step(y, 0.0, h), StepStatus::ok);
    const State<double> x1 = stepper.to_state(y);
    const double w = Omega.norm();
    const double angle = S::traits.name == "lgvi" ? std::asin(h * w) : h * w;
    const Mat3<double> expected = R0 * so3::exp(Vec3<double>((angle / w) * Omega));
    EXPECT_LT((x1.R - expected).cwiseAbs().maxCoeff(), 4e-16) << S::traits.name << " Ω = " << Omega.transpose();
    EXPECT_LT((x1.Omega - Omega).cwiseAbs().maxCoeff(), 4 * 2.3e-16 * w) << S::traits.name;
  }
}

// The same with a non-diagonal J (principal moments 2, 2, 1 rotated by Q): Ω along Q's columns, the
// principal axes, is a steady rotation too; this takes the full-matrix paths.
TYPED_TEST(IntegratorTest, SteadyRotationIsExactWithRotatedInertia) {
  using S = typename TypeParam::template type<FreeBody<double>>;
  const Mat3<double> Q = so3::exp(Vec3<double>(0.4, -0.3, 0.9));
  FreeBody<double> body{Q * Vec3<double>(2.0, 2.0, 1.0).asDiagonal() * Q.transpose()};
  body.inertia = (0.5 * (body.inertia + body.inertia.transpose())).eval();
  const Mat3<double> R0 = so3::exp(Vec3<double>(0.3, -1.1, 0.4));
  const double h = 0.01;
  for (int axis = 0; axis < 3; ++axis) {
    const Vec3<double> Omega = 4.0 * Q.col(axis);
    S stepper(body);
    auto y = stepper.to_internal({R0, Omega}, 0.0);
    ASSERT_EQ(stepper.step(y, 0.0, h), StepStatus::ok);
    const State<double> x1 = stepper.to_state(y);
    const double angle = S::traits.name == "lgvi" ? std::asin(h * 4.0) : h * 4.0;
    const Mat3<double> expected = R0 * so3::exp(Vec3<double>((angle / 4.0) * Omega));
    EXPECT_LT((x1.R - expected).cwiseAbs().maxCoeff(), 1e-15) << S::traits.name << " axis " << axis;
    EXPECT_LT((x1.Omega - Omega).cwiseAbs().maxCoeff(), 1e-14) << S::traits.name;
  }
}

// Jets flow through every integrator: the derivative of the state after 50 steps with respect to Ω0 and
// to the parameter b, carried by ceres::Jet, equals central finite differences.
TYPED_TEST(IntegratorTest, JetDerivativesMatchFiniteDifferences) {
  // The value part is the double computation to round-off (not bit for bit: Eigen vectorises double
  // products with another summation order, and the LGVI takes one more Newton update for Jets).
  test::expect_heavy_top_jets_match<TypeParam::template type>(/*h=*/0.02, /*T=*/1.0, /*value_tol=*/4e-15);
}

// A Jet that carries ∂/∂J01 through a diagonal-valued inertia: the integrators must not take their
// diagonal fast paths (which would drop that derivative). Checked against central differences.
TYPED_TEST(IntegratorTest, InertiaDerivativeThroughDiagonalValue) {
  using Jet = ceres::Jet<double, 1>;
  using SJ = typename TypeParam::template type<HeavyTop<Jet>>;
  using SD = typename TypeParam::template type<HeavyTop<double>>;
  const auto problem = HeavyTop<double>::hairer_vilmart();
  const State<double> x0 = test::hairer_vilmart_state(problem);
  const double h = 0.02, T = 1.0;
  auto jet_problem = problem.cast<Jet>();
  jet_problem.inertia(0, 1).v[0] = 1;
  jet_problem.inertia(1, 0).v[0] = 1;
  State<Jet> xj = x0.cast<Jet>();
  SJ jet_stepper(jet_problem);
  ASSERT_EQ(integrate_to(jet_stepper, xj, Jet(0), Jet(h), Jet(T)).status, RunStatus::completed);
  const auto run = [&](double dJ) {
    auto p = problem;
    p.inertia(0, 1) += dJ;
    p.inertia(1, 0) += dJ;
    State<double> x = x0;
    SD stepper(p);
    integrate_to(stepper, x, 0.0, h, T);
    return x;
  };
  const double eps = 1e-6;
  const State<double> plus = run(eps), minus = run(-eps);
  double largest = 0;
  for (int r = 0; r < 3; ++r) {
    const double fd = (plus.Omega[r] - minus.Omega[r]) / (2 * eps);
    largest = std::max(largest, std::abs(fd));
    EXPECT_NEAR(xj.Omega[r].v[0], fd, 1e-7) << "dΩ" << r << "/dJ01";
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(xj.R(r, c).v[0], (plus.R(r, c) - minus.R(r, c)) / (2 * eps), 1e-7) << "dR/dJ01";
  }
  EXPECT_GT(largest, 0.1);  // the derivative is not trivially zero
}

// The heavy top seen only through torque(R): no reduced-attitude functions, so every integrator takes its
// generic torque path (stage attitudes R·exp(u) in RKMK).
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
static_assert(RigidBodyProblem<OpaqueTop> && !ReducedAttitudeProblem<OpaqueTop>);
static_assert(ReducedAttitudeProblem<HeavyTop<double>>);

// Generic and reduced torque paths give the same trajectory to round-off, and the generic path has the
// declared order too.
TYPED_TEST(IntegratorTest, GenericTorquePathMatchesReducedPath) {
  using SR = typename TypeParam::template type<HeavyTop<double>>;
  using SG = typename TypeParam::template type<OpaqueTop>;
  const auto top = test::skew_heavy_top();
  const OpaqueTop opaque{top, top.inertia};
  const State<double> x0 = test::skew_initial_state();
  State<double> xr = x0, xg = x0;
  SR reduced(top);
  SG generic(opaque);
  integrate_to(reduced, xr, 0.0, 0.01, 2.0);
  integrate_to(generic, xg, 0.0, 0.01, 2.0);
  // The same operations for the LGVI (0 measured); the RKMK methods' double runs carry principal axes and the
  // opaque top's run the body frame (rkmk.hpp): 3.5e-15 … 3.7e-15.
  test::expect_figure(std::string("generic vs reduced torque path over 200 steps, ") + std::string(SR::traits.name) +
                          " (test_integrators)",
                      test::state_distance(xr, xg), 1.5e-14);

  const State<double> ref = test::reference_solution(top, x0, 2.0, 40000);
  std::vector<double> hs, errors;
  const int n0 = SG::traits.order == 1 ? 400 : SG::traits.order == 2 ? 50 : 20;
  for (int n = n0; n <= 8 * n0; n *= 2) {
    SG stepper(opaque);
    State<double> x = x0;
    integrate_to(stepper, x, 0.0, 2.0 / n, 2.0);
    hs.push_back(2.0 / n);
    errors.push_back(test::state_distance(x, ref));
  }
  EXPECT_NEAR(test::fitted_order(hs, errors), SG::traits.order, 0.2) << SG::traits.name;
}

// The LGVI's implicit equation has no solution along a principal axis once h|Ω| > 1 (sin φ = h|Ω|): the
// step says so and leaves the state as it was; it never returns NaN.
TEST(Lgvi, NewtonFailureIsAStatusAndLeavesTheStateUntouched) {
  FreeBody<double> body{Vec3<double>(2.0, 2.0, 1.0).asDiagonal()};
  Lgvi<FreeBody<double>> stepper(body);
  const State<double> x0{so3::exp(Vec3<double>(0.1, 0.2, 0.3)), Vec3<double>(0, 0, 150.0)};
  auto y = stepper.to_internal(x0, 0.0);
  const auto before = y;
  EXPECT_EQ(stepper.step(y, 0.0, 0.01), StepStatus::not_converged);  // h|Ω| = 1.5
  EXPECT_EQ(y.R, before.R);
  EXPECT_EQ(y.Pi, before.Pi);
  EXPECT_EQ(stepper.step(y, 0.0, 0.005), StepStatus::ok);  // h|Ω| = 0.75 converges
}

// The iteration limit is honoured: one Newton update cannot reach the tolerance from the predictor at a
// large step, and the step reports not_converged rather than a half-solved F.
TEST(Lgvi, IterationLimitIsHonoured) {
  const auto problem = test::skew_heavy_top();
  const State<double> x0 = test::skew_initial_state();
  Lgvi<HeavyTop<double>> one(problem, StepperOptions{.tolerance = 1e-14, .max_iterations = 1});
  Lgvi<HeavyTop<double>> many(problem);
  auto y1 = one.to_internal(x0, 0.0), y2 = many.to_internal(x0, 0.0);
  EXPECT_EQ(one.step(y1, 0.0, 0.5), StepStatus::not_converged);
  EXPECT_EQ(many.step(y2, 0.0, 0.5), StepStatus::ok);
  EXPECT_LE(many.newton_iterations(), 6);
}

// Negative control of the Jet check (jet_check.hpp): an LGVI that loses one derivative — the ∂/∂b part of its
// momentum after every step, as a step that let b's derivative fall out of the torque would — fails it.
template <class P>
struct LgviDroppingDb : Lgvi<P> {
  using Lgvi<P>::Lgvi;
  static constexpr MethodTraits traits = [] {
    MethodTraits t = Lgvi<P>::traits;
    t.name = "lgvi dropping d/db (negative control)";  // scripts/validation_table.py leaves it out of the table
    return t;
  }();
  StepStatus step(typename Lgvi<P>::Internal& y, const typename Lgvi<P>::Scalar& t, const typename Lgvi<P>::Scalar& h) {
    const StepStatus s = Lgvi<P>::step(y, t, h);
    if constexpr (!std::is_same_v<typename Lgvi<P>::Scalar, double>)
      for (int i = 0; i < 3; ++i) y.Pi[i].v[3] = 0;
    return s;
  }
};

TEST(JetCheck, FailsAMethodThatDropsADerivative) {
  EXPECT_NONFATAL_FAILURE(test::expect_heavy_top_jets_match<LgviDroppingDb>(0.02, 1.0, 4e-15),
                          "Jet derivatives vs central differences");
}

// Newton converges in one update at ordinary step sizes (the predictor is third-order accurate): a second update
// in one step of ten would fail this.
TEST(Lgvi, NewtonIterationsPerStep) {
  const auto problem = HeavyTop<double>::hairer_vilmart();
  Lgvi<HeavyTop<double>> stepper(problem);
  State<double> x = test::hairer_vilmart_state(problem);
  integrate_to(stepper, x, 0.0, 0.01, 100.0);
  const double per_step = static_cast<double>(stepper.newton_iterations()) / 10000;
  std::printf("lgvi, HV heavy top, 1e4 steps of h = 0.01: %lld Newton updates\n",
              static_cast<long long>(stepper.newton_iterations()));
  test::expect_figure("Newton updates per LGVI step, HV heavy top, h = 0.01", per_step, 1.1);
  EXPECT_GE(per_step, 1.0);
}

}  // namespace
}  // namespace lgi
