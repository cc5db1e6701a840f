// tests/jet_check.hpp — ceres::Jet through a method on the skew heavy top, against central differences.
//
// expect_heavy_top_jets_match<Method>(h, T, value_tol): integrates test::skew_heavy_top() from
// test::skew_initial_state() to T with step h, once with Jets seeded on Ω0 (3 components) and b, and
// 8 times in double with Ω0 and b moved by ±1e-6; every derivative of R(T) and Ω(T) must match the
// central difference to 1e-7, and the Jet's value part must match the plain run to value_tol.
#pragma once

#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/core/scalar.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <ceres/jet.h>
#include <gtest/gtest.h>

namespace lgi::test {

template <template <class> class Method>
void expect_heavy_top_jets_match(double h, double T, double value_tol) {
  using Jet = ceres::Jet<double, 4>;
  using SD = Method<HeavyTop<double>>;
  const auto problem = skew_heavy_top();
  const State<double> x0 = skew_initial_state();
  auto jet_problem = problem.template cast<Jet>();
  jet_problem.b.v[3] = 1;
  State<Jet> xj = x0.cast<Jet>();
  for (int i = 0; i < 3; ++i) xj.Omega[i].v[i] = 1;
  Method<HeavyTop<Jet>> jet_stepper(jet_problem);
  ASSERT_EQ(integrate_to(jet_stepper, xj, Jet(0), Jet(h), Jet(T)).status, RunStatus::completed);
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
  for (int j = 0; j < 4; ++j) {
    const Vec3<double> d = j < 3 ? Vec3<double>(eps * Vec3<double>::Unit(j)) : Vec3<double>::Zero();
    const double db = j == 3 ? eps : 0.0;
    const State<double> plus = run(d, db), minus = run(-d, -db);
    for (int r = 0; r < 3; ++r) {
      EXPECT_NEAR(xj.Omega[r].v[j], (plus.Omega[r] - minus.Omega[r]) / (2 * eps), 1e-7)
          << SD::traits.name << ": dΩ" << r << "/dp" << j;
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(xj.R(r, c).v[j], (plus.R(r, c) - minus.R(r, c)) / (2 * eps), 1e-7)
            << SD::traits.name << ": dR/dp" << j;
    }
  }
  ASSERT_TRUE(all_finite(xj.R) && all_finite(xj.Omega));
  const State<double> plain = run(Vec3<double>::Zero(), 0.0);
  for (int r = 0; r < 3; ++r) EXPECT_NEAR(xj.Omega[r].a, plain.Omega[r], value_tol) << SD::traits.name;
}

}  // namespace lgi::test
