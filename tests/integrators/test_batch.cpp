// Batches (core/batch.hpp, integrators/batch_lgvi.hpp, batch_rkmk.hpp) against single-body runs, bit for bit: the
// LGVI and RKMK4 kernels (baseline lane blocks of 4, AVX2 blocks of 8, AVX-512 blocks of 16, per_body: each a test
// instance, skipped with a message where the CPU lacks it) on the heavy top with per-body b and on the free body;
// random attitudes and a spread of |Ω| so that Newton takes different iteration counts per body (LGVI) and every
// branch of exp's coefficients is taken — Taylor, polynomial sin, libm beyond π — in neighbouring lanes (RKMK4);
// batch sizes that are not multiples of the lane width; 1, 2 and 3 threads; bodies that fail (not_converged,
// non_finite) in the middle of a run; the generic per-body driver with RKMK4 and with per-body problems.
// The reference is always a fresh single-body Lgvi (or Rkmk4) stepper stepped by hand.
#include "batch_kernel_controls.hpp"
#include "fp_traps.hpp"

#include <lgi/core/batch.hpp>
#include <lgi/core/so3.hpp>
#include <lgi/integrators/batch_lgvi.hpp>
#include <lgi/integrators/batch_rkmk.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <ostream>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace lgi {

// Test parameters print as their names.
void PrintTo(BatchKernel k, std::ostream* os);
void PrintTo(BatchKernel k, std::ostream* os) { *os << to_string(k); }

namespace {

struct Outcome {
  State<double> x;
  StepStatus status = StepStatus::ok;
  std::int64_t steps = 0;
  std::int64_t newton = 0;  // LGVI Newton updates (0 for other methods)
};

// The single-body run: to_internal, step with t = t0 + n h until a failure, to_state.
template <class S>
Outcome single(S stepper, const State<double>& x0, double t0, double h, std::int64_t n_steps) {
  auto y = stepper.to_internal(x0, t0);
  Outcome o;
  for (; o.steps < n_steps; ++o.steps) {
    o.status = stepper.step(y, t0 + static_cast<double>(o.steps) * h, h);
    if (o.status != StepStatus::ok) break;
  }
  o.x = stepper.to_state(y);
  if constexpr (requires { stepper.newton_iterations(); }) o.newton = stepper.newton_iterations();
  return o;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Body i of the batch equals its reference bit for bit (state, status and steps).
bool identical(const BodyBatch& batch, std::size_t i, const Outcome& ref) {
  const State<double> x = batch.state(i);
  bool same = batch.status[i] == ref.status && batch.steps[i] == ref.steps;
  for (int e = 0; e < 9; ++e) same = same && same_bits(x.R.data()[e], ref.x.R.data()[e]);
  for (int j = 0; j < 3; ++j) same = same && same_bits(x.Omega(j), ref.x.Omega(j));
  return same;
}

// Bit-for-bit comparison of body i with its reference; reports the first difference.
void expect_identical(const BodyBatch& batch, std::size_t i, const Outcome& ref, const char* what) {
  const State<double> x = batch.state(i);
  EXPECT_TRUE(identical(batch, i, ref)) << what << ": body " << i << " status " << to_string(batch.status[i]) << " / "
                    << to_string(ref.status) << ", steps " << batch.steps[i] << " / " << ref.steps
                    << ", R(0,0) " << x.R(0, 0) << " / " << ref.x.R(0, 0) << " (diff " << x.R(0, 0) - ref.x.R(0, 0)
                    << "), Omega(0) " << x.Omega(0) << " / " << ref.x.Omega(0);
}

// n bodies: uniformly random attitudes, Ω in a random direction with |Ω| log-uniform in [0.01, omega_max].
std::vector<State<double>> random_bodies(std::size_t n, double omega_max, unsigned seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<State<double>> x(n);
  for (auto& s : x) {
    const Vec3<double> axis(normal(gen), normal(gen), normal(gen));
    s.R = so3::exp(Vec3<double>(axis.normalized() * (3.0 * unit(gen))));
    const Vec3<double> dir(normal(gen), normal(gen), normal(gen));
    s.Omega = dir.normalized() * (0.01 * std::pow(omega_max / 0.01, unit(gen)));
  }
  return x;
}

BodyBatch make_batch(const std::vector<State<double>>& x) {
  BodyBatch batch(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) batch.set_state(i, x[i]);
  return batch;
}

// Every kernel, one test instance each: an ISA kernel that this program or CPU lacks is skipped with a message
// (never a silent pass); test_batch links lgi::batch, so on an x86-64 CPU with AVX2/AVX-512 they all run.
const BatchKernel all_kernels[] = {BatchKernel::baseline, BatchKernel::avx2, BatchKernel::avx512, BatchKernel::per_body};

class BatchKernels : public ::testing::TestWithParam<BatchKernel> {
 protected:
  void SetUp() override {
    if (!batch_kernel_available(GetParam()))
      GTEST_SKIP() << "the " << to_string(GetParam())
                   << " kernel is not available here (lgi::batch not linked, or the CPU lacks the instruction set): "
                      "its bit-identity is NOT checked on this machine";
  }
};

std::string kernel_test_name(const ::testing::TestParamInfo<BatchKernel>& info) { return to_string(info.param); }

TEST(Batch, KernelAvailabilityIsReported) {
  // Records which kernels the other tests compared, and that availability follows the CPU when lgi::batch is linked.
  std::printf("kernels compared: baseline, per_body%s%s\n", batch_avx2_available() ? ", avx2" : " (no avx2 kernel)",
              batch_avx512_available() ? ", avx512" : " (no avx512 kernel)");
#if defined(LGI_HAVE_BATCH_AVX2)
  EXPECT_EQ(batch_avx2_available(), __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"));
#endif
#if defined(LGI_HAVE_BATCH_AVX512)
  EXPECT_EQ(batch_avx512_available(), __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq"));
#endif
  EXPECT_EQ(batch_widest_kernel(), batch_avx512_available() ? BatchKernel::avx512
                                   : batch_avx2_available() ? BatchKernel::avx2
                                                            : BatchKernel::baseline);
}

// automatic picks the widest kernel available, and says so.
TEST(Batch, AutomaticPicksTheWidestKernel) {
  const auto x0 = random_bodies(5, 5.0, 6);
  BodyBatch batch = make_batch(x0);
  EXPECT_EQ(integrate_batch_lgvi(HeavyTop<double>::hairer_vilmart(), batch, 0.0, 0.01, 3), batch_widest_kernel());
}

// Heavy top, per-body b, 37 bodies (not a multiple of the lane widths 2 and 4), 400 steps, h = 0.05, |Ω| up to 15 (h|Ω| up to
// 0.75 at the start: Newton takes 2 updates a step at small h|Ω|, more for the fast bodies).
TEST_P(BatchKernels, HeavyTopLgviEqualsSingleBodyBitForBit) {
  const BatchKernel kernel = GetParam();
  const HeavyTop<double> top = HeavyTop<double>::hairer_vilmart();
  const std::size_t n = 37;
  const double t0 = 0.25, h = 0.05;
  const std::int64_t steps = 400;
  const auto x0 = random_bodies(n, 15.0, 1);
  std::vector<double> b(n);
  for (std::size_t i = 0; i < n; ++i) b[i] = 3.0 * static_cast<double>(i % 7) / 7.0;  // b = 0 (free) … 2.57

  std::vector<Outcome> ref(n);
  std::set<std::int64_t> newton_counts;
  for (std::size_t i = 0; i < n; ++i) {
    HeavyTop<double> p = top;
    p.b = b[i];
    ref[i] = single(Lgvi<HeavyTop<double>>(p), x0[i], t0, h, steps);
    ASSERT_EQ(ref[i].status, StepStatus::ok) << "body " << i;
    newton_counts.insert(ref[i].newton);
  }
  // The spread of |Ω| makes Newton's work differ per body (else the masking would go untested).
  EXPECT_GE(newton_counts.size(), 10u);
  EXPECT_LT(*newton_counts.begin() * 2, *newton_counts.rbegin());

  for (const int threads : {1, 2, 3}) {
    BodyBatch batch = make_batch(x0);
    const BatchKernel ran = integrate_batch_lgvi(top, batch, t0, h, steps, {}, {.threads = threads}, b, kernel);
    EXPECT_EQ(ran, kernel);
    for (std::size_t i = 0; i < n; ++i) expect_identical(batch, i, ref[i], to_string(kernel));
  }
}

TEST_P(BatchKernels, FreeBodyLgviEqualsSingleBodyBitForBit) {
  const BatchKernel kernel = GetParam();
  const FreeBody<double> body = FreeBody<double>::hairer_vilmart();
  const std::size_t n = 21;
  const double t0 = 0, h = 0.1;
  const std::int64_t steps = 300;
  const auto x0 = random_bodies(n, 20.0, 2);
  std::vector<Outcome> ref(n);
  for (std::size_t i = 0; i < n; ++i) ref[i] = single(Lgvi<FreeBody<double>>(body), x0[i], t0, h, steps);
  for (const int threads : {1, 3}) {
    BodyBatch batch = make_batch(x0);
    integrate_batch_lgvi(body, batch, t0, h, steps, {}, {.threads = threads}, {}, kernel);
    for (std::size_t i = 0; i < n; ++i) expect_identical(batch, i, ref[i], to_string(kernel));
  }
}

// Bodies that fail: with at most 3 Newton updates a step, a heavy top with b = 100 falling from a tilt of 1.2 rad
// stops with not_converged after a few good steps and the fastest bodies at step 0; b = 1e306 overflows the
// torque (non_finite); a NaN initial velocity fails at step 0. Their lanes' neighbours must come out exactly
// as alone.
TEST_P(BatchKernels, LgviFailingBodiesKeepLastGoodStateAndDoNotDisturbOtherLanes) {
  const BatchKernel kernel = GetParam();
  const lgi::test::FpTrapsOff traps_off;  // the failing bodies make NaN and ∞ on purpose
  const HeavyTop<double> top = HeavyTop<double>::hairer_vilmart();
  const std::size_t n = 19;
  const double t0 = 0, h = 0.05;
  const std::int64_t steps = 300;
  const StepperOptions options{.tolerance = 1e-14, .max_iterations = 3};
  auto x0 = random_bodies(n, 25.0, 3);
  std::vector<double> b(n, 1.0);
  b[2] = 100;
  x0[2].R = so3::exp(Vec3<double>(1.2, 0.3, 0));
  x0[2].Omega = Vec3<double>(0.3, 0.2, 1).normalized() * 5.0;
  b[5] = 1e306;                                            // torque overflows as the top moves
  x0[9].Omega(1) = std::numeric_limits<double>::quiet_NaN();  // non-finite from the start
  std::vector<Outcome> ref(n);
  int not_converged_late = 0, non_finite = 0, ok = 0;
  for (std::size_t i = 0; i < n; ++i) {
    HeavyTop<double> p = top;
    p.b = b[i];
    ref[i] = single(Lgvi<HeavyTop<double>>(p, options), x0[i], t0, h, steps);
    not_converged_late += ref[i].status == StepStatus::not_converged && ref[i].steps > 0;
    non_finite += ref[i].status == StepStatus::non_finite;
    ok += ref[i].status == StepStatus::ok;
  }
  // The scenario is what it claims to be.
  EXPECT_GE(not_converged_late, 1);
  EXPECT_GE(non_finite, 2);
  EXPECT_GE(ok, 5);
  EXPECT_EQ(ref[9].status, StepStatus::non_finite);
  EXPECT_EQ(ref[9].steps, 0);
  EXPECT_EQ(ref[5].status, StepStatus::non_finite);
  EXPECT_EQ(ref[2].status, StepStatus::not_converged);
  EXPECT_GT(ref[2].steps, 0);

  for (const int threads : {1, 2}) {
    BodyBatch batch = make_batch(x0);
    integrate_batch_lgvi(top, batch, t0, h, steps, options, {.threads = threads}, b, kernel);
    for (std::size_t i = 0; i < n; ++i) expect_identical(batch, i, ref[i], to_string(kernel));
  }
}

// A non-diagonal J is outside the kernels: automatic runs the stepper per body, with the same bits.
TEST(Batch, NonDiagonalInertiaRunsPerBody) {
  HeavyTop<double> top = HeavyTop<double>::hairer_vilmart();
  top.inertia(0, 1) = top.inertia(1, 0) = 0.05;
  const auto x0 = random_bodies(9, 10.0, 4);
  BodyBatch batch = make_batch(x0);
  EXPECT_EQ(integrate_batch_lgvi(top, batch, 0.0, 0.05, 100), BatchKernel::per_body);
  for (std::size_t i = 0; i < x0.size(); ++i)
    expect_identical(batch, i, single(Lgvi<HeavyTop<double>>(top), x0[i], 0.0, 0.05, 100), "per_body");
}

// The generic driver with another method (RKMK4) and per-body problems, 1 and 3 threads.
TEST(Batch, GenericDriverRkmk4PerBodyProblemsEqualSingleBody) {
  const auto x0 = random_bodies(11, 5.0, 5);
  const auto problem_of = [](std::size_t i) {
    HeavyTop<double> p = HeavyTop<double>::hairer_vilmart();
    p.b = 0.25 * static_cast<double>(i);
    return p;
  };
  for (const int threads : {1, 3}) {
    BodyBatch batch = make_batch(x0);
    integrate_batch<Rkmk4>(problem_of, batch, 0.5, 0.02, 200, {}, {.threads = threads});
    for (std::size_t i = 0; i < x0.size(); ++i)
      expect_identical(batch, i, single(Rkmk4<HeavyTop<double>>(problem_of(i)), x0[i], 0.5, 0.02, 200), "rkmk4");
  }
}

TEST(Batch, BadArgumentsThrowNamingTheArgument) {
  const HeavyTop<double> top = HeavyTop<double>::hairer_vilmart();
  BodyBatch batch(5);
  const std::vector<double> b(4, 1.0);
  try {
    integrate_batch_lgvi(top, batch, 0.0, 0.1, 10, {}, {}, b);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("per-body b has 4 entries for 5 bodies"), std::string::npos) << e.what();
  }
  EXPECT_THROW(integrate_batch_lgvi(FreeBody<double>::hairer_vilmart(), batch, 0.0, 0.1, 10, {}, {}, b),
               std::invalid_argument);
  EXPECT_THROW(integrate_batch_lgvi(top, batch, 0.0, std::nan(""), 10), std::invalid_argument);
  EXPECT_THROW(integrate_batch_lgvi(top, batch, 0.0, 0.1, -1), std::invalid_argument);
  EXPECT_THROW(integrate_batch_lgvi(top, batch, 0.0, 0.1, 10, {}, {.threads = -1}), std::invalid_argument);
}

// ---- RKMK4 (integrators/batch_rkmk.hpp) ----

// The largest and smallest rotation angle h|Ω| over a reference run (a proxy for the angle of the step's
// exponential, h|Σ b_i U_i|, and of the stages' ones): which branches of so3::exp_coefficients a body exercises.
struct AngleRange {
  double lo = 1e300, hi = 0;
};
template <class P>
Outcome single_rkmk4(const P& p, const State<double>& x0, double t0, double h, std::int64_t n_steps, AngleRange& r) {
  Rkmk4<P> stepper(p);
  auto y = stepper.to_internal(x0, t0);
  Outcome o;
  for (; o.steps < n_steps; ++o.steps) {
    const double a = std::abs(h) * y.Omega.norm();
    r.lo = std::min(r.lo, a);
    r.hi = std::max(r.hi, a);
    o.status = stepper.step(y, t0 + static_cast<double>(o.steps) * h, h);
    if (o.status != StepStatus::ok) break;
  }
  o.x = stepper.to_state(y);
  return o;
}

// Heavy top, per-body b, 37 bodies (not a multiple of 2, 4, 8), h = 0.04, |Ω| log-uniform in [0.01, 120] and every
// sixth body at |Ω| = 85 … 115: the step angle h|Ω| runs from 4e-4 to 4.6, so every branch of exp_coefficients is
// taken — Taylor (θ < 0.1), the polynomial sin (0.1 ≤ θ ≤ π) and libm through the kernels' scalar fallback
// (θ > π) — in lanes next to each other.
TEST_P(BatchKernels, HeavyTopRkmk4EqualsSingleBodyBitForBit) {
  const BatchKernel kernel = GetParam();
  const HeavyTop<double> top = HeavyTop<double>::hairer_vilmart();
  const std::size_t n = 37;
  const double t0 = 0.5, h = 0.04;
  const std::int64_t steps = 150;
  auto x0 = random_bodies(n, 120.0, 7);
  for (std::size_t i = 1; i < n; i += 6) x0[i].Omega = x0[i].Omega.normalized() * (85.0 + 5.0 * static_cast<double>(i / 6));
  std::vector<double> b(n);
  for (std::size_t i = 0; i < n; ++i) b[i] = 3.0 * static_cast<double>(i % 5) / 5.0;
  std::vector<Outcome> ref(n);
  int taylor_only = 0, polynomial = 0, beyond_pi = 0, finite = 0;
  for (std::size_t i = 0; i < n; ++i) {
    HeavyTop<double> p = top;
    p.b = b[i];
    AngleRange r;
    ref[i] = single_rkmk4(p, x0[i], t0, h, steps, r);
    taylor_only += r.hi < 0.09;
    polynomial += r.lo > 0.11 && r.hi < 3.0;
    beyond_pi += r.hi > 3.3;
    finite += ref[i].status == StepStatus::ok;
  }
  // The scenario is what it claims to be.
  EXPECT_GE(taylor_only, 5);
  EXPECT_GE(polynomial, 5);
  EXPECT_GE(beyond_pi, 3);
  EXPECT_GE(finite, 30);
  for (const int threads : {1, 2, 3}) {
    BodyBatch batch = make_batch(x0);
    const BatchKernel ran = integrate_batch_rkmk4(top, batch, t0, h, steps, {}, {.threads = threads}, b, kernel);
    EXPECT_EQ(ran, kernel);
    for (std::size_t i = 0; i < n; ++i) expect_identical(batch, i, ref[i], to_string(kernel));
  }
}

TEST_P(BatchKernels, FreeBodyRkmk4EqualsSingleBodyBitForBit) {
  const BatchKernel kernel = GetParam();
  const FreeBody<double> body = FreeBody<double>::hairer_vilmart();
  const std::size_t n = 21;
  const double t0 = 0, h = 0.05;
  const std::int64_t steps = 200;
  auto x0 = random_bodies(n, 90.0, 8);
  for (std::size_t i = 2; i < n; i += 5) x0[i].Omega = x0[i].Omega.normalized() * (70.0 + 4.0 * static_cast<double>(i / 5));
  std::vector<Outcome> ref(n);
  int beyond_pi = 0;
  for (std::size_t i = 0; i < n; ++i) {
    AngleRange r;
    ref[i] = single_rkmk4(body, x0[i], t0, h, steps, r);
    beyond_pi += r.hi > 3.3;
  }
  EXPECT_GE(beyond_pi, 2);
  for (const int threads : {1, 3}) {
    BodyBatch batch = make_batch(x0);
    integrate_batch_rkmk4(body, batch, t0, h, steps, {}, {.threads = threads}, {}, kernel);
    for (std::size_t i = 0; i < n; ++i) expect_identical(batch, i, ref[i], to_string(kernel));
  }
}

// RKMK4 is explicit: a body fails when its state becomes non-finite. b = 1e306 overflows the torque after the top
// moves, a NaN in Ω fails at step 0, |Ω| = 1e155 overflows JΩ × Ω at once, and three bodies at |Ω| = 85, 100, 150
// (h|Ω| = 8.5 … 15, beyond RK4's stability) blow up after a few steps. Their neighbours must come out exactly as
// alone.
TEST_P(BatchKernels, Rkmk4FailingBodiesKeepLastGoodStateAndDoNotDisturbOtherLanes) {
  const BatchKernel kernel = GetParam();
  const lgi::test::FpTrapsOff traps_off;  // the failing bodies make NaN and ∞ on purpose
  const HeavyTop<double> top = HeavyTop<double>::hairer_vilmart();
  const std::size_t n = 19;
  const double t0 = 0, h = 0.1;
  const std::int64_t steps = 300;
  auto x0 = random_bodies(n, 120.0, 9);
  std::vector<double> b(n, 1.0);
  b[5] = 1e306;
  x0[9].Omega(1) = std::numeric_limits<double>::quiet_NaN();
  x0[12].Omega = Vec3<double>(1, -2, 0.5) * 1e155;
  x0[3].Omega = x0[3].Omega.normalized() * 85.0;
  x0[7].Omega = x0[7].Omega.normalized() * 100.0;
  x0[15].Omega = x0[15].Omega.normalized() * 150.0;
  std::vector<Outcome> ref(n);
  int failed_late = 0, ok = 0;
  for (std::size_t i = 0; i < n; ++i) {
    HeavyTop<double> p = top;
    p.b = b[i];
    ref[i] = single(Rkmk4<HeavyTop<double>>(p), x0[i], t0, h, steps);
    EXPECT_TRUE(ref[i].status == StepStatus::ok || ref[i].status == StepStatus::non_finite);
    failed_late += ref[i].status == StepStatus::non_finite && ref[i].steps > 0;
    ok += ref[i].status == StepStatus::ok;
  }
  EXPECT_EQ(ref[9].status, StepStatus::non_finite);
  EXPECT_EQ(ref[9].steps, 0);
  EXPECT_EQ(ref[12].status, StepStatus::non_finite);
  EXPECT_EQ(ref[5].status, StepStatus::non_finite);
  EXPECT_GE(failed_late, 4);
  EXPECT_GE(ok, 5);
  for (const int threads : {1, 2}) {
    BodyBatch batch = make_batch(x0);
    integrate_batch_rkmk4(top, batch, t0, h, steps, {}, {.threads = threads}, b, kernel);
    for (std::size_t i = 0; i < n; ++i) expect_identical(batch, i, ref[i], to_string(kernel));
  }
}

TEST(Batch, Rkmk4NonDiagonalInertiaRunsPerBodyAndBadArgumentsThrow) {
  HeavyTop<double> top = HeavyTop<double>::hairer_vilmart();
  top.inertia(0, 2) = top.inertia(2, 0) = 0.04;
  const auto x0 = random_bodies(9, 10.0, 10);
  BodyBatch batch = make_batch(x0);
  EXPECT_EQ(integrate_batch_rkmk4(top, batch, 0.0, 0.05, 100), BatchKernel::per_body);
  for (std::size_t i = 0; i < x0.size(); ++i)
    expect_identical(batch, i, single(Rkmk4<HeavyTop<double>>(top), x0[i], 0.0, 0.05, 100), "per_body");
  BodyBatch five(5);
  const std::vector<double> b(4, 1.0);
  try {
    integrate_batch_rkmk4(HeavyTop<double>::hairer_vilmart(), five, 0.0, 0.1, 10, {}, {}, b);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("per-body b has 4 entries for 5 bodies"), std::string::npos) << e.what();
  }
  EXPECT_THROW(integrate_batch_rkmk4(FreeBody<double>::hairer_vilmart(), five, 0.0, 0.1, 10, {}, {}, b),
               std::invalid_argument);
  EXPECT_THROW(integrate_batch_rkmk4(HeavyTop<double>::hairer_vilmart(), five, 0.0, 0.0, 10), std::invalid_argument);
  EXPECT_EQ(integrate_batch_rkmk4(HeavyTop<double>::hairer_vilmart(), five, 0.0, 0.1, 10), batch_widest_kernel());
}

#if defined(LGI_BATCH_CONTROLS)
// The negative controls (batch_kernel_controls.hpp): the AVX2 lane blocks compiled with FMA contraction, or with
// reassociated sums, on the scenario of HeavyTopLgviEqualsSingleBodyBitForBit / HeavyTopRkmk4EqualsSingleBodyBitForBit
// (37 heavy tops, per-body b): the comparison that holds the library's kernels to the single-body bits must fail
// them, while the library's own AVX2 blocks pass it on the same input.
TEST(Batch, ContractedOrReassociatedKernelsFailTheComparison) {
  if (!batch_kernel_available(BatchKernel::avx2))
    GTEST_SKIP() << "no AVX2 and FMA here: the negative controls of the AVX2 kernel cannot run";
  const HeavyTop<double> top = HeavyTop<double>::hairer_vilmart();
  const std::size_t n = 37, blocks = (n + 7) / 8;
  const double t0 = 0.5, h = 0.04;
  const std::int64_t steps = 150;
  const auto x0 = random_bodies(n, 30.0, 11);
  std::vector<double> b(n);
  for (std::size_t i = 0; i < n; ++i) b[i] = 3.0 * static_cast<double>(i % 5) / 5.0;
  std::vector<Outcome> lgvi_ref(n), rkmk4_ref(n);
  for (std::size_t i = 0; i < n; ++i) {
    HeavyTop<double> p = top;
    p.b = b[i];
    lgvi_ref[i] = single(Lgvi<HeavyTop<double>>(p), x0[i], t0, h, steps);
    rkmk4_ref[i] = single(Rkmk4<HeavyTop<double>>(p), x0[i], t0, h, steps);
  }
  const batch_kernel::LgviParams lp = batch_kernel::lgvi_params(top, StepperOptions{});
  const batch_kernel::Rkmk4Params rp = batch_kernel::rkmk4_params(top);
  // Bodies that differ from their single-body run, and the largest difference in R or Ω among them.
  const auto differing = [&](const std::vector<Outcome>& ref, const auto& run, double& largest) {
    BodyBatch batch = make_batch(x0);
    run(batch_kernel::bind_io(batch, b));
    int count = 0;
    largest = 0;
    for (std::size_t i = 0; i < n; ++i) {
      if (identical(batch, i, ref[i])) continue;
      ++count;
      const State<double> x = batch.state(i);
      largest = std::max({largest, (x.R - ref[i].x.R).cwiseAbs().maxCoeff(),
                          (x.Omega - ref[i].x.Omega).cwiseAbs().maxCoeff()});
    }
    return count;
  };
  namespace bk = batch_kernel;
  struct Case {
    const char* name;
    std::function<void(const bk::BatchIO&)> run;
    const std::vector<Outcome>* ref;
  };
  const Case cases[] = {
      {"lgvi, library avx2", [&](const bk::BatchIO& io) { bk::run_blocks_avx2(lp, io, 0, blocks, h, steps, true); }, &lgvi_ref},
      {"lgvi, contracted", [&](const bk::BatchIO& io) { bk::avx2_contracted::lgvi_control_blocks(lp, io, 0, blocks, h, steps, true); }, &lgvi_ref},
      {"lgvi, reassociated", [&](const bk::BatchIO& io) { bk::avx2_reassociated::lgvi_control_blocks(lp, io, 0, blocks, h, steps, true); }, &lgvi_ref},
      {"rkmk4, library avx2", [&](const bk::BatchIO& io) { bk::rkmk4_blocks_avx2(rp, io, 0, blocks, h, steps, true); }, &rkmk4_ref},
      {"rkmk4, contracted", [&](const bk::BatchIO& io) { bk::avx2_contracted::rkmk4_control_blocks(rp, io, 0, blocks, h, steps, true); }, &rkmk4_ref},
      {"rkmk4, reassociated", [&](const bk::BatchIO& io) { bk::avx2_reassociated::rkmk4_control_blocks(rp, io, 0, blocks, h, steps, true); }, &rkmk4_ref},
  };
  for (const Case& c : cases) {
    double largest = 0;
    const int count = differing(*c.ref, c.run, largest);
    std::printf("AVX2 lane blocks, %-20s %2d of %zu bodies differ from their single-body runs (largest |difference| "
                "%.2e)\n", c.name, count, n, largest);
    if (std::string(c.name).find("library") != std::string::npos)
      EXPECT_EQ(count, 0) << c.name;
    else
      EXPECT_GT(count, 0) << c.name << ": the negative control passes the bit-identity comparison";
  }
}
#endif

INSTANTIATE_TEST_SUITE_P(Batch, BatchKernels, ::testing::ValuesIn(all_kernels), kernel_test_name);

}  // namespace
}  // namespace lgi
