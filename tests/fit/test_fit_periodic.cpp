// Periodic orbits: Ω0 and the period T with the state returning to itself modulo the
// problem's symmetry, the step T/N for fixed N.
//
// Free asymmetric body: every motion of Ω is periodic; with Ω0's first component fixed (it fixes the phase on
// the orbit) the fit finds Ω0's other two components and T. The period of the fitted Ω0 is known exactly
// (Jacobi elliptic functions, problems/free_body_exact.hpp: 4K(κ)/|λ|), an independent reference: the fitted T
// differs from it by the discretisation error of the method (order 2 for LGVI, 4 for RKMK4), measured.
// Heavy top: R(T) = Exp(φk) R0, Ω(T) = Ω0 with φ, T and Ω0 unknown, from a guess near the small swing of a
// hanging asymmetric top.
#include "test_fit_data.hpp"

#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/free_body_exact.hpp>

#include <gtest/gtest.h>

#include <cstdio>

namespace lgi {
namespace {

template <template <class> class Method>
double free_body_period(const char* name, int steps) {
  const FreeBody<double> body = FreeBody<double>::hairer_vilmart();
  const State<double> x0 = test::hairer_vilmart_state(body);
  const double T_exact = static_cast<double>(FreeBodyExact<double>(body.inertia).solve(x0).period());
  State<double> guess = x0;
  guess.Omega(1) *= 1.05;
  guess.Omega(2) *= 0.95;
  const fit::Unknown unknowns[] = {{"initial.omega", {0}, {}, {}}, {"period", {}, {}, {}}};
  fit::PeriodicOptions options;
  options.steps = steps;
  const auto res = fit::fit_periodic<Method, 8>(body, guess, 1.05 * T_exact, unknowns, options);
  const double T_fit = res.at("period").value[0];
  const double T_ref = static_cast<double>(FreeBodyExact<double>(body.inertia).solve(res.initial).period());
  std::printf("%s free body, %d steps: residual %.2e, T = %.12f, exact period of the fitted Omega0 %.12f (difference "
              "%.2e), %d iterations, %.3f s\n", name, steps, res.max_residual, T_fit, T_ref, T_fit - T_ref, res.iterations,
              res.seconds);
  EXPECT_TRUE(res.usable) << res.report;
  EXPECT_LE(res.max_residual, 1e-10);
  return std::abs(T_fit - T_ref);
}

TEST(FitPeriodic, FreeBodyLgvi) {
  const double e1 = free_body_period<Lgvi>("lgvi", 1000), e2 = free_body_period<Lgvi>("lgvi", 2000);
  std::printf("lgvi: period error order %.2f\n", std::log2(e1 / e2));
  EXPECT_NEAR(std::log2(e1 / e2), 2.0, 0.1);
}

TEST(FitPeriodic, FreeBodyRkmk4) {
  // 500 steps, not fewer: RKMK4 does not conserve the free body's energy and |m|, and the drift over one period
  // (O(h⁵) per period) leaves a residual floor no Ω0, T can remove — measured 4.2e-10 at 250 steps, 1.3e-11 at 500.
  const double e1 = free_body_period<Rkmk4>("rkmk4", 500), e2 = free_body_period<Rkmk4>("rkmk4", 1000);
  std::printf("rkmk4: period error order %.2f\n", std::log2(e1 / e2));
  EXPECT_NEAR(std::log2(e1 / e2), 4.0, 0.3);
}

// The Hairer–Vilmart heavy top (moments 0.6, 0.8, 1.0; b = 1; k = z0 = e3) hanging (R z0 = −k at rest), started
// tilted by 0.6 rad about its body axis 1 with a small velocity off that axis, T guessed from the small-
// oscillation period 2π√(I1/b). Unknowns Ω0, T, φ.
template <template <class> class Method>
void heavy_top_orbit(const char* name) {
  const HeavyTop<double> top = HeavyTop<double>::hairer_vilmart();
  State<double> guess;
  guess.R = so3::exp(Vec3<double>(M_PI - 0.6, 0, 0));
  guess.Omega = Vec3<double>(0.0, 0.05, 0.05);
  const double T0 = 2 * M_PI * std::sqrt(0.6);
  const fit::Unknown unknowns[] = {{"initial.omega", {}, {}, {}}, {"period", {}, {}, {}}, {"phase", {}, {}, {}}};
  fit::PeriodicOptions options;
  options.steps = 1000;
  const auto res = fit::fit_periodic<Method, 8>(top, guess, T0, unknowns, options, 0.1);
  const Vec3<double> W = res.initial.Omega;
  // The orbit is not a rest point: the swing's angular velocity reaches O(1) (checked by integrating it).
  Method<HeavyTop<double>> stepper(top);
  State<double> x = res.initial;
  double w_max = 0;
  integrate_every(stepper, x, 0.0, res.period / options.steps, res.period, 10,
                  [&](double, const State<double>& s) { w_max = std::max(w_max, s.Omega.norm()); });
  std::printf("%s heavy top: residual %.2e, T = %.10f (guess %.4f), phase %.3e, Omega0 = (%.3e, %.3e, %.3e), max |Omega| "
              "on the orbit %.3f, %d iterations, %.3f s\n", name, res.max_residual, res.period, T0, res.phase, W(0), W(1),
              W(2), w_max, res.iterations, res.seconds);
  EXPECT_TRUE(res.usable) << res.report;
  EXPECT_LE(res.max_residual, 1e-10);
  EXPECT_GT(w_max, 0.3);
}

TEST(FitPeriodic, HeavyTopLgvi) { heavy_top_orbit<Lgvi>("lgvi"); }
TEST(FitPeriodic, HeavyTopRkmk4) { heavy_top_orbit<Rkmk4>("rkmk4"); }

}  // namespace
}  // namespace lgi
