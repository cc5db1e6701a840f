// Observation kinds and losses in a fit: body-axis directions alone, quaternion input, rows of an `lgi run`
// table, and robust losses against gross outliers. Heavy top of test_problems.hpp, LGVI, h = 0.01, T = 10.
#include "figures.hpp"
#include "test_fit_data.hpp"

#include <lgi/integrators/lgvi.hpp>

#include <gtest/gtest.h>

#include <cstdio>

namespace lgi {
namespace {

const HeavyTop<double> top = test::skew_heavy_top();
const State<double> truth = test::skew_initial_state();
const std::vector<double> times = test::uniform_times(50, 10.0);
constexpr double dt = 0.01;
const std::vector<fit::Unknown> omega_only = {{"initial.omega", {}, {}, {}}};

State<double> start() { return {truth.R, truth.Omega.cwiseProduct(Vec3<double>(1.2, 0.8, 1.2))}; }

fit::FitResult<HeavyTop<double>> run(const std::vector<fit::Observation>& obs) {
  fit::FitOptions options;
  options.dt = dt;
  return fit::fit_observations<Lgvi, 8>(top, start(), omega_only, obs, options);
}
double omega_error(const fit::FitResult<HeavyTop<double>>& r) {
  return (test::as_vec3(r.at("initial.omega").value) - truth.Omega).cwiseAbs().maxCoeff();
}

// The laboratory direction of body axis 1 only (a star tracker's boresight, say): 2 residuals per time.
TEST(FitObservations, BodyAxisDirectionsAlone) {
  const auto data = test::observe<Lgvi>(top, truth, dt, times);
  std::vector<fit::Observation> obs;
  for (std::size_t i = 0; i < times.size(); ++i)
    obs.push_back(fit::Observation::body_axis(times[i], Vec3<double>::UnitX(), data[i].R.col(0), 1e-3));
  const auto res = run(obs);
  std::printf("body axis 1 only: |Omega0 error| %.2e, %d iterations\n", omega_error(res), res.iterations);
  EXPECT_TRUE(res.usable) << res.report;
  // Noise-free (a fit stopped one iteration early leaves ≈ 1e-7): round-off, held to ≈ 5×.
  test::expect_figure("noise-free fit of Omega0 from body-axis directions", omega_error(res), 3e-12);
}

// Quaternions (w, x, y, z) give the same fit as the matrices they stand for.
TEST(FitObservations, QuaternionInput) {
  const auto data = test::observe<Lgvi>(top, truth, dt, times);
  std::vector<fit::Observation> obs;
  for (std::size_t i = 0; i < times.size(); ++i) {
    const Eigen::Quaterniond q(data[i].R);
    obs.push_back(fit::Observation::attitude_quaternion(times[i], Eigen::Vector4d(q.w(), q.x(), q.y(), q.z()), 1e-3));
  }
  const auto res = run(obs);
  EXPECT_TRUE(res.usable) << res.report;
  test::expect_figure("noise-free fit of Omega0 from quaternions", omega_error(res), 6e-14);
}

// Rows with `lgi run`'s column names (t, R11..R33, omega1..3, and others ignored).
TEST(FitObservations, FromRunTable) {
  const auto data = test::observe<Lgvi>(top, truth, dt, times);
  const std::vector<std::string> header = {"t", "R11", "R12", "R13", "R21", "R22", "R23", "R31", "R32", "R33",
                                           "omega1", "omega2", "omega3", "energy"};
  std::vector<std::vector<double>> rows;
  for (std::size_t i = 0; i < times.size(); ++i) {
    std::vector<double> row = {times[i]};
    for (int k = 0; k < 9; ++k) row.push_back(data[i].R(k / 3, k % 3));
    for (int k = 0; k < 3; ++k) row.push_back(data[i].Omega(k));
    row.push_back(0.0);
    rows.push_back(row);
  }
  const auto obs = fit::observations_from_table(header, rows, {.sigma_attitude = 1e-3, .sigma_omega = 1e-2});
  ASSERT_EQ(obs.size(), 100u);
  EXPECT_EQ(obs[1].kind, fit::ObservationKind::angular_velocity);
  const auto res = run(obs);
  EXPECT_TRUE(res.usable) << res.report;
  test::expect_figure("noise-free fit of Omega0 from lgi run's table", omega_error(res), 7e-14);
}

// 5 of 50 attitudes replaced by gross errors (rotations by 0.3 rad), the rest with σ = 1e-3 noise. Plain least
// squares is pulled far off; Huber and Cauchy (scale 3σ) must stay within 5 of their reported σ (measured).
TEST(FitObservations, RobustLossesResistOutliers) {
  const auto data = test::observe<Lgvi>(top, truth, dt, times);
  std::mt19937_64 rng(11);
  auto obs = test::attitudes(times, data, 1e-3, &rng, 1e-3);
  for (const int i : {7, 18, 25, 33, 41}) obs[i].R = obs[i].R * so3::exp(Vec3<double>(0.3, -0.2, 0.1));
  double err[3], z[3];
  const fit::Loss losses[] = {fit::Loss::none, fit::Loss::huber, fit::Loss::cauchy};
  for (int l = 0; l < 3; ++l) {
    auto o = obs;
    for (auto& x : o) x.with_loss(losses[l], 3.0);
    const auto res = run(o);
    err[l] = omega_error(res);
    const auto& w = res.at("initial.omega");
    z[l] = 0;
    for (int k = 0; k < 3; ++k) z[l] = std::max(z[l], std::abs(w.value[k] - truth.Omega(k)) / w.sigma[k]);
  }
  std::printf("5 outliers of 0.3 rad in 50: |Omega0 error| plain %.2e (%.0f sigma), huber %.2e (%.1f sigma), cauchy %.2e "
              "(%.1f sigma)\n", err[0], z[0], err[1], z[1], err[2], z[2]);
  EXPECT_GT(z[0], 10.0);
  EXPECT_LE(z[1], 5.0);
  EXPECT_LE(z[2], 5.0);
}

}  // namespace
}  // namespace lgi
