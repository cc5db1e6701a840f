// tests/jet_check.hpp — ceres::Jet through a method on the skew heavy top, against central differences.
//
// expect_heavy_top_jets_match<Method>(h, T, value_tol, derivative_tol): integrates test::skew_heavy_top() from
// test::skew_initial_state() to T with step h, once with Jets seeded on Ω0 (3 components) and b, and 8 times in
// double with Ω0 and b moved by ±1e-6. It prints and checks (figures.hpp) the largest |Jet derivative − central
// difference| over R(T) and Ω(T) against derivative_tol — what it measures is the central differences' rounding,
// ε |x| / 1e-6 ≈ 1e-10 grown along the run: 3.3e-10 … 7.2e-10 for the single-step methods at h = 0.02 (the
// default 1.6e-9), 6.5e-10 … 2.8e-9 for the compositions, whose negative coefficients amplify it —, and the largest
// |Jet value − plain run| against value_tol: the value parts take other code paths (ceres' functions of Jets) and
// agree to 1 … 9 ulps of O(1) numbers (1.1e-16 … 1.9e-15), held to 13 … 36 ulps.
#pragma once

#include "figures.hpp"
#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/core/scalar.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace lgi::test {

template <template <class> class Method>
void expect_heavy_top_jets_match(double h, double T, double value_tol, double derivative_tol = 1.6e-9) {
  using Jet = ceres::Jet<double, 4>;
  using SD = Method<HeavyTop<double>>;
  const std::string name(SD::traits.name);
  const auto problem = skew_heavy_top();
  const State<double> x0 = skew_initial_state();
  auto jet_problem = problem.template cast<Jet>();
  jet_problem.b.v[3] = 1;
  State<Jet> xj = x0.cast<Jet>();
  for (int i = 0; i < 3; ++i) xj.Omega[i].v[i] = 1;
  Method<HeavyTop<Jet>> jet_stepper(jet_problem);
  ASSERT_EQ(integrate_to(jet_stepper, xj, Jet(0), Jet(h), Jet(T)).status, RunStatus::completed);
  ASSERT_TRUE(all_finite(xj.R) && all_finite(xj.Omega));
  const auto run = [&](const Vec3<double>& dOmega, double db) {
    auto p = problem;
    p.b += db;
    State<double> x = x0;
    x.Omega += dOmega;
    SD stepper(p);
    integrate_to(stepper, x, 0.0, h, T);
    return x;
  };
  const double eps = 1e-6;
  double worst = 0, largest = 0;
  const auto compare = [&](double jet, double fd) {
    worst = std::max(worst, std::isnan(jet - fd) ? INFINITY : std::abs(jet - fd));
    largest = std::max(largest, std::abs(fd));
  };
  for (int j = 0; j < 4; ++j) {
    const Vec3<double> d = j < 3 ? Vec3<double>(eps * Vec3<double>::Unit(j)) : Vec3<double>::Zero();
    const double db = j == 3 ? eps : 0.0;
    const State<double> plus = run(d, db), minus = run(-d, -db);
    for (int r = 0; r < 3; ++r) {
      compare(xj.Omega[r].v[j], (plus.Omega[r] - minus.Omega[r]) / (2 * eps));
      for (int c = 0; c < 3; ++c) compare(xj.R(r, c).v[j], (plus.R(r, c) - minus.R(r, c)) / (2 * eps));
    }
  }
  const State<double> plain = run(Vec3<double>::Zero(), 0.0);
  double value = 0;
  for (int r = 0; r < 3; ++r) {
    value = std::max(value, std::abs(xj.Omega[r].a - plain.Omega[r]));
    for (int c = 0; c < 3; ++c) value = std::max(value, std::abs(xj.R(r, c).a - plain.R(r, c)));
  }
  std::printf("%s: Jets through %g steps, largest derivative %.2f\n", name.c_str(), T / h, largest);
  expect_figure("Jet derivatives vs central differences (absolute), " + name, worst, derivative_tol);
  expect_figure("Jet value vs the plain run, " + name, value, value_tol);
  EXPECT_GT(largest, 0.1) << name;
}

}  // namespace lgi::test
