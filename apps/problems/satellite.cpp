// lgi/apps/problems/satellite.cpp — the `satellite` problem type of scenes: its parser and its registration (every method
// that applies to it is compiled here, problem_model.hpp).
#include "../problem_model.hpp"

#include <lgi/problems/satellite.hpp>

#include <cmath>

namespace lgi::app {
namespace {

Satellite<double> parse(const Node& p) {
  Satellite<double> sat;
  sat.inertia = read_inertia(p.at("inertia"));
  sat.n = p.at("n").positive();
  if (auto nu = p.find("normal")) sat.normal = read_unit_vector(*nu);
  if (auto r = p.find("radial")) {
    const Vec3<double> r0 = read_unit_vector(*r);
    const double c = r0.dot(sat.normal);
    if (!(std::abs(c) <= 1e-9))
      r->fail("the radial direction must be perpendicular to the orbit normal (to 1e-9), radial . normal = " +
              format_number(c));
    sat.radial0 = (r0 - c * sat.normal).normalized();
  } else if (std::abs(sat.normal.dot(sat.radial0)) > 1e-9) {
    p.at("normal").fail("the default radial direction e1 is not perpendicular to this orbit normal: give \"radial\"");
  } else {
    sat.radial0 = (sat.radial0 - sat.normal.dot(sat.radial0) * sat.normal).normalized();
  }
  return sat;
}


}  // namespace

LGI_DEFINE_PROBLEM(satellite, Satellite<double>, "satellite on a circular orbit (rate n) under the gravity-gradient torque 3 n^2 rho x J rho, rho = R^T r(t)", ({"type", "inertia", "n", "radial", "normal"}), parse)

}  // namespace lgi::app
