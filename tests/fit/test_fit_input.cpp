// Bad input to the fitting API: one FitInputError (a std::invalid_argument) naming the field, before any
// integration; and an integration that fails inside a residual makes the cost function return false.
#include "fp_traps.hpp"
#include "test_fit_data.hpp"

#include <lgi/integrators/lgvi.hpp>
#include <lgi/problems/free_body.hpp>

#include <gtest/gtest.h>

#include <functional>
#include <limits>

namespace lgi {
namespace {

using M = fit::Model<Lgvi, HeavyTop<double>, 8>;
const HeavyTop<double> top = test::skew_heavy_top();
const State<double> x0 = test::skew_initial_state();

std::vector<fit::Observation> good_obs() {
  return {fit::Observation::attitude(1.0, Mat3<double>::Identity(), 0.01),
          fit::Observation::angular_velocity(1.0, Vec3<double>(1, 2, 3), 0.01),
          fit::Observation::attitude(2.0, Mat3<double>::Identity(), 0.01)};
}
const std::vector<fit::Unknown> omega_only = {{"initial.omega", {}, {}, {}}};

fit::ModelOptions options(double t_end = 10) {
  fit::ModelOptions mo;
  mo.dt = 0.01;
  mo.t_end = t_end;
  return mo;
}

void expect_field(const std::function<void()>& f, const std::string& field, const std::string& words = "") {
  try {
    f();
    ADD_FAILURE() << "no error; expected one naming " << field;
  } catch (const fit::FitInputError& e) {
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind(field + ": ", 0), 0u) << e.what();
  }
}

TEST(FitInput, GoodInputIsAccepted) { EXPECT_NO_THROW(M(top, x0, omega_only, good_obs(), options())); }

TEST(FitInput, ObservationTimes) {
  auto obs = good_obs();
  obs[2].t = 10.5;
  expect_field([&] { M(top, x0, omega_only, obs, options()); }, "observations[2].t", "outside [0, 10]");
  obs[2].t = -1;
  expect_field([&] { M(top, x0, omega_only, obs, options()); }, "observations[2].t", "outside");
  obs[2].t = 0.5;
  expect_field([&] { M(top, x0, omega_only, obs, options()); }, "observations[2].t", "increasing");
  obs[2].t = std::numeric_limits<double>::quiet_NaN();
  expect_field([&] { M(top, x0, omega_only, obs, options()); }, "observations[2].t");
  obs = good_obs();
  obs[1].kind = fit::ObservationKind::attitude;  // two attitudes at t = 1
  obs[1].R = Mat3<double>::Identity();
  expect_field([&] { M(top, x0, omega_only, obs, options()); }, "observations[1].t", "repeats");
  expect_field([&] { M(top, x0, omega_only, {}, options()); }, "observations");
}

TEST(FitInput, StandardDeviations) {
  for (const double s : {0.0, -1e-3, std::numeric_limits<double>::infinity()}) {
    auto obs = good_obs();
    obs[1].sigma = s;
    expect_field([&] { M(top, x0, omega_only, obs, options()); }, "observations[1].sigma", "> 0");
  }
  auto obs = good_obs();
  obs[0].with_loss(fit::Loss::huber, 0);
  expect_field([&] { M(top, x0, omega_only, obs, options()); }, "observations[0].loss_scale");
  expect_field([] { fit::loss_from_name("tukey", "observations[4].loss"); }, "observations[4].loss", "tukey");
}

TEST(FitInput, RotationsAndUnitVectors) {
  auto obs = good_obs();
  obs[0].R(0, 0) = 1.001;
  expect_field([&] { M(top, x0, omega_only, obs, options()); }, "observations[0].R", "rotation");
  obs = good_obs();
  obs[0] = fit::Observation::attitude_quaternion(1.0, Eigen::Vector4d(1, 0.1, 0, 0), 0.01);
  expect_field([&] { M(top, x0, omega_only, obs, options()); }, "observations[0].q", "unit quaternion");
  obs = good_obs();
  obs[1] = fit::Observation::body_axis(1.0, Vec3<double>(1, 1, 0), Vec3<double>(1, 0, 0), 0.01);
  expect_field([&] { M(top, x0, omega_only, obs, options()); }, "observations[1].axis", "unit");
  State<double> bad = x0;
  bad.R(1, 2) += 1e-6;
  expect_field([&] { M(top, bad, omega_only, good_obs(), options()); }, "initial.R", "rotation");
  bad = x0;
  bad.R = -bad.R;  // orthogonal, det −1
  expect_field([&] { M(top, bad, omega_only, good_obs(), options()); }, "initial.R", "rotation");
}

TEST(FitInput, Unknowns) {
  const auto check = [&](const std::vector<fit::Unknown>& u, const std::string& field, const std::string& words) {
    expect_field([&] { M(top, x0, u, good_obs(), options()); }, field, words);
  };
  check({{"initial.omega", {}, {}, {}}, {"initial.spin", {}, {}, {}}}, "unknowns[1].name", "unknown unknown 'initial.spin'");
  check({{"initial.omega", {}, {}, {}}, {"initial.omega", {}, {}, {}}}, "unknowns[1].name", "twice");
  check({{"period", {}, {}, {}}}, "unknowns[0].name", "periodic");
  check({{"initial.omega", {3}, {}, {}}}, "unknowns[0].fixed", "out of range");
  check({{"initial.R", {1}, {}, {}}}, "unknowns[0].fixed", "separately");
  check({{"initial.omega", {}, {0, 0}, {}}}, "unknowns[0].lower", "expected 3 values, got 2");
  check({{"initial.omega", {}, {1, -1, 0}, {}}}, "unknowns[0].lower", "outside its bounds");
  check({{"initial.omega", {}, {}, {0, 0, 0}}}, "unknowns[0].lower", "outside its bounds");
  check({{"problem.z0", {}, {0, 0, 0}, {}}}, "unknowns[0].lower", "no bounds");
  check({{"initial.omega", {0, 1, 2}, {}, {}}}, "unknowns", "nothing to fit");
  check({}, "unknowns", "nothing to fit");
  // problem.b does not exist for a free body
  const FreeBody<double> body = FreeBody<double>::hairer_vilmart();
  const std::vector<fit::Unknown> b = {{"problem.b", {}, {}, {}}};
  expect_field([&] { fit::Model<Lgvi, FreeBody<double>, 8>(body, x0, b, good_obs(), options()); }, "unknowns[0].name",
               "does not apply to problem free_body");
}

TEST(FitInput, Options) {
  fit::ModelOptions mo = options();
  mo.dt = 0;
  expect_field([&] { M(top, x0, omega_only, good_obs(), mo); }, "integrator.dt");
  mo = options();
  mo.stepper.rtol = mo.stepper.atol = 1e-8;
  expect_field([&] { M(top, x0, omega_only, good_obs(), mo); }, "integrator.rtol", "fixed steps");
  mo = options();
  mo.stepper.max_iterations = 0;
  expect_field([&] { M(top, x0, omega_only, good_obs(), mo); }, "integrator", "max_iterations");
  const std::string header[] = {"t", "R11", "omega1"};
  const std::vector<double> rows[] = {{0.0, 1.0}};
  // A σ given for columns the table lacks: an error naming them (not a fit of what is left).
  expect_field([&] { fit::observations_from_table(header, rows, {.sigma_attitude = 1e-3, .sigma_omega = 1e-3}); },
               "observations", "R12, R13, R21, R22, R23, R31, R32, R33 are missing");
  expect_field([&] { fit::observations_from_table(header, rows, {.sigma_omega = 1e-3}); }, "observations",
               "omega2, omega3 are missing");
  expect_field([&] { fit::observations_from_table(header, rows, {}); }, "observations", "no usable columns");
  const std::string twice[] = {"t", "omega1", "omega2", "omega3", "omega2"};
  const std::vector<double> rows5[] = {{0.0, 1.0, 2.0, 3.0, 4.0}};
  expect_field([&] { fit::observations_from_table(twice, rows5, {.sigma_omega = 1e-3}); }, "observations",
               "column 'omega2' appears twice (columns 3 and 5");
}

// An integration that fails inside a residual (LGVI's Newton iteration at h|Ω| = 50, far beyond its
// convergence region) makes the cost function return false, with and without Jacobians; a non-finite b as well.
TEST(FitInput, FailedIntegrationRejectsTheStep) {
  const std::vector<fit::Unknown> unknowns = {{"initial.omega", {}, {}, {}}, {"problem.b", {}, {}, {}}};
  M model(top, x0, unknowns, good_obs(), options());
  std::vector<double*> params = model.parameter_blocks();
  const auto cost = model.observation_cost(0);
  double r[3], j0[9], j1[3];
  double* jac[2] = {j0, j1};
  EXPECT_TRUE(cost->Evaluate(params.data(), r, jac));
  const test::FpTrapsOff traps_off;  // the failing runs make non-finite numbers on purpose
  std::vector<double> omega = {5000, -3000, 2000}, b = {1.3};
  double* fast[2] = {omega.data(), b.data()};
  EXPECT_FALSE(cost->Evaluate(fast, r, nullptr));
  EXPECT_FALSE(cost->Evaluate(fast, r, jac));
  std::vector<double> slow = {0.7, -0.4, 1.1}, nan_b = {std::numeric_limits<double>::quiet_NaN()};
  double* bad[2] = {slow.data(), nan_b.data()};
  EXPECT_FALSE(cost->Evaluate(bad, r, jac));
  EXPECT_TRUE(cost->Evaluate(params.data(), r, jac));  // and back to a good point
}

}  // namespace
}  // namespace lgi
