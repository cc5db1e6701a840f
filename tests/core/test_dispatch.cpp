// tests/core/test_dispatch.cpp — the runtime-dispatched copies of the splitting and RKMK steps (core/scalar.hpp,
// LGI_DISPATCH_CLONES; integrators/splitting.hpp, integrators/rkmk.hpp) give the same results bit for bit as the
// step compiled for the baseline instruction set. This executable is the one test built with the copies on: step()
// (and an RKMK pair's attempt()) goes through the copy the loader picked for this CPU (AVX2 where it has it),
// step_inline() (attempt_inline()) is the baseline code of this translation unit. Each method runs 3000 steps both
// ways from the same state, on the Hairer–Vilmart heavy top (diagonal J), the skew top of test_problems.hpp
// (non-diagonal J, z0 and k off the axes: the RKMK steps in principal axes) and a free body; the final R, Ω and
// the internal state must match to the last bit, and each trial step's error estimate too.
#include "test_problems.hpp"

#include <lgi/integrators/rkmk.hpp>
#include <lgi/integrators/splitting.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>

namespace lgi {
namespace {

template <class S, class P>
void same_bits(const char* name, const P& problem, const State<double>& x0, double h) {
  S a(problem), b(problem);
  auto ya = a.to_internal(x0, 0.0);
  auto yb = b.to_internal(x0, 0.0);
  for (int n = 0; n < 3000; ++n) {
    ASSERT_EQ(a.step(ya, n * h, h), StepStatus::ok) << name;
    ASSERT_EQ(b.step_inline(yb, n * h, h), StepStatus::ok) << name;
  }
  const State<double> xa = a.to_state(ya), xb = b.to_state(yb);
  EXPECT_EQ(std::memcmp(xa.R.data(), xb.R.data(), sizeof(double) * 9), 0) << name;
  EXPECT_EQ(std::memcmp(xa.Omega.data(), xb.Omega.data(), sizeof(double) * 3), 0) << name;
  if constexpr (requires { ya.Pi; })  // the splittings' internal momentum
    EXPECT_EQ(std::memcmp(ya.Pi.data(), yb.Pi.data(), sizeof(double) * 3), 0) << name;
  else  // RKMK: (R, Ω) in the internal frame
    EXPECT_EQ(std::memcmp(ya.Omega.data(), yb.Omega.data(), sizeof(double) * 3), 0) << name;
  // the two runs are not trivially the same state: 3000 steps moved it
  EXPECT_GT((xa.Omega - x0.Omega).norm(), 1e-3) << name;
  if constexpr (requires(const S& s, const typename S::Internal& z, typename S::Internal& z1, double& e,
                          typename S::Dense& d) { s.attempt(z, 0.0, 0.0, z1, e, d); }) {
    // an embedded pair: its trial steps, each one accepted
    StepperOptions tolerances;
    tolerances.rtol = 1e-9;
    tolerances.atol = 1e-12;
    const S pa(problem, tolerances), pb(problem, tolerances);
    typename S::Dense da, db;
    auto za = pa.to_internal(x0, 0.0), zb = pb.to_internal(x0, 0.0);
    for (int n = 0; n < 3000; ++n) {
      auto za1 = za, zb1 = zb;
      double ea = 0, eb = 0;
      ASSERT_EQ(pa.attempt(za, n * h, h, za1, ea, da), StepStatus::ok) << name;
      ASSERT_EQ(pb.attempt_inline(zb, n * h, h, zb1, eb, db), StepStatus::ok) << name;
      ASSERT_EQ(std::memcmp(&ea, &eb, sizeof ea), 0) << name << ": error estimate of trial step " << n;
      za = za1;
      zb = zb1;
    }
    EXPECT_EQ(std::memcmp(za.R.data(), zb.R.data(), sizeof(double) * 9), 0) << name << " (trial steps)";
    EXPECT_EQ(std::memcmp(za.Omega.data(), zb.Omega.data(), sizeof(double) * 3), 0) << name << " (trial steps)";
  }
}

template <template <class> class M>
void every_case(const char* name) {
  HeavyTop<double> hv;
  hv.inertia = Vec3<double>(0.6, 0.8, 1.0).asDiagonal();  // Hairer–Vilmart heavy top (NUMERICS.md)
  hv.b = 1.0;
  const State<double> x_hv{Mat3<double>::Identity(), hv.inertia.inverse() * Vec3<double>(1.8, 0.4, -0.9)};
  same_bits<M<HeavyTop<double>>>(name, hv, x_hv, 0.01);
  same_bits<M<HeavyTop<double>>>(name, test::skew_heavy_top(), test::skew_initial_state(), 0.01);
  const FreeBody<double> body{test::skew_heavy_top().inertia};
  same_bits<M<FreeBody<double>>>(name, body, test::skew_initial_state(), 0.01);
}

TEST(Dispatch, SplittingStepsEqualTheBaselineBitForBit) {
#if defined(LGI_DISPATCH_CLONES)
  std::printf("dispatched copies on; this CPU %s AVX2, so step() runs the %s copy\n",
              __builtin_cpu_supports("avx2") ? "has" : "lacks", __builtin_cpu_supports("avx2") ? "avx2" : "default");
#else
  std::printf("dispatched copies off for this compiler or target: step() is step_inline()\n");
#endif
  every_case<SplitDmv>("split_dmv");
  every_case<SplitDmv4>("split_dmv4");
  every_case<SplitDmv10>("split_dmv10");
  every_case<SplitAxes>("split_axes");
}

TEST(Dispatch, RkmkStepsAndTrialStepsEqualTheBaselineBitForBit) {
  every_case<Rkmk4>("rkmk4");
  every_case<RkmkDp5Cayley>("rkmk_dp5_cayley");
  every_case<RkmkVern9>("rkmk_vern9");
  every_case<RkmkVern9Cayley>("rkmk_vern9_cayley");
}

// Negative control: the same steps compiled with FMA contraction (dispatch_fma_control.cpp, a program of its own)
// end in other bits, so the comparison above would fail a copy whose flags contracted a·b + c.
TEST(Dispatch, AContractedCopyWouldFailTheComparison) {
#if defined(LGI_DISPATCH_FMA_CONTROL)
  if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma")) GTEST_SKIP() << "this CPU has no AVX2 and FMA";
  const HeavyTop<double> top = test::skew_heavy_top();
  SplitDmv<HeavyTop<double>> stepper(top);
  auto y = stepper.to_internal(test::skew_initial_state(), 0.0);
  for (int n = 0; n < 3000; ++n) ASSERT_EQ(stepper.step_inline(y, n * 0.01, 0.01), StepStatus::ok);
  const State<double> x = stepper.to_state(y);
  std::FILE* pipe = popen(LGI_DISPATCH_FMA_CONTROL, "r");
  ASSERT_NE(pipe, nullptr);
  int differ = 0, read = 0;
  double largest = 0;
  for (int i = 0; i < 12; ++i) {
    std::uint64_t bits = 0;
    if (std::fscanf(pipe, "%" SCNx64, &bits) != 1) break;
    ++read;
    double v;
    std::memcpy(&v, &bits, sizeof v);
    const double mine = i < 9 ? x.R.data()[i] : x.Omega[i - 9];
    differ += std::memcmp(&v, &mine, sizeof v) != 0;
    largest = std::max(largest, std::abs(v - mine));
  }
  ASSERT_EQ(pclose(pipe), 0);
  ASSERT_EQ(read, 12);
  std::printf("split_dmv, skew top, 3000 steps: the FMA-contracted copy differs in %d of 12 numbers, by up to %.2e\n",
              differ, largest);
  EXPECT_GT(differ, 0);
#else
  GTEST_SKIP() << "no FMA control program in this build (x86-64 with GCC only)";
#endif
}

}  // namespace
}  // namespace lgi
