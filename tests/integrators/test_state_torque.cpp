// Torques that read the angular velocity and the time, M(t, R, Ω) (core/problem.hpp, StateTorqueProblem), through
// every method that takes one: the observed order against the declared one on a damped, periodically driven skew
// heavy top; the energy balance E(T) − E(0) = ∫ Ω·M_nc dt along the discrete trajectory; Jets through the
// torque; and the methods that need a torque of the attitude alone (the variational integrator, the splittings,
// their compositions, the projection) refusing the problem at compile time.
#include "order_measure.hpp"
#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/core/invariants.hpp>
#include <lgi/integrators/commutator_free.hpp>
#include <lgi/integrators/composition.hpp>
#include <lgi/integrators/embedding.hpp>
#include <lgi/integrators/lagrange_split.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/projection.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/integrators/split_exact.hpp>
#include <lgi/integrators/splitting.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string_view>
#include <vector>

namespace lgi {
namespace {

using test::DrivenDampedTop;
using test::driven_damped_skew_top;
using P = DrivenDampedTop<double>;
static_assert(StateTorqueProblem<P> && !AttitudeTorqueProblem<P> && !ReducedAttitudeProblem<P>);
static_assert(AttitudeTorqueProblem<HeavyTop<double>> && !StateTorqueProblem<HeavyTop<double>>);

// The methods that need a torque of (t, R) alone do not exist for P: the registry (apps/registry.hpp,
// method_applies_v) then does not offer them, and the scene loader names the methods that apply.
template <template <class> class M>
constexpr bool exists_for_P = requires { typename M<P>; };
static_assert(!exists_for_P<Lgvi> && !exists_for_P<SplitDmv> && !exists_for_P<SplitAxes> && !exists_for_P<SplitDmv4> &&
              !exists_for_P<SplitExact> && !exists_for_P<LgviYoshida4> && !exists_for_P<SplitDmvKahanLi8> &&
              !exists_for_P<LagrangeSplit> && !exists_for_P<LagrangeSplitYoshida4>);
static_assert(!ProjectableProblem<P> && !ProjectableStepper<Rkmk4<P>>);
static_assert(Stepper<Rkmk4<P>> && Stepper<Cf4<P>> && Stepper<Cg3<P>> && Stepper<Rk4Quat<P>> && Stepper<Dop853Mat<P>>);

const test::Reference& driven_reference() {
  static const test::Reference r = test::make_reference(driven_damped_skew_top(), test::skew_initial_state(), 2.0);
  return r;
}

template <template <class> class M>
void expect_order() {
  const double p = test::observed_order<M>(driven_damped_skew_top(), test::skew_initial_state(), 2.0,
                                           driven_reference(), "driven");
  EXPECT_NEAR(p, M<P>::traits.order, 0.2) << M<P>::traits.name;
}

TEST(StateTorqueOrder, Rkmk) {
  expect_order<LieEuler>();
  expect_order<RkmkHeun>();
  expect_order<Rkmk3>();
  expect_order<Rkmk4>();
  expect_order<Rkmk4Rule38>();
  expect_order<RkmkDp5>();
  expect_order<RkmkDp8>();
  expect_order<RkmkVern9>();
}

// Verner 9(8) in Cayley coordinates shows its h¹⁰ terms everywhere above the round-off of long double (integrators/
// rkmk.hpp; 9.99 here, as on the skew top): its order 9 on this problem is measured in binary128 by
// tests/integrators/test_quad_order.cpp (QuadOrder.Vern9CayleyOnTheDrivenDampedTop); here the pre-asymptotic slope is
// held where it is, between 9 and 10.2.
TEST(StateTorqueOrder, RkmkCayley) {
  expect_order<Rkmk4Cayley>();
  expect_order<RkmkDp5Cayley>();
  expect_order<RkmkDp8Cayley>();
  const double p = test::observed_order<RkmkVern9Cayley>(driven_damped_skew_top(), test::skew_initial_state(), 2.0,
                                                         driven_reference(), "driven");
  EXPECT_GE(p, 9.0 - 0.2);
  EXPECT_LE(p, 10.0 + 0.2);
}

TEST(StateTorqueOrder, CommutatorFreeAndCrouchGrossman) {
  expect_order<Cf4>();
  expect_order<Cg3>();
}

TEST(StateTorqueOrder, Baselines) {
  expect_order<Rk4Quat>();
  expect_order<Rk4QuatRenorm>();
  expect_order<Rk4Mat>();
  expect_order<Rk4MatRenorm>();
  expect_order<Dop853Quat>();
  expect_order<Dop853QuatRenorm>();
  expect_order<Dop853Mat>();
  expect_order<Dop853MatRenorm>();
}

// E(T) − E(0) − W(T), W the work of the non-conservative torque along the discrete trajectory (composite Simpson on
// the step grid, order 4): the defect converges at order min(4, the method's) — 4 for RKMK4 and Verner 9(8) in
// Cayley coordinates.
template <template <class> class M>
double energy_balance_defect(int n) {
  const P p = driven_damped_skew_top();
  const double T = 2.0, h = T / n;
  M<P> stepper(p);
  State<double> x = test::skew_initial_state();
  std::vector<double> power;
  const double E0 = energy(p, x);
  const auto observe = [&](double t, const State<double>& y) { power.push_back(p.power(t, y.Omega)); };
  EXPECT_EQ(integrate_every(stepper, x, 0.0, h, T, 1, observe).status, RunStatus::completed);
  EXPECT_EQ(static_cast<int>(power.size()), n + 1);
  double work = power.front() + power.back();
  for (int i = 1; i < n; ++i) work += (i % 2 ? 4.0 : 2.0) * power[static_cast<std::size_t>(i)];
  work *= h / 3;
  return std::abs(energy(p, x) - E0 - work);
}

template <template <class> class M>
void expect_energy_balance(const char* label) {
  std::vector<double> hs, defects;
  for (const int n : {40, 80, 160, 320}) {
    hs.push_back(2.0 / n);
    defects.push_back(energy_balance_defect<M>(n));
  }
  const double order = test::fitted_order(hs, defects);
  std::printf("%-18s energy balance defect %.3e .. %.3e, observed order %.3f\n", label, defects.front(),
              defects.back(), order);
  EXPECT_NEAR(order, 4.0, 0.2) << label;
}

TEST(StateTorqueEnergy, BalanceWithTheWorkOfTheTorqueConverges) {
  expect_energy_balance<Rkmk4>("rkmk4");
  expect_energy_balance<RkmkVern9Cayley>("rkmk_vern9_cayley");
}

// Damping alone: the energy falls by the work −∫Ω·CΩ dt > 0, and at every step of a fine run.
TEST(StateTorqueEnergy, DampingAloneDissipatesAtEveryStep) {
  P p = driven_damped_skew_top();
  p.a.setZero();
  Rkmk4<P> stepper(p);
  State<double> x = test::skew_initial_state();
  double previous = energy(p, x), largest_rise = -1;
  int steps = 0;
  const auto observe = [&](double, const State<double>& y) {
    const double E = energy(p, y);
    if (steps++ > 0) largest_rise = std::max(largest_rise, E - previous);
    previous = E;
  };
  EXPECT_EQ(integrate_every(stepper, x, 0.0, 1e-3, 20.0, 1, observe).status, RunStatus::completed);
  std::printf("damped skew top, 20000 RKMK4 steps: E from %.6f to %.6f, largest rise between steps %.3e\n",
              energy(p, test::skew_initial_state()), energy(p, x), largest_rise);
  EXPECT_LT(largest_rise, 0.0);
  EXPECT_LT(so3::orthogonality_error(x.R), 1e-13);
}

// Jets through the torque: the derivative of the final state with respect to the damping scale s (C → s C) and to the
// drive's frequency, against central differences.
TEST(StateTorqueJets, DerivativesAgreeWithFiniteDifferences) {
  using Jet = ceres::Jet<double, 2>;
  const P p = driven_damped_skew_top();
  const auto run = [&](double s, double w) {
    P q = p;
    q.C *= s;
    q.w = w;
    Rkmk4<P> stepper(q);
    State<double> x = test::skew_initial_state();
    integrate_to(stepper, x, 0.0, 0.01, 2.0);
    return x;
  };
  auto pj = p.cast<Jet>();
  pj.C *= Jet(1.0, 0);
  pj.w = Jet(p.w, 1);
  Rkmk4<DrivenDampedTop<Jet>> stepper(pj);
  const State<double> x0 = test::skew_initial_state();
  State<Jet> x{x0.R.cast<Jet>(), x0.Omega.cast<Jet>()};
  ASSERT_EQ(integrate_to(stepper, x, Jet(0), Jet(0.01), Jet(2.0)).status, RunStatus::completed);
  const double d = 1e-6;
  const State<double> sp = run(1 + d, p.w), sm = run(1 - d, p.w), wp = run(1, p.w + d), wm = run(1, p.w - d);
  double worst = 0;
  for (int i = 0; i < 3; ++i) {
    const double fd_s = (sp.Omega(i) - sm.Omega(i)) / (2 * d), fd_w = (wp.Omega(i) - wm.Omega(i)) / (2 * d);
    worst = std::max({worst, std::abs(x.Omega(i).v(0) - fd_s) / (1 + std::abs(fd_s)),
                      std::abs(x.Omega(i).v(1) - fd_w) / (1 + std::abs(fd_w))});
    for (int j = 0; j < 3; ++j) {
      const double fr_s = (sp.R(i, j) - sm.R(i, j)) / (2 * d), fr_w = (wp.R(i, j) - wm.R(i, j)) / (2 * d);
      worst = std::max({worst, std::abs(x.R(i, j).v(0) - fr_s) / (1 + std::abs(fr_s)),
                        std::abs(x.R(i, j).v(1) - fr_w) / (1 + std::abs(fr_w))});
    }
  }
  std::printf("Jets through M(t, R, Omega): largest difference to central differences %.2e\n", worst);
  EXPECT_LT(worst, 1e-7);
}

}  // namespace
}  // namespace lgi
