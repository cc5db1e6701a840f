// Fitting R0, Ω0 and the principal moments of inertia to attitude + gyro observations,
// and what the observations cannot fix.
//
// A free body's motion (R(t), Ω(t)) is unchanged when the inertia is scaled, J → λJ (Euler's equations
// J Ω' = JΩ × Ω are homogeneous in J; so is every step of the integrators), so attitudes and gyros fix only the
// ratios of the moments: one moment is held fixed. A heavy top with known b fixes the scale through the gravity
// torque (J → λJ, b → λb is the symmetry there): all three moments are recovered. Data come from the same
// method and step as the fit (the fit itself is under test; see test_fit_omega.cpp for the model error).
#include "figures.hpp"
#include "test_fit_data.hpp"

#include <lgi/integrators/lgvi.hpp>
#include <lgi/problems/free_body.hpp>

#include <gtest/gtest.h>

#include <cstdio>

namespace lgi {
namespace {

const std::vector<double> times = test::uniform_times(50, 10.0);
constexpr double dt = 0.01;
const Mat3<double> R_true = so3::exp(Vec3<double>(0.4, 0.2, -0.3));

FreeBody<double> free_body(const Vec3<double>& I) { return {I.asDiagonal()}; }

// R0 and Ω0 off by about 0.27 rad and 10 %; moments as given.
State<double> start_from(const State<double>& truth) {
  return {truth.R * so3::exp(Vec3<double>(0.2, -0.1, 0.15)), truth.Omega.cwiseProduct(Vec3<double>(1.1, 0.9, 1.1))};
}

double rotation_error(const std::vector<double>& rowwise, const Mat3<double>& R) {
  Mat3<double> F;
  for (int i = 0; i < 9; ++i) F(i / 3, i % 3) = rowwise[static_cast<std::size_t>(i)];
  return so3::log(Mat3<double>(R.transpose() * F)).norm();
}

TEST(FitInertia, FreeBodyRatiosFromAttitudesAndGyros) {
  const Vec3<double> I_true(0.6, 0.8, 1.0);
  const State<double> truth{R_true, Vec3<double>(3.0, 0.5, -0.9)};
  const auto data = test::observe<Lgvi>(free_body(I_true), truth, dt, times);
  const auto obs = test::merge(test::attitudes(times, data, 1e-3), test::gyros(times, data, 1e-3));
  const fit::Unknown unknowns[] = {{"initial.omega", {}, {}, {}}, {"initial.R", {}, {}, {}},
                                   {"problem.inertia", {2}}};  // I3 fixed: the scale
  fit::FitOptions options;
  options.dt = dt;
  options.continuation = {0.1, 0.3};  // the body turns 5 times in 10 s: fit 1 s, then 3 s, then all
  const auto res = fit::fit_observations<Lgvi, 8>(free_body(Vec3<double>(0.69, 0.72, 1.0)), start_from(truth), unknowns, obs, options);
  const double eR = rotation_error(res.at("initial.R").value, truth.R);
  const double eW = (test::as_vec3(res.at("initial.omega").value) - truth.Omega).cwiseAbs().maxCoeff();
  const double eI = (test::as_vec3(res.at("problem.inertia").value) - I_true).cwiseAbs().maxCoeff();
  std::printf("free body, I3 fixed: |R0 error| %.2e rad, |Omega0 error| %.2e, |I error| %.2e after %d iterations (%s), "
              "%.3f s; sigma(I1, I2) = %.2e, %.2e at sigma 1e-3 data\n",
              eR, eW, eI, res.iterations, res.termination_type.c_str(), res.seconds, res.at("problem.inertia").sigma[0],
              res.at("problem.inertia").sigma[1]);
  EXPECT_TRUE(res.usable) << res.report;
  // Noise-free (a fit stopped one iteration early leaves ≈ 1e-7): round-off, a few ulps, held to 16 ulps.
  test::expect_figure("noise-free fit of a free body, R0", eR, 3.6e-15);
  test::expect_figure("noise-free fit of a free body, Omega0", eW, 3.6e-15);
  test::expect_figure("noise-free fit of a free body, I1 and I2", eI, 3.6e-15);
  EXPECT_EQ(res.at("problem.inertia").sigma[2], 0.0);  // fixed
  // The same fit in one stage (a measurement, printed): from this start it ends in a local minimum.
  options.continuation.clear();
  const auto one = fit::fit_observations<Lgvi, 8>(free_body(Vec3<double>(0.69, 0.72, 1.0)), start_from(truth), unknowns, obs, options);
  std::printf("  without continuation: |Omega0 error| %.2e, cost %.3e, %s after %d iterations\n",
              (test::as_vec3(one.at("initial.omega").value) - truth.Omega).cwiseAbs().maxCoeff(), one.final_cost,
              one.termination_type.c_str(), one.iterations);
  // The cost at the guess over the whole arc: what the one-stage fit starts from; the stages lower it before the last
  // solve starts.
  std::printf("  cost at the guess %.6e (one stage starts at %.6e), after the continuation stages %.3e\n", res.guess_cost,
              one.initial_cost, res.initial_cost);
  EXPECT_NEAR(res.guess_cost, one.initial_cost, 1e-12 * one.initial_cost);
  EXPECT_EQ(one.guess_cost, one.initial_cost);
  EXPECT_LT(res.initial_cost, 1e-6 * res.guess_cost);
}

// All three moments free: the scale is not identifiable. The fit still matches the data (the cost reaches round-off
// and the ratios are right), but the Jacobian is rank deficient, so there is no covariance and the result is
// reported not usable.
TEST(FitInertia, FreeBodyScaleIsNotIdentifiable) {
  const Vec3<double> I_true(0.6, 0.8, 1.0);
  const State<double> truth{R_true, Vec3<double>(3.0, 0.5, -0.9)};
  const auto data = test::observe<Lgvi>(free_body(I_true), truth, dt, times);
  const auto obs = test::merge(test::attitudes(times, data, 1e-3), test::gyros(times, data, 1e-3));
  const fit::Unknown unknowns[] = {{"initial.omega", {}, {}, {}}, {"initial.R", {}, {}, {}}, {"problem.inertia", {}, {}, {}}};
  fit::FitOptions options;
  options.dt = dt;
  options.continuation = {0.1, 0.3};
  const auto res = fit::fit_observations<Lgvi, 8>(free_body(Vec3<double>(0.69, 0.72, 1.1)), start_from(truth), unknowns, obs, options);
  const Vec3<double> I = test::as_vec3(res.at("problem.inertia").value);
  const double ratio_error = std::max(std::abs(I(0) / I(2) - 0.6), std::abs(I(1) / I(2) - 0.8));
  std::printf("free body, all moments free: I = (%.6f, %.6f, %.6f), ratio error %.2e, cost %.2e, covariance %s, usable %s\n",
              I(0), I(1), I(2), ratio_error, res.final_cost, res.covariance_ok ? "yes" : "no", res.usable ? "yes" : "no");
  EXPECT_LE(ratio_error, 1e-8);
  EXPECT_FALSE(res.covariance_ok);
  EXPECT_FALSE(res.usable);
}

// Heavy top with b known: all three principal moments (about the base tensor's principal axes), R0 and Ω0.
// Noisy data (σ = 1e-3 on attitudes and gyros): every estimate within 4 reported σ of the truth.
TEST(FitInertia, HeavyTopMomentsR0Omega0) {
  const HeavyTop<double> top = test::skew_heavy_top();
  const State<double> truth = test::skew_initial_state();
  const auto data = test::observe<Lgvi>(top, truth, dt, times);
  std::mt19937_64 rng(7);
  const auto obs = test::merge(test::attitudes(times, data, 1e-3, &rng, 1e-3), test::gyros(times, data, 1e-3, &rng, 1e-3));
  // The guess: moments (0.9, 1.3, 1.7) about the true axes changed to (1.0, 1.2, 1.9).
  HeavyTop<double> guess = top;
  const Eigen::SelfAdjointEigenSolver<Mat3<double>> eig(top.inertia);
  guess.inertia = eig.eigenvectors() * Vec3<double>(1.0, 1.2, 1.9).asDiagonal() * eig.eigenvectors().transpose();
  const fit::Unknown unknowns[] = {{"initial.omega", {}, {}, {}}, {"initial.R", {}, {}, {}}, {"problem.inertia", {}, {}, {}}};
  fit::FitOptions options;
  options.dt = dt;
  const auto res = fit::fit_observations<Lgvi, 8>(guess, start_from(truth), unknowns, obs, options);
  ASSERT_TRUE(res.usable) << res.report;
  const auto& I = res.at("problem.inertia");
  const auto& W = res.at("initial.omega");
  const Vec3<double> I_true = eig.eigenvalues();  // 0.9, 1.3, 1.7
  double worst = 0;
  for (int k = 0; k < 3; ++k) {
    worst = std::max(worst, std::abs(I.value[k] - I_true(k)) / I.sigma[k]);
    worst = std::max(worst, std::abs(W.value[k] - truth.Omega(k)) / W.sigma[k]);
  }
  // R0: the error δ = Log(R_trueᵀ R̂) in the tangent coordinates of the estimate.
  Mat3<double> R_fit;
  for (int i = 0; i < 9; ++i) R_fit(i / 3, i % 3) = res.at("initial.R").value[static_cast<std::size_t>(i)];
  const Vec3<double> dR = so3::log(Mat3<double>(R_fit.transpose() * truth.R));
  for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(dR(k)) / res.at("initial.R").sigma[k]);
  std::printf("heavy top, b known: I = (%.6f, %.6f, %.6f) +- (%.1e, %.1e, %.1e), largest |error|/sigma %.2f, %d iterations, "
              "%.3f s\n", I.value[0], I.value[1], I.value[2], I.sigma[0], I.sigma[1], I.sigma[2], worst, res.iterations,
              res.seconds);
  EXPECT_LE(worst, 4.0);
  EXPECT_LE(I.sigma[0], 1e-2);  // the data do pin the scale down
}

}  // namespace
}  // namespace lgi
