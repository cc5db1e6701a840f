// Integrates the Hairer–Vilmart heavy top for 10 time units with the LGVI and prints the energy error:
// the smallest complete program that uses lgi as a library.
#include <lgi/core/driver.hpp>
#include <lgi/core/invariants.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <cmath>
#include <cstdio>

int main() {
  const auto top = lgi::HeavyTop<double>::hairer_vilmart();
  lgi::State<double> x;
  x.Omega = top.inertia.inverse() * lgi::Vec3<double>(1.8, 0.4, -0.9);
  const double E0 = lgi::energy(top, x);

  lgi::Lgvi<lgi::HeavyTop<double>> stepper(top);
  const lgi::IntegrationSummary summary = lgi::integrate_to(stepper, x, 0.0, 0.01, 10.0);

  const double dE = std::abs(lgi::energy(top, x) - E0) / std::abs(E0);
  std::printf("%lld steps, relative energy error %.2e, |R^T R - I| = %.2e\n", static_cast<long long>(summary.steps), dE,
              lgi::so3::orthogonality_error(x.R));
  return summary.status == lgi::RunStatus::completed && dE < 1e-3 ? 0 : 1;
}
