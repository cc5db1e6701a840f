// Drivers: exact landing on output times, a trajectory independent of the outputs asked for, every-N
// output, failures and stops that keep the last good state.
#include "fp_traps.hpp"
#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

namespace lgi {
namespace {

struct Recorder {
  std::vector<double> t;
  std::vector<State<double>> x;
  void operator()(double ti, const State<double>& xi) {
    t.push_back(ti);
    x.push_back(xi);
  }
};

bool same_bits(const State<double>& a, const State<double>& b) { return a.R == b.R && a.Omega == b.Omega; }

TEST(Driver, LandsExactlyOnOutputTimesWithoutPerturbingTheTrajectory) {
  const auto problem = test::skew_heavy_top();
  const State<double> x0 = test::skew_initial_state();
  const double h = 0.1;
  const std::vector<double> times = {0.25, 0.5, 0.73, 1.0, 1.3000000000000003};

  Lgvi<HeavyTop<double>> stepper(problem);
  Recorder rec;
  State<double> x = x0;
  const auto summary = integrate_times(stepper, x, 0.0, h, std::span<const double>(times), rec);
  ASSERT_EQ(summary.status, RunStatus::completed);
  ASSERT_EQ(rec.t.size(), times.size() + 1);
  EXPECT_EQ(rec.t[0], 0.0);
  for (std::size_t i = 0; i < times.size(); ++i) EXPECT_EQ(rec.t[i + 1], times[i]);  // the requested times
  EXPECT_EQ(summary.t, times.back());
  EXPECT_TRUE(same_bits(x, rec.x.back()));

  // t = 0.73: seven grid steps, then one step of 0.73 − 0.7 from a copy.
  Lgvi<HeavyTop<double>> by_hand(problem);
  auto y = by_hand.to_internal(x0, 0.0);
  for (int n = 0; n < 7; ++n) ASSERT_EQ(by_hand.step(y, n * h, h), StepStatus::ok);
  auto side = y;
  ASSERT_EQ(by_hand.step(side, 7 * h, 0.73 - 7 * h), StepStatus::ok);
  EXPECT_TRUE(same_bits(rec.x[3], by_hand.to_state(side)));

  // t = 1.0 is on the grid: the state there is the one a run with no other outputs reaches, bit for bit.
  State<double> plain = x0;
  Lgvi<HeavyTop<double>> fresh(problem);
  integrate_to(fresh, plain, 0.0, h, 1.0);
  EXPECT_TRUE(same_bits(rec.x[4], plain));
  // 1.3000000000000003 is 13 h to rounding: on the grid, no side-step.
  EXPECT_EQ(summary.steps, 13 + 2);  // 13 grid steps + side-steps to 0.25 and 0.73
}

TEST(Driver, ZeroIsObservedOnceAndEmptyTimesObserveOnlyTheStart) {
  const auto problem = test::skew_heavy_top();
  Rkmk4<HeavyTop<double>> stepper(problem);
  Recorder rec;
  State<double> x = test::skew_initial_state();
  const std::vector<double> times = {0.0, 0.5};
  integrate_times(stepper, x, 0.0, 0.1, std::span<const double>(times), rec);
  EXPECT_EQ(rec.t, (std::vector<double>{0.0, 0.5}));

  Recorder only_start;
  State<double> x2 = test::skew_initial_state();
  const auto s = integrate_times(stepper, x2, 0.0, 0.1, std::span<const double>(), only_start);
  EXPECT_EQ(only_start.t, std::vector<double>{0.0});
  EXPECT_EQ(s.steps, 0);
}

TEST(Driver, EveryNStepsAndTheEnd) {
  const auto problem = test::skew_heavy_top();
  Lgvi<HeavyTop<double>> stepper(problem);
  Recorder rec;
  State<double> x = test::skew_initial_state();
  const auto summary = integrate_every(stepper, x, 0.0, 0.1, 1.05, 4, rec);
  ASSERT_EQ(summary.status, RunStatus::completed);
  ASSERT_EQ(rec.t.size(), 4u);
  EXPECT_EQ(rec.t[0], 0.0);
  EXPECT_DOUBLE_EQ(rec.t[1], 0.4);
  EXPECT_DOUBLE_EQ(rec.t[2], 0.8);
  EXPECT_EQ(rec.t[3], 1.05);  // t_end, after 10 grid steps and a side-step of 0.05
  EXPECT_EQ(summary.steps, 11);

  Recorder exact;
  State<double> x2 = test::skew_initial_state();
  integrate_every(stepper, x2, 0.0, 0.1, 0.8, 4, exact);
  EXPECT_EQ(exact.t.size(), 3u);  // 0, 0.4, 0.8: the end is a multiple, written once
}

// A torque that turns NaN after t = 0.5: the run stops with a status, x holds the last good state, and
// no observer ever sees a non-finite number.
struct PoisonedTop : HeavyTop<double> {
  Vec3<double> torque(const double& t, const Mat3<double>& R) const {
    if (t > 0.5) return Vec3<double>::Constant(std::numeric_limits<double>::quiet_NaN());
    return HeavyTop<double>::torque(R);
  }
};

TEST(Driver, NonFiniteTorqueStopsTheRunWithTheLastGoodState) {
  const test::FpTrapsOff traps_off;  // the torque is NaN on purpose: the driver must see it as a status
  PoisonedTop problem;
  static_cast<HeavyTop<double>&>(problem) = test::skew_heavy_top();
  static_assert(RigidBodyProblem<PoisonedTop>);
  Rkmk4<PoisonedTop> stepper(problem);
  bool saw_non_finite = false;
  auto observe = [&](double, const State<double>& xi) { saw_non_finite |= !is_finite(xi); };
  State<double> x = test::skew_initial_state();
  const std::vector<double> times = {0.3, 1.0};
  const auto summary = integrate_times(stepper, x, 0.0, 0.1, std::span<const double>(times), observe);
  EXPECT_EQ(summary.status, RunStatus::step_failed);
  EXPECT_EQ(summary.step_status, StepStatus::non_finite);
  // The step from 0.4 evaluates the torque at t ≤ 0.5; the one from 0.5 at 0.55: it fails.
  EXPECT_NEAR(summary.t, 0.5, 1e-15);
  EXPECT_FALSE(saw_non_finite);
  EXPECT_TRUE(is_finite(x));
}

TEST(Driver, MonitorCanStopTheRun) {
  const auto problem = test::skew_heavy_top();
  Lgvi<HeavyTop<double>> stepper(problem);
  State<double> x = test::skew_initial_state();
  std::int64_t calls = 0;
  auto monitor = [&](std::int64_t steps) {
    ++calls;
    return steps < 2 * monitor_stride;
  };
  const auto summary = integrate_to(stepper, x, 0.0, 0.001, 100.0, NoObserver{}, monitor);
  EXPECT_EQ(summary.status, RunStatus::stopped);
  EXPECT_EQ(summary.steps, 2 * monitor_stride);
  EXPECT_NEAR(summary.t, 2 * monitor_stride * 0.001, 1e-12);
  EXPECT_EQ(calls, 2);
}

TEST(Driver, RejectsInvalidArguments) {
  const auto problem = test::skew_heavy_top();
  Lgvi<HeavyTop<double>> stepper(problem);
  State<double> x = test::skew_initial_state();
  const std::vector<double> decreasing = {0.5, 0.4};
  EXPECT_THROW(integrate_times(stepper, x, 0.0, 0.1, std::span<const double>(decreasing)), std::invalid_argument);
  EXPECT_THROW(integrate_to(stepper, x, 0.0, 0.0, 1.0), std::invalid_argument);
  EXPECT_THROW(integrate_every(stepper, x, 0.0, 0.1, 1.0, 0), std::invalid_argument);
}

}  // namespace
}  // namespace lgi
