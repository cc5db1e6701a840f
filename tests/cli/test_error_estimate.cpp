// The error estimate of `lgi run --error-estimate` (apps/runner.hpp, estimate_error) against the true error, on random
// free bodies, asymmetric heavy tops and Lagrange tops (random inertia, spin, tilt of the centre of mass, T in [5, 10]),
// run by fixed-step methods of orders 2-8 (Richardson with 2 dt) and by embedded pairs (tolerances / 1000), as
// `lgi run` runs them (parse_scene, run_scene). The truth: the exact solution (problems/free_body_exact.hpp, long-double
// constants) for the free bodies, rkmk_vern9 at rtol = atol = 1e-14 for the tops (its error ≈ 1e-13, 1000× below the
// smallest error counted). Counted: cases whose true error exceeds 1e-10 (far above round-off and the reference's
// error); the estimate, R's angle + |ΔΩ|/|Ω| as the truth is measured, must lie within a factor 10 of the truth on
// ≥ 95 % of ≥ 200 counted cases.
#include "run_rows.hpp"
#include "output_file.hpp"
#include "runner.hpp"
#include "scene.hpp"

#include <lgi/core/so3.hpp>
#include <lgi/problems/free_body_exact.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
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

// "method": "auto" (apps/auto_method.hpp) on random bodies: free bodies (the exact solution), asymmetric heavy tops
// with a diagonal or a non-diagonal inertia tensor and Kovalevskaya tops (the adaptive pair), Lagrange tops (the
// splitting's compositions with probed steps), at tolerances 1e-6 … 1e-12, T in [5, 30], rows at 5 output times.
// The truth at every output: the exact solution (free bodies), else rkmk_vern9 at rtol = atol = 1e-14 with the same
// output times (its error ≈ 1e-13, 100× below the smallest bound checked, 10 × 1e-12). Every output of every case must
// be within 10 × the tolerance (auto_method.hpp's measure: R's angle + |ΔΩ| / |Ω|).
std::vector<std::vector<double>> rows_of(const Scene& scene, const std::string& path) {
  RunReport r;
  std::vector<std::vector<double>> rows = test::run_csv_rows(scene, path, &r);
  if (r.summary.status != RunStatus::completed) return {};
  return rows;
}

State<double> row_state(const std::vector<double>& row) {
  State<double> x;
  for (int i = 0; i < 9; ++i) x.R(i / 3, i % 3) = row[static_cast<std::size_t>(1 + i)];
  x.Omega = Vec3<double>(row[10], row[11], row[12]);
  return x;
}

TEST(AutoMethod, WithinTenTimesTheToleranceAtEveryOutputOnRandomBodies) {
  std::mt19937_64 rng(20261128);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), moment(1.0, 2.0), uniform(0.0, 1.0);
  const std::string path = ::testing::TempDir() + "lgi_auto_rows.csv";
  std::vector<double> worst;  // per case: max over outputs of error / tolerance
  std::vector<std::string> chosen;
  for (int i = 0; i < 300; ++i) {
    const int kind = i % 5;  // 0 free body, 1 heavy top, 2 non-diagonal heavy top, 3 Lagrange top, 4 Kovalevskaya
    const double tol = std::pow(10.0, -6.0 - 2.0 * ((i / 5) % 4));
    std::array<double, 3> I{moment(rng), moment(rng), moment(rng)};
    json inertia = I;
    if (kind == 3) I[1] = I[0], inertia = I;
    if (kind == 2) {
      const Mat3<double> Q = so3::exp(Vec3<double>(unit(rng), unit(rng), unit(rng)));
      const Mat3<double> J = Q * Vec3<double>(I[0], I[1], I[2]).asDiagonal() * Q.transpose();
      inertia = json::array();
      for (int r = 0; r < 3; ++r) inertia.push_back({J(r, 0), J(r, 1), J(r, 2)});
    }
    const double b = 0.5 + uniform(rng);
    json problem;
    if (kind == 0) {
      problem = {{"type", "free_body"}, {"inertia", inertia}};
    } else if (kind == 1 || kind == 2) {
      const Vec3<double> z0 = Vec3<double>(unit(rng), unit(rng), 1.0).normalized();
      problem = {{"type", "heavy_top"}, {"inertia", inertia}, {"b", b}, {"k", {0.0, 0.0, 1.0}},
                 {"z0", {z0.x(), z0.y(), z0.z()}}};
    } else if (kind == 3) {
      const double k2 = unit(rng), n = std::sqrt(1 + k2 * k2);
      problem = {{"type", "lagrange_top"}, {"inertia", inertia}, {"b", b}, {"k", {0.0, k2 / n, 1.0 / n}}};
    } else {
      const Vec3<double> z0 = Vec3<double>(unit(rng), unit(rng), 0.0).normalized();
      problem = {{"type", "kovalevskaya_top"}, {"inertia", {2 * I[2], 2 * I[2], I[2]}}, {"b", b},
                 {"k", {0.0, 0.0, 1.0}}, {"z0", {z0.x(), z0.y(), 0.0}}};
    }
    // Spin: up to 3 about the third axis (Lagrange tops: up to 20, a fast top).
    const double spin = kind == 3 ? 1 + 19 * uniform(rng) : 1 + 2 * uniform(rng);
    const std::array<double, 3> omega{unit(rng) + 0.3, unit(rng), spin};
    const Mat3<double> R0 = so3::exp(Vec3<double>(0.5 * unit(rng), 0.5 * unit(rng), 0.5 * unit(rng)));
    json R = json::array();
    for (int r = 0; r < 3; ++r) R.push_back({R0(r, 0), R0(r, 1), R0(r, 2)});
    const double T = 5 + 25 * uniform(rng);
    json doc = {{"problem", problem}, {"initial", {{"R", R}, {"omega", omega}}},
                {"integrator", {{"method", "auto"}, {"tolerance", tol}}}, {"t_end", T},
                {"output", {{"interval", T / 5}}}};
    const std::string name = "random case " + std::to_string(i);
    const Scene scene = parse_scene(doc, name);
    const auto rows = rows_of(scene, path);
    ASSERT_EQ(rows.size(), 6u) << name;
    std::vector<State<double>> truth;
    if (kind == 0) {
      const auto solution = FreeBodyExact<double>(scene.problem->body().J).solve(scene.initial);
      for (const auto& row : rows) truth.push_back(solution.state(row[0]));
    } else {
      doc["integrator"] = {{"method", "rkmk_vern9"}, {"dt", 0.01}, {"rtol", 1e-14}, {"atol", 1e-14}};
      const auto ref = rows_of(parse_scene(doc, name + ", reference"), path);
      ASSERT_EQ(ref.size(), rows.size()) << name;
      for (const auto& row : ref) truth.push_back(row_state(row));
    }
    double w = 0;
    for (std::size_t k = 0; k < rows.size(); ++k) {
      const State<double> x = row_state(rows[k]);
      const double scale = std::max(x.Omega.norm(), scene.initial.Omega.norm());
      const double err = so3::log(Mat3<double>(truth[k].R.transpose() * x.R)).norm() +
                         (x.Omega - truth[k].Omega).norm() / scale;
      w = std::max(w, err / tol);
    }
    worst.push_back(w);
    chosen.push_back(std::string(scene.method->traits.name));
    EXPECT_LE(w, 10.0) << name << " (" << chosen.back() << ", tolerance " << tol << ", T = " << T << ")";
  }
  std::vector<double> sorted = worst;
  std::sort(sorted.begin(), sorted.end());
  const auto at = [&](double f) { return sorted[static_cast<std::size_t>(f * static_cast<double>(sorted.size() - 1) + 0.5)]; };
  std::printf("  %zu cases; largest error over the outputs / tolerance: min %.2g, median %.2g, 95%% %.2g, max %.2g\n",
              sorted.size(), sorted.front(), at(0.5), at(0.95), sorted.back());
  for (int kind = 0; kind < 5; ++kind) {
    double m = 0;
    for (std::size_t i = static_cast<std::size_t>(kind); i < worst.size(); i += 5) m = std::max(m, worst[i]);
    std::printf("    kind %d (%s): max %.2g\n", kind, chosen[static_cast<std::size_t>(kind)].c_str(), m);
  }
}

}  // namespace
}  // namespace lgi::app
