// lgi/apps/problems/lagrange_top_euler_angles.cpp — the `lagrange_top_euler_angles` problem type of scenes: its parser and its registration (every method
// that applies to it is compiled here, problem_model.hpp).
#include "../problem_model.hpp"

#include <lgi/problems/euler_angle_top.hpp>

#include <cmath>

namespace lgi::app {
namespace {

EulerAngleTop<double> parse(const Node& p) {
  EulerAngleTop<double> top;
  top.I2 = p.at("I2").positive();
  top.I3 = p.at("I3").positive();
  // Principal moments (I2, I2, I3) of a body: the triangle inequality I3 <= 2 I2 (to a relative 1e-12).
  if (!(top.I3 <= 2 * top.I2 * (1 + 1e-12)))
    p.at("I3").fail("must not exceed 2*I2 = " + format_number(2 * top.I2) + " (triangle inequality of the moments)");
  top.b = p.at("b").non_negative();
  const Node k2 = p.at("k2"), k3 = p.at("k3");
  top.k2 = k2.number();
  top.k3 = k3.number();
  const double norm = std::hypot(top.k2, top.k3);
  if (!(std::abs(norm - 1) <= 1e-9))
    p.fail("k = (0, k2, k3) must be a unit vector (to 1e-9), its length is " + format_number(norm));
  top.k2 /= norm;
  top.k3 /= norm;
  if (auto s = p.find("min_sin_theta")) {
    top.min_sin_theta = s->non_negative();
    if (!(top.min_sin_theta < 1)) s->fail("must be in [0, 1), got " + format_number(top.min_sin_theta));
  }
  return top;
}


}  // namespace

LGI_DEFINE_PROBLEM(lagrange_top_euler_angles, EulerAngleTop<double>, "seed paper's Lagrange top in Euler angles, eqs. (s6.1)-(s6.3); k = (0, k2, k3), z0 = e3, "
                   "I = diag(I2, I2, I3); stops where sin(theta) < min_sin_theta (default 0.05)", ({"type", "I2", "I3", "b", "k2", "k3", "min_sin_theta"}), parse)

}  // namespace lgi::app
