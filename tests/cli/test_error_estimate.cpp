// The error estimate of `lgi run --error-estimate` (apps/runner.hpp, estimate_error) against the true error, on random
// free bodies, asymmetric heavy tops and Lagrange tops (random inertia, spin, tilt of the centre of mass, T in [5, 10]),
// run by fixed-step methods of orders 2-8 (Richardson with 2 dt) and by embedded pairs (tolerances / 1000), as
// `lgi run` runs them (parse_scene, run_scene). The truth: the exact solution (problems/free_body_exact.hpp, long-double
// constants) for the free bodies, rkmk_vern9 at rtol = atol = 1e-14 for the tops (its error ≈ 1e-13, 1000× below the
// smallest error counted). Counted: cases whose true error exceeds 1e-10 (far above round-off and the reference's
// error); the estimate, R's angle + |ΔΩ|/|Ω| as the truth is measured, must lie within a factor 10 of the truth on
// ≥ 95 % of ≥ 200 counted cases.
#include "runner.hpp"
#include "scene.hpp"

#include <lgi/core/so3.hpp>
#include <lgi/problems/free_body_exact.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace lgi::app {
namespace {

double distance(const State<double>& x, const State<double>& ref) {
  return so3::log(Mat3<double>(ref.R.transpose() * x.R)).norm() + (x.Omega - ref.Omega).norm() / ref.Omega.norm();
}

struct MethodCase {
  const char* name;
  bool adaptive;
};

TEST(ErrorEstimate, WithinAFactorTenOfTheTrueErrorOnRandomTops) {
  const std::vector<MethodCase> methods = {{"rkmk4", false},      {"lgvi", false},          {"rkmk4_cayley", false},
                                           {"cf4", false},        {"lgvi_yoshida4", false}, {"split_dmv", false},
                                           {"rkmk_dp8", false},   {"rkmk_dp5", true},       {"rkmk_vern9_cayley", true},
                                           {"rkmk_dp8_cayley", true}};
  std::mt19937_64 rng(20261127);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), moment(1.0, 2.0), uniform(0.0, 1.0);  // moments in [1, 2]: I3 ≤ I1 + I2
  int counted = 0, within = 0, below = 0;
  std::vector<double> ratios;
  for (int i = 0; i < 300; ++i) {
    const int kind = i % 3;  // 0 free body, 1 asymmetric heavy top, 2 Lagrange top
    const MethodCase& m = methods[static_cast<std::size_t>(i) % methods.size()];
    json problem;
    std::array<double, 3> I{moment(rng), moment(rng), moment(rng)};
    if (kind == 2) I[1] = I[0];
    if (kind == 0) {
      problem = {{"type", "free_body"}, {"inertia", I}};
    } else if (kind == 1) {
      const Vec3<double> z0 = Vec3<double>(unit(rng), unit(rng), 1.0).normalized();
      problem = {{"type", "heavy_top"}, {"inertia", I}, {"b", 0.5 + uniform(rng)},
                 {"k", {0.0, 0.0, 1.0}}, {"z0", {z0.x(), z0.y(), z0.z()}}};
    } else {
      const double k2 = unit(rng), n = std::sqrt(1 + k2 * k2);
      problem = {{"type", "lagrange_top"}, {"inertia", I}, {"b", 0.5 + uniform(rng)}, {"k", {0.0, k2 / n, 1.0 / n}}};
    }
    const std::array<double, 3> omega{unit(rng) + 0.3, unit(rng), 1.0 + 2 * uniform(rng)};
    const std::array<double, 3> axis_angle{0.5 * unit(rng), 0.5 * unit(rng), 0.5 * unit(rng)};
    const double w = std::sqrt(omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]);
    const double T = 5 + 5 * uniform(rng);
    json integrator = {{"method", m.name}};
    if (m.adaptive) {
      const double tol = std::pow(10.0, -5 - 4 * uniform(rng));
      integrator["dt"] = 0.01;
      integrator["rtol"] = tol;
      integrator["atol"] = tol;
    } else {
      integrator["dt"] = std::pow(10.0, std::log10(0.02) + std::log10(15.0) * uniform(rng)) / w;  // h|Ω| in [0.02, 0.3]
    }
    const Mat3<double> R0 = so3::exp(Vec3<double>(axis_angle[0], axis_angle[1], axis_angle[2]));
    json R = json::array();
    for (int r = 0; r < 3; ++r) R.push_back({R0(r, 0), R0(r, 1), R0(r, 2)});
    json doc = {{"problem", problem}, {"initial", {{"R", R}, {"omega", omega}}}, {"integrator", integrator}, {"t_end", T}};
    const std::string name = "random case " + std::to_string(i) + " (" + m.name + ")";
    const Scene scene = parse_scene(doc, name);
    const RunReport run = run_scene(scene, RunOptions{});
    ASSERT_EQ(run.summary.status, RunStatus::completed) << name;
    const ErrorEstimate e = estimate_error(scene, run);
    ASSERT_TRUE(e.available) << name << ": " << e.how;
    State<double> ref;
    if (kind == 0) {
      ref = FreeBodyExact<double>(scene.problem->body().J).solve(scene.initial).state(T);
    } else {
      doc["integrator"] = {{"method", "rkmk_vern9"}, {"dt", 0.01}, {"rtol", 1e-14}, {"atol", 1e-14}};
      const RunReport r = run_scene(parse_scene(doc, name + ", reference"), RunOptions{});
      ASSERT_EQ(r.summary.status, RunStatus::completed) << name;
      ref = r.final_state;
    }
    const double truth = distance(run.final_state, ref), estimate = e.R + e.Omega;
    if (!(truth > 1e-10)) continue;
    ++counted;
    const double q = estimate / truth;
    ratios.push_back(q);
    if (q >= 0.1 && q <= 10) ++within;
    if (q < 0.1) ++below;
  }
  std::sort(ratios.begin(), ratios.end());
  const auto at = [&](double f) { return ratios[static_cast<std::size_t>(f * static_cast<double>(ratios.size() - 1) + 0.5)]; };
  std::printf("  %d cases counted (true error > 1e-10); estimate / true error: min %.2f, 5%% %.2f, median %.2f, 95%% %.2f, "
              "max %.2f; within a factor 10: %d (%.1f %%), below 1/10 (optimistic): %d\n",
              counted, ratios.front(), at(0.05), at(0.5), at(0.95), ratios.back(), within,
              100.0 * within / std::max(counted, 1), below);
  EXPECT_GE(counted, 200);
  EXPECT_GE(within, 0.95 * counted);
}

// The exact solution needs no estimate; a run that did not complete has none.
TEST(ErrorEstimate, NotAvailableWhereItDoesNotApply) {
  json doc = {{"problem", {{"type", "free_body"}, {"inertia", {1.0, 2.0, 3.0}}}},
              {"initial", {{"omega", {1.0, 0.2, 0.5}}}},
              {"integrator", {{"method", "exact"}, {"dt", 0.5}}},
              {"t_end", 10.0}};
  Scene scene = parse_scene(doc, "exact");
  ErrorEstimate e = estimate_error(scene, run_scene(scene, RunOptions{}));
  EXPECT_FALSE(e.available);
  EXPECT_NE(e.how.find("exact solution"), std::string::npos) << e.how;
  doc["integrator"] = {{"method", "rkmk4"}, {"dt", 0.01}};
  doc["limits"] = {{"max_steps", 10}};
  scene = parse_scene(doc, "stopped");
  e = estimate_error(scene, run_scene(scene, RunOptions{}));
  EXPECT_FALSE(e.available);
  EXPECT_NE(e.how.find("did not complete"), std::string::npos) << e.how;
}

}  // namespace
}  // namespace lgi::app
