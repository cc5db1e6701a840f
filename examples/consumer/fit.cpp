// Uses lgi::fit: recovers a free body's initial angular velocity from attitudes the LGVI itself produced.
#include <lgi/core/driver.hpp>
#include <lgi/fit/fit.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/problems/free_body.hpp>

#include <cstdio>
#include <vector>

int main() {
  const auto body = lgi::FreeBody<double>::hairer_vilmart();
  lgi::State<double> truth;
  truth.Omega = lgi::Vec3<double>(1.0, 0.4, -0.6);

  std::vector<lgi::fit::Observation> observations;
  lgi::Lgvi<lgi::FreeBody<double>> stepper(body);
  lgi::State<double> x = truth;
  double t = 0;
  for (int k = 1; k <= 8; ++k) {
    lgi::integrate_to(stepper, x, t, 0.01, 0.5 * k);
    t = 0.5 * k;
    observations.push_back(lgi::fit::Observation::attitude(t, x.R, 1e-3));
  }

  lgi::State<double> guess = truth;
  guess.Omega += lgi::Vec3<double>(0.05, -0.03, 0.02);
  const lgi::fit::Unknown unknowns[] = {{"initial.omega"}};
  lgi::fit::FitOptions options;
  options.dt = 0.01;
  options.t_end = 4;
  // Jet size 3: the unknowns' three tangent coordinates in one pass.
  const auto result = lgi::fit::fit_observations<lgi::Lgvi, 3>(body, guess, unknowns, observations, options);
  const double error = (result.initial.Omega - truth.Omega).norm();
  std::printf("lgi::fit: initial omega recovered to %.2e (%s)\n", error, result.usable ? "usable" : "not usable");
  return result.usable && error < 1e-8 ? 0 : 1;
}
