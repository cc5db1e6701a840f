// No heap allocation in the library's loops, measured (allocation_counter.hpp counts every allocation of the
// process): steps and the library's drivers (integrate_times, integrate_every, integrate_adaptive, the Euler-angle
// and batch paths) with an observer, on the cases the conformance suite (test_conformance.cpp: every registered
// method on four problems, through the engine's loop) does not run: the Kovalevskaya top, a body whose torque is
// differentiated automatically, diagonal-J splittings, DMV substeps at h|Ω| > 1. Under ASan the counter is off and
// the test is skipped.
#include "allocation_counter.hpp"
#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/integrators/splitting.hpp>
#include <lgi/integrators/split_exact.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>
#include <lgi/integrators/lagrange_split.hpp>
#include <lgi/problems/kovalevskaya_top.hpp>
#include <lgi/problems/lagrange_top.hpp>
#include <lgi/problems/potential_problem.hpp>
#include <lgi/problems/satellite.hpp>
#include <lgi/integrators/commutator_free.hpp>
#include <lgi/integrators/composition.hpp>
#include <lgi/integrators/euclidean_rk.hpp>
#include <lgi/problems/euler_angle_top.hpp>

#include <lgi/integrators/adaptive.hpp>
#include <lgi/integrators/embedding.hpp>
#include <lgi/integrators/projection.hpp>

#include <gtest/gtest.h>

#include <cstddef>
#include <span>
#include <vector>


namespace lgi {
namespace {

template <template <class> class Method, class P>
void expect_no_allocation(const P& problem, const State<double>& x0) {
  Method<P> stepper(problem);
  auto y = stepper.to_internal(x0, 0.0);
  std::vector<double> sampled;  // observer storage, reserved before the loop
  sampled.reserve(64);
  auto observe = [&](double t, const State<double>&) { sampled.push_back(t); };
  const double times[] = {0.5, 0.75, 1.0};

  const long before = test::allocations();
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(stepper.step(y, 0.001 * i, 0.001), StepStatus::ok);
  State<double> x = x0;
  integrate_times(stepper, x, 0.0, 0.001, std::span<const double>(times), observe);
  integrate_every(stepper, x, 0.0, 0.001, 1.0, 100, observe, [](std::int64_t) { return true; });
  const long after = test::allocations();
  EXPECT_EQ(after - before, 0) << Method<P>::traits.name << " on " << P::name;
}

TEST(NoAllocation, CounterWorks) {
  if (!test::counting_allocations) GTEST_SKIP() << "allocation counter disabled under sanitizers";
  const long before = test::allocations();
  std::vector<double> v(100);
  EXPECT_GT(test::allocations(), before);  // the counter sees allocations at all
}

TEST(NoAllocation, StepLoopsOfEveryIntegrator) {
  if (!test::counting_allocations) GTEST_SKIP() << "allocation counter disabled under sanitizers";
  const auto top = test::skew_heavy_top();
  const auto body = FreeBody<double>::hairer_vilmart();
  const State<double> x0 = test::skew_initial_state();
  expect_no_allocation<Lgvi>(top, x0);
  expect_no_allocation<Rkmk4>(top, x0);
  expect_no_allocation<LieEuler>(top, x0);
  expect_no_allocation<Lgvi>(body, x0);
  expect_no_allocation<Rkmk4>(body, x0);
  expect_no_allocation<LieEuler>(body, x0);
}

// The problem library (problems/lagrange_top.hpp … potential_problem.hpp) and its splitting.
TEST(NoAllocation, ProblemLibrary) {
  if (!test::counting_allocations) GTEST_SKIP() << "allocation counter disabled under sanitizers";
  const State<double> x0 = test::skew_initial_state();
  const auto lagrange = LagrangeTop<double>::make(2.0, 1.0, 1.0, Vec3<double>(0, 0.6, 0.8));
  expect_no_allocation<LagrangeSplit>(lagrange, x0);
  expect_no_allocation<Lgvi>(KovalevskayaTop<double>{}, x0);
  FieldPotentialBody<double> field;  // torque by automatic differentiation
  field.V.terms = 1;
  field.V.b[0] = 1.0;
  field.V.z[0] = field.V.k[0] = Vec3<double>::UnitZ();
  field.V.c = 2.0;
  field.V.Q = Vec3<double>(1, 2, 3).asDiagonal();
  expect_no_allocation<Lgvi>(field, x0);
  expect_no_allocation<Rkmk4>(field, x0);
}

// Splittings: kicks + axis rotations / DMV / preprocessed DMV (integrators/splitting.hpp), diagonal and
// non-diagonal J, and the DMV substeps at h|Ω| > 1 taken inside the flow.
TEST(NoAllocation, Splittings) {
  if (!test::counting_allocations) GTEST_SKIP() << "allocation counter disabled under sanitizers";
  const auto hv = HeavyTop<double>::hairer_vilmart();
  const auto body = FreeBody<double>::hairer_vilmart();
  const State<double> x0 = test::skew_initial_state();
  expect_no_allocation<SplitAxes>(hv, x0);
  expect_no_allocation<SplitDmv>(hv, x0);
  expect_no_allocation<SplitDmv>(body, State<double>{Mat3<double>::Identity(), Vec3<double>(900.0, 300.0, -500.0)});
}

// Runge–Kutta on the Euler angles of the seed paper's top (integrators/euclidean_rk.hpp) and its driver.
TEST(NoAllocation, EuclideanRkOnEulerAngles) {
  if (!test::counting_allocations) GTEST_SKIP() << "allocation counter disabled under sanitizers";
  EulerAngleTop<double> top;
  top.I2 = 2.0;
  top.I3 = 1.0;
  top.b = 1.0;
  top.k2 = 0.6;
  top.k3 = 0.8;
  const EulerAngleTop<double>::Vector y0 = top.from_state({rotation_from_euler_angles(0.5, 1.2, 0.0), Vec3<double>(0.3, -0.2, 4.0)});
  const EuclideanRk<tableaus::classical_rk4, EulerAngleTop<double>> rk4(top);
  const EuclideanRk<tableaus::dormand_prince5, EulerAngleTop<double>> dp5(top);
  std::vector<double> sampled;
  sampled.reserve(64);
  auto observe = [&](double t, const EulerAngleTop<double>::Vector&) { sampled.push_back(t); };
  const double times[] = {0.5, 0.75, 1.0};
  const long before = test::allocations();
  auto y = y0;
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(rk4.step(y, 0.001 * i, 0.001), StepStatus::ok);
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(dp5.step(y, 0.001 * i, 0.001), StepStatus::ok);
  y = y0;
  integrate_times_euclidean(rk4, y, 0.0, 0.001, std::span<const double>(times), observe);
  integrate_every_euclidean(rk4, y, 0.0, 0.001, 1.0, 100, observe, [](std::int64_t) { return true; });
  EXPECT_EQ(test::allocations() - before, 0);
}

// The RKMK family, the embedding baselines, projected steppers and the adaptive driver
// (integrators/rkmk.hpp, embedding.hpp, projection.hpp, adaptive.hpp).
template <class P>
using ProjectedRkmk4 = Projected<Rkmk4<P>>;
template <class P>
using ProjectedRk4Quat = Projected<Rk4QuatRenorm<P>>;

template <class S, class P>
void expect_no_allocation_adaptive(const P& problem, const State<double>& x0) {
  StepperOptions o;
  o.rtol = o.atol = 1e-9;
  S stepper(problem, o);
  std::vector<double> sampled;
  sampled.reserve(256);
  auto observe = [&](double t, const State<double>&) { sampled.push_back(t); };
  const double times[] = {0.3, 0.55, 1.0, 2.0};
  AdaptiveOptions every;
  every.every = 10;
  const long before = test::allocations();
  State<double> x = x0;
  integrate_adaptive(stepper, x, 0.0, 0.01, std::span<const double>(times), observe);
  integrate_adaptive(stepper, x, 0.0, 0.01, std::span<const double>(times), observe, every,
                     [](std::int64_t) { return true; });
  const long after = test::allocations();
  EXPECT_EQ(after - before, 0) << S::traits.name << " (adaptive) on " << P::name;
}

TEST(NoAllocation, RkmkFamilyBaselinesProjectionAdaptive) {
  if (!test::counting_allocations) GTEST_SKIP() << "allocation counter disabled under sanitizers";
  const auto top = test::skew_heavy_top();
  const auto body = FreeBody<double>::hairer_vilmart();
  const State<double> x0 = test::skew_initial_state();
  expect_no_allocation<RkmkHeun>(top, x0);
  expect_no_allocation<Rkmk3>(top, x0);
  expect_no_allocation<Rkmk4Rule38>(top, x0);
  expect_no_allocation<RkmkDp5>(top, x0);
  expect_no_allocation<RkmkDp8>(top, x0);
  expect_no_allocation<RkmkDp8>(body, x0);
  expect_no_allocation<Rkmk4Cayley>(top, x0);
  expect_no_allocation<RkmkDp8Cayley>(body, x0);
  expect_no_allocation<RkmkVern9>(top, x0);
  expect_no_allocation<RkmkVern9>(body, x0);
  expect_no_allocation<RkmkVern9Cayley>(top, x0);
  expect_no_allocation<Rk4Quat>(top, x0);
  expect_no_allocation<Rk4MatRenorm>(top, x0);
  expect_no_allocation<Dop853QuatRenorm>(top, x0);
  expect_no_allocation<Dop853Mat>(body, x0);
  expect_no_allocation<ProjectedRkmk4>(top, x0);
  expect_no_allocation<ProjectedRkmk4>(body, x0);
  expect_no_allocation<ProjectedRk4Quat>(top, x0);
  expect_no_allocation_adaptive<RkmkDp5<HeavyTop<double>>>(top, x0);
  expect_no_allocation_adaptive<RkmkDp8<HeavyTop<double>>>(top, x0);
  expect_no_allocation_adaptive<RkmkDp8<FreeBody<double>>>(body, x0);
  expect_no_allocation_adaptive<RkmkDp8Cayley<HeavyTop<double>>>(top, x0);
  expect_no_allocation_adaptive<Projected<RkmkDp8Cayley<HeavyTop<double>>>>(top, x0);
  expect_no_allocation_adaptive<RkmkVern9<HeavyTop<double>>>(top, x0);
  expect_no_allocation_adaptive<RkmkVern9Cayley<HeavyTop<double>>>(top, x0);
  expect_no_allocation_adaptive<RkmkVern9<FreeBody<double>>>(body, x0);
  expect_no_allocation_adaptive<Projected<RkmkDp5<HeavyTop<double>>>>(top, x0);
  expect_no_allocation_adaptive<Dop853MatRenorm<HeavyTop<double>>>(top, x0);
}

}  // namespace
}  // namespace lgi
