// Fitting the torques a body feels (fit/model.hpp: problem.damping, problem.body_torque, problem.lab_torque,
// problem.k_R, problem.k_Omega) through the forced LGVI (integrators/lgvi.hpp), and a gyrostat's rotor friction and
// wheel gains (problem.rotor_friction, problem.wheel_k_R, problem.wheel_k_Omega) through the gyrostat LGVI
// (integrators/gyrostat.hpp): coverage of the reported standard deviations over 100 seeded noisy data sets, and the
// unknowns refused where they do not apply.
#include "test_fit_data.hpp"

#include <lgi/integrators/gyrostat.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/problems/gyrostat.hpp>
#include <lgi/problems/torqued_body.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <vector>

namespace lgi {
namespace {

const std::vector<double> times = test::uniform_times(50, 10.0);
constexpr double dt = 0.02;

// A damped asymmetric body under a constant body-frame disturbance (C = c I).
TorquedBody<double> damped_body() {
  TorquedBody<double> b;
  b.inertia = Vec3<double>(0.9, 1.3, 1.7).asDiagonal();
  b.damping = 0.15 * Mat3<double>::Identity();
  b.has_damping = true;
  b.body_torque = Vec3<double>(0.02, -0.03, 0.015);
  b.has_constant = true;
  return b;
}
const State<double> truth{so3::exp(Vec3<double>(0.4, 0.2, -0.3)), Vec3<double>(0.7, -0.4, 1.1)};

// 100 data sets: the attitudes at 50 times over T = 10 with rotation noise σ = 2e-3 rad (the model's own method and
// step, so the data have no discretisation error the model lacks). Unknowns: the damping coefficient, the disturbance
// and Ω0, from a guess c = 0.05, M = 0, Ω0 off by 10 %. A trial covers when each of the four torque parameters is
// within 3 of its reported σ of the truth.
TEST(FitTorques, DampingAndDisturbanceWithinThreeSigmaIn95Of100) {
  const TorquedBody<double> body = damped_body();
  const auto data = test::observe<Lgvi>(body, truth, dt, times);
  TorquedBody<double> guess = body;
  guess.damping = 0.05 * Mat3<double>::Identity();
  guess.body_torque.setZero();
  const State<double> start{truth.R, truth.Omega.cwiseProduct(Vec3<double>(1.1, 0.9, 1.1))};
  const fit::Unknown unknowns[] = {{"problem.damping"}, {"problem.body_torque"}, {"initial.omega"}};
  fit::FitOptions options;
  options.dt = dt;
  int covered = 0, usable = 0;
  std::vector<double> worst;
  double sigma_c = 0, sigma_M = 0;
  for (int seed = 0; seed < 100; ++seed) {
    std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
    const auto obs = test::attitudes(times, data, 2e-3, &rng, 2e-3);
    const auto res = fit::fit_observations<Lgvi, 8>(guess, start, unknowns, obs, options);
    if (!res.usable) continue;
    ++usable;
    const auto& c = res.at("problem.damping");
    const auto& M = res.at("problem.body_torque");
    double w = std::abs(c.value[0] - 0.15) / c.sigma[0];
    for (int k = 0; k < 3; ++k) w = std::max(w, std::abs(M.value[static_cast<std::size_t>(k)] - body.body_torque(k)) / M.sigma[static_cast<std::size_t>(k)]);
    worst.push_back(w);
    covered += w <= 3.0;
    sigma_c = c.sigma[0];
    sigma_M = M.sigma[0];
  }
  std::sort(worst.begin(), worst.end());
  const auto q = [&](double f) { return worst.empty() ? 0.0 : worst[static_cast<std::size_t>(f * static_cast<double>(worst.size() - 1))]; };
  std::printf("100 seeded fits of c, M_body, Omega0 (sigma 2e-3 rad attitudes): %d usable, %d with every torque "
              "parameter within 3 sigma; largest |error|/sigma per trial: median %.2f, 90th %.2f, max %.2f; sigma(c) "
              "%.1e, sigma(M1) %.1e\n",
              usable, covered, q(0.5), q(0.9), q(1.0), sigma_c, sigma_M);
  EXPECT_EQ(usable, 100);
  EXPECT_GE(covered, 95);
}

// The torque unknowns on problems without those terms, an anisotropic damping matrix, gains without a controller:
// one FitInputError naming the unknown.
TEST(FitTorques, UnknownsThatDoNotApplyAreRefused) {
  const auto data = test::observe<Lgvi>(damped_body(), truth, dt, times);
  const auto obs = test::attitudes(times, data, 1e-3);
  fit::FitOptions options;
  options.dt = dt;
  const auto message = [&](const auto& problem, const char* name) {
    const fit::Unknown unknowns[] = {{name}};
    try {
      fit::fit_observations<Lgvi, 8>(problem, truth, unknowns, obs, options);
    } catch (const fit::FitInputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message(HeavyTop<double>(test::skew_heavy_top()), "problem.damping"),
            "unknowns[0].name: 'problem.damping' does not apply to problem heavy_top");
  TorquedBody<double> anisotropic = damped_body();
  anisotropic.damping(1, 1) = 0.2;
  EXPECT_EQ(message(anisotropic, "problem.damping"),
            "unknowns[0].name: 'problem.damping' fits c of C = c I; the scene's damping matrix is not a multiple of I");
  EXPECT_EQ(message(damped_body(), "problem.k_R"),
            "unknowns[0].name: 'problem.k_R' needs the scene's attitude_control term (its target)");
  EXPECT_EQ(message(damped_body(), "problem.rotor_friction"),
            "unknowns[0].name: 'problem.rotor_friction' does not apply to problem rigid_body");
}

// A spacecraft slewing on three reaction wheels under the wheel PD law, its wheels spinning with bearing friction.
Gyrostat<double> wheeled_spacecraft() {
  Gyrostat<double> g;
  g.body.inertia = Vec3<double>(12.0, 10.0, 8.0).asDiagonal();
  g.rotor_count = 3;
  const double friction[3] = {0.002, 0.003, 0.0015}, rate[3] = {50.0, -30.0, 40.0};
  for (int i = 0; i < 3; ++i) g.rotors[i] = {Vec3<double>::Unit(i), 0.05, friction[i], 0.0, rate[i]};
  g.wheel_control = true;
  g.target = so3::exp(Vec3<double>(0.2, -0.5, 0.8));
  g.k_R = 2.0;
  g.k_Omega = 6.0;
  return g;
}

// 100 data sets of the slew: attitudes at 50 times over T = 20 with rotation noise σ = 2e-3 rad, generated by the
// gyrostat LGVI with the model's step. Unknowns: the three wheels' friction, both gains and Ω0, from a guess with
// friction 0.001 on each wheel, gains 1.5 and 5 and Ω0 off by 0.01 rad/s. A trial covers when each of the five
// torque parameters is within 3 of its reported σ of the truth.
TEST(FitTorques, RotorFrictionAndWheelGainsWithinThreeSigmaIn95Of100) {
  const std::vector<double> slew_times = test::uniform_times(50, 20.0);
  const Gyrostat<double> g = wheeled_spacecraft();
  const State<double> x0{Mat3<double>::Identity(), Vec3<double>(0.02, -0.01, 0.03)};
  const auto data = test::observe<GyrostatLgvi>(g, x0, dt, slew_times);
  Gyrostat<double> guess = g;
  for (int i = 0; i < 3; ++i) guess.rotors[i].friction = 0.001;
  guess.k_R = 1.5;
  guess.k_Omega = 5.0;
  const State<double> start{x0.R, x0.Omega + Vec3<double>(0.01, 0.01, -0.01)};
  const fit::Unknown unknowns[] = {{"problem.rotor_friction"}, {"problem.wheel_k_R"}, {"problem.wheel_k_Omega"},
                                   {"initial.omega"}};
  fit::FitOptions options;
  options.dt = dt;
  int covered = 0, usable = 0;
  std::vector<double> worst;
  double sigma_c = 0, sigma_k = 0, seconds = 0;
  for (int seed = 0; seed < 100; ++seed) {
    std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
    const auto obs = test::attitudes(slew_times, data, 2e-3, &rng, 2e-3);
    const auto res = fit::fit_observations<GyrostatLgvi, 8>(guess, start, unknowns, obs, options);
    seconds += res.seconds;
    if (!res.usable) continue;
    ++usable;
    const auto& c = res.at("problem.rotor_friction");
    const auto& kR = res.at("problem.wheel_k_R");
    const auto& kW = res.at("problem.wheel_k_Omega");
    EXPECT_EQ(c.value.size(), 3u);
    double w = std::max(std::abs(kR.value[0] - g.k_R) / kR.sigma[0], std::abs(kW.value[0] - g.k_Omega) / kW.sigma[0]);
    for (std::size_t k = 0; k < 3; ++k) w = std::max(w, std::abs(c.value[k] - g.rotors[k].friction) / c.sigma[k]);
    worst.push_back(w);
    covered += w <= 3.0;
    sigma_c = c.sigma[0];
    sigma_k = kR.sigma[0];
  }
  std::sort(worst.begin(), worst.end());
  const auto q = [&](double f) { return worst.empty() ? 0.0 : worst[static_cast<std::size_t>(f * static_cast<double>(worst.size() - 1))]; };
  std::printf("100 seeded fits of a gyrostat's rotor friction (3), wheel gains (2) and Omega0 (sigma 2e-3 rad "
              "attitudes): %d usable, %d with every torque parameter within 3 sigma; largest |error|/sigma per trial: "
              "median %.2f, 90th %.2f, max %.2f; sigma(c1) %.1e, sigma(k_R) %.1e; %.2f s a fit\n",
              usable, covered, q(0.5), q(0.9), q(1.0), sigma_c, sigma_k, seconds / 100);
  EXPECT_EQ(usable, 100);
  EXPECT_GE(covered, 95);
}

// A gyrostat's unknowns where they do not apply: wheel gains without wheel_control, a rotor component beyond the
// rotors present; problem.b and problem.damping reach the gyrostat's body.
TEST(FitTorques, GyrostatUnknownsAreCheckedAgainstItsRotors) {
  const std::vector<double> slew_times = test::uniform_times(10, 2.0);
  Gyrostat<double> g = wheeled_spacecraft();
  g.wheel_control = false;
  const State<double> x0{Mat3<double>::Identity(), Vec3<double>(0.02, -0.01, 0.03)};
  const auto obs = test::attitudes(slew_times, test::observe<GyrostatLgvi>(g, x0, dt, slew_times), 1e-3);
  fit::FitOptions options;
  options.dt = dt;
  const auto message = [&](const fit::Unknown& u) {
    const fit::Unknown unknowns[] = {u};
    try {
      fit::fit_observations<GyrostatLgvi, 8>(g, x0, unknowns, obs, options);
    } catch (const fit::FitInputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message({"problem.wheel_k_R"}),
            "unknowns[0].name: 'problem.wheel_k_R' needs the scene's wheel_control (its target)");
  EXPECT_EQ(message({"problem.rotor_friction", {3}}), "unknowns[0].fixed: component 3 out of range [0, 2]");
  EXPECT_EQ(message({"problem.rotor_friction", {}, {0, 0}}), "unknowns[0].lower: expected 3 values, got 2");
  EXPECT_EQ(message({"problem.damping"}), "no error");
}

}  // namespace
}  // namespace lgi
