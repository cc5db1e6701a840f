// lgi/apps/problems/satellite.cpp — the `satellite` problem type of scenes: its parser and its registration (every method
// that applies to it is compiled here, problem_model.hpp).
#include "../problem_model.hpp"
#include "torqued_body_reader.hpp"

#include <lgi/problems/satellite.hpp>

#include <cmath>

namespace lgi::app {
namespace {

Satellite<double> parse(const Node& p) {
  Satellite<double> sat;
  sat.inertia = read_inertia(p.at("inertia"));
  const CircularOrbit orbit = read_circular_orbit(p);
  sat.n = orbit.n;
  sat.radial0 = orbit.radial;
  sat.normal = orbit.normal;
  return sat;
}


}  // namespace

LGI_DEFINE_PROBLEM(satellite, Satellite<double>, "satellite on a circular orbit (rate n) under the gravity-gradient torque 3 n^2 rho x J rho, rho = R^T r(t)", ({"type", "inertia", "n", "radial", "normal"}), parse)

}  // namespace lgi::app
