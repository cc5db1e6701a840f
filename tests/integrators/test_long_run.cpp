// Long runs, measured: 10⁶ steps on the heavy top, 10⁷ on the free body. The LGVI keeps R on SO(3) to round-off, its energy
// error bounded (no secular drift) and m·k to round-off; RKMK4 keeps R on SO(3) too but drifts in energy —
// the negative control that shows the drift test can fail.
#include "figures.hpp"
#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/core/invariants.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace lgi {
namespace {

struct Trajectory {
  std::vector<double> t, energy_error, momentum_error, orthogonality;
};

// Integrates n_steps of size h, sampling the relative energy error, the m·k error relative to |m| and
// ‖RᵀR − I‖ every `every` steps. (m·k is measured against |m|, the scale of its round-off, because m·k
// itself may be near zero: for the skew top m·k = −0.10 while |m| = 1.85.)
template <template <class> class Method>
Trajectory long_run(const HeavyTop<double>& problem, const State<double>& x0, double h, std::int64_t n_steps,
             std::int64_t every) {
  Method<HeavyTop<double>> stepper(problem);
  const double E0 = energy(problem, x0);
  const double mk0 = problem.invariants(x0)[0];
  const double m0 = spatial_momentum(problem.inertia, x0).norm();
  Trajectory run;
  auto observe = [&](double t, const State<double>& x) {
    run.t.push_back(t);
    run.energy_error.push_back((energy(problem, x) - E0) / std::abs(E0));
    run.momentum_error.push_back((problem.invariants(x)[0] - mk0) / m0);
    run.orthogonality.push_back(so3::orthogonality_error(x.R));
  };
  State<double> x = x0;
  const auto summary = integrate_every(stepper, x, 0.0, h, h * static_cast<double>(n_steps), every, observe);
  EXPECT_EQ(summary.status, RunStatus::completed);
  EXPECT_EQ(summary.steps, n_steps);
  return run;
}

double max_abs(const std::vector<double>& v, std::size_t from, std::size_t to) {
  double m = 0;
  for (std::size_t i = from; i < to; ++i) m = std::max(m, std::abs(v[i]));
  return m;
}

// Largest |error| in the last tenth of the run over the largest in the first tenth: ≈ 1 for a bounded
// error, ≈ 10 (or more) for one growing linearly from zero.
double growth_ratio(const std::vector<double>& err) {
  const std::size_t n = err.size(), tenth = n / 10;
  return max_abs(err, n - tenth, n) / max_abs(err, 1, tenth);
}

// The change of the mean (signed) error between the first and the last tenth, relative to the largest
// |error| of the run: a bounded error oscillating about a fixed mean gives ≈ 0; a drift from 0 to A
// gives 0.9. Sensitive to a drift much smaller than the oscillation, which growth_ratio is not.
double mean_shift(const std::vector<double>& err) {
  const std::size_t n = err.size(), tenth = n / 10;
  double first = 0, last = 0;
  for (std::size_t i = 0; i < tenth; ++i) {
    first += err[i];
    last += err[n - tenth + i];
  }
  return std::abs(last - first) / static_cast<double>(tenth) / max_abs(err, 0, n);
}

TEST(LongRun, LgviHeavyTopMillionSteps) {
  const auto problem = HeavyTop<double>::hairer_vilmart();
  const Trajectory run = long_run<Lgvi>(problem, test::hairer_vilmart_state(problem), 0.01, 1'000'000, 100);
  const double orth = max_abs(run.orthogonality, 0, run.orthogonality.size());
  const double mk = max_abs(run.momentum_error, 0, run.momentum_error.size());
  const double energy = max_abs(run.energy_error, 0, run.energy_error.size());
  const double growth = growth_ratio(run.energy_error);
  const double shift = mean_shift(run.energy_error);
  // For this top m·k = −0.9 and |m| = 2.03: relative to m·k itself, as the acceptance states.
  const double mk_rel = mk * spatial_momentum(problem.inertia, test::hairer_vilmart_state(problem)).norm() /
                        std::abs(problem.invariants(test::hairer_vilmart_state(problem))[0]);
  std::printf("LGVI 1e6 steps h=0.01: max |RtR-I| %.3e, max m.k error / |m.k| %.3e, max rel. energy error %.3e, "
              "energy growth ratio (last/first tenth) %.3f, mean shift %.4f\n",
              orth, mk_rel, energy, growth, shift);
  test::expect_figure("|RtR - I| after 1e6 steps, lgvi", orth, test::orthogonality_walk_bound(1e6));
  test::expect_figure("m.k error / |m.k| after 1e6 steps, lgvi, HV heavy top", mk_rel, 1e-12);
  EXPECT_LT(growth, 1.5);   // bounded: the last tenth's error no larger than the first's (+50 %)
  EXPECT_LT(shift, 0.05);   // and no drift of its mean
  EXPECT_LT(energy, 1e-3);  // O(h²) for h = 0.01
}

TEST(LongRun, LgviSkewHeavyTopMillionSteps) {
  const auto problem = test::skew_heavy_top();
  const Trajectory run = long_run<Lgvi>(problem, test::skew_initial_state(), 0.01, 1'000'000, 100);
  const double growth = growth_ratio(run.energy_error);
  const double shift = mean_shift(run.energy_error);
  std::printf("LGVI skew top 1e6 steps: max |RtR-I| %.3e, max m.k error / |m| %.3e, energy growth ratio %.3f, "
              "mean shift %.4f\n",
              max_abs(run.orthogonality, 0, run.orthogonality.size()),
              max_abs(run.momentum_error, 0, run.momentum_error.size()), growth, shift);
  test::expect_figure("|RtR - I| after 1e6 steps, lgvi, skew top", max_abs(run.orthogonality, 0, run.orthogonality.size()),
                      test::orthogonality_walk_bound(1e6));
  test::expect_figure("m.k error / |m| after 1e6 steps, lgvi, skew top",
                      max_abs(run.momentum_error, 0, run.momentum_error.size()), 2e-13);
  EXPECT_LT(growth, 1.5);
  EXPECT_LT(shift, 0.05);
}

TEST(LongRun, Rkmk4StaysOnTheGroupButDriftsInEnergy) {
  const auto problem = HeavyTop<double>::hairer_vilmart();
  const Trajectory fine = long_run<Rkmk4>(problem, test::hairer_vilmart_state(problem), 0.01, 1'000'000, 100);
  const double orth = max_abs(fine.orthogonality, 0, fine.orthogonality.size());
  std::printf("RKMK4 1e6 steps h=0.01: max |RtR-I| %.3e, energy growth ratio %.3f, final rel. energy error %.3e\n",
              orth, growth_ratio(fine.energy_error), fine.energy_error.back());
  test::expect_figure("|RtR - I| after 1e6 steps, rkmk4 (test_long_run)", orth, test::orthogonality_walk_bound(1e6));

  // Negative control (NUMERICS.md: RK4, RKMK4, CF4 drift linearly at h = 0.05): the growth test flags it.
  const Trajectory coarse = long_run<Rkmk4>(problem, test::hairer_vilmart_state(problem), 0.05, 200'000, 20);
  const double growth = growth_ratio(coarse.energy_error);
  const double shift = mean_shift(coarse.energy_error);
  std::printf("RKMK4 2e5 steps h=0.05: energy growth ratio %.3f, mean shift %.3f, final rel. energy error %.3e\n",
              growth, shift, coarse.energy_error.back());
  EXPECT_GT(growth, 5.0);
  EXPECT_GT(shift, 0.5);
}

// The long-run figure (docs/findings.md) at CI size: 10⁷ LGVI steps on the Hairer–Vilmart free body (h = 0.01, T = 10⁵).
// For the free body the LGVI is the discrete Moser–Veselov map, which conserves E and |m| exactly: what is
// left is rounding, a random walk (figures.hpp for R; E and m are held to 1.2e-12 and 1e-12). The 10⁸-step run itself is benchmark-sized: `lgi run benchmarks/long_run_free_body.json` (README).
TEST(LongRun, LgviFreeBodyTenMillionSteps) {
  const auto body = FreeBody<double>::hairer_vilmart();
  const State<double> x0 = test::hairer_vilmart_state(body);
  Lgvi<FreeBody<double>> stepper(body);
  const double E0 = energy(body, x0);
  const Vec3<double> m0 = spatial_momentum(body.inertia, x0);
  double orth = 0, e = 0, m = 0;
  State<double> x = x0;
  const auto summary = integrate_every(stepper, x, 0.0, 0.01, 1e5, 100'000, [&](double, const State<double>& xt) {
    orth = std::max(orth, so3::orthogonality_error(xt.R));
    e = std::max(e, std::abs(energy(body, xt) - E0) / E0);
    m = std::max(m, (spatial_momentum(body.inertia, xt) - m0).norm() / m0.norm());
  });
  std::printf("LGVI free body 1e7 steps h=0.01: max |RtR-I| %.3e, max rel. energy error %.3e, max |m - m0|/|m0| %.3e\n",
              orth, e, m);
  EXPECT_EQ(summary.steps, 10'000'000);
  test::expect_figure("|RtR - I| after 1e7 steps, lgvi, free body", orth, test::orthogonality_walk_bound(1e7));
  test::expect_figure("relative energy error over 1e7 steps, lgvi, free body", e, 1.2e-12);
  test::expect_figure("|m - m0| / |m0| over 1e7 steps, lgvi, free body", m, 1e-12);
}

// Small steady steps: h|Ω| = 5e-6 repeats the same rounding of F's diagonal every step unless the
// increment F − I is formed without the 1 (core/so3.hpp); then ‖RᵀR − I‖ and m·k stay a random walk.
// (Measured with R·F formed directly: ‖RᵀR − I‖ = 2.9e-11 and m·k/|m| = 1.5e-11 at the end, 100× more.)
TEST(LongRun, TinyStepsDoNotAccumulateRounding) {
  HeavyTop<double> top{Vec3<double>(2.0, 2.0, 1.0).asDiagonal(), 1.0, Vec3<double>(0, 0.6, 0.8), Vec3<double>::UnitZ()};
  const State<double> x0{Mat3<double>::Identity(), Vec3<double>(0.1, 0.2, 5.0)};
  for (const bool lgvi : {true, false}) {
    const Trajectory run = lgvi ? long_run<Lgvi>(top, x0, 1e-6, 3'000'000, 300'000)
                                : long_run<Rkmk4>(top, x0, 1e-6, 3'000'000, 300'000);
    const double orth = max_abs(run.orthogonality, 0, run.orthogonality.size());
    std::printf("%s 3e6 steps h=1e-6: max |RtR-I| %.3e, max m.k error / |m| %.3e\n", lgvi ? "LGVI" : "RKMK4", orth,
                max_abs(run.momentum_error, 0, run.momentum_error.size()));
    const double mk = max_abs(run.momentum_error, 0, run.momentum_error.size());
    if (lgvi) {
      test::expect_figure("|RtR - I| after 3e6 steps of h|Omega| = 5e-6, lgvi", orth, 3e-13);
      test::expect_figure("m.k error / |m| after 3e6 steps of h|Omega| = 5e-6, lgvi", mk, 1.5e-13);
    } else {
      test::expect_figure("|RtR - I| after 3e6 steps of h|Omega| = 5e-6, rkmk4", orth, test::orthogonality_walk_bound(3e6));
      test::expect_figure("m.k error / |m| after 3e6 steps of h|Omega| = 5e-6, rkmk4", mk, 2.5e-13);
    }
  }
}

// Negative control of the orthogonality bound (figures.hpp): a steady rotation, F = exp(hΩ̂) the same every step,
// 3·10⁶ steps of h|Ω| = 5e-6, updated as R + R·(F − I) with F − I formed without the 1 (so3::exp_increment, as the
// integrators do) and as R·F. The product rounds F's diagonal 1 − O(θ²) the same way every step, so its ‖RᵀR − I‖
// grows linearly, past ten times the bound; the increment stays a random walk within it.
TEST(LongRun, OrthogonalityBoundFailsTheProductUpdate) {
  const Vec3<double> w = 1e-6 * Vec3<double>(0.1, 0.2, 5.0);
  const Mat3<double> D = so3::exp_increment(w);
  const Mat3<double> F = Mat3<double>::Identity() + D;
  Mat3<double> increment = so3::exp(Vec3<double>(0.3, -0.2, 0.1)), product = increment;
  for (int n = 0; n < 3'000'000; ++n) {
    increment = (increment + increment * D).eval();
    product = (product * F).eval();
  }
  const double bound = test::orthogonality_walk_bound(3e6);
  std::printf("steady rotation, 3e6 steps of h|Omega| = 5e-6: |RtR - I| %.3e updated as R + R (F - I), %.3e as R F "
              "(bound %.3e)\n",
              so3::orthogonality_error(increment), so3::orthogonality_error(product), bound);
  EXPECT_LE(so3::orthogonality_error(increment), bound);
  EXPECT_GT(so3::orthogonality_error(product), 10 * bound);
}

}  // namespace
}  // namespace lgi
