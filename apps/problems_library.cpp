#include "registry.hpp"

#include <cmath>
#include <string>

namespace lgi::app {
namespace {

// A body-frame inertia tensor that must be diagonal (principal axes): the library's tops are written in
// principal axes. Returns the principal moments.
Vec3<double> read_principal_inertia(const Node& node, std::string_view why) {
  const Mat3<double> J = read_inertia(node);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (r != c && J(r, c) != 0)
        node.fail("must be diagonal (" + std::string(why) + "): I" + std::to_string(r + 1) + std::to_string(c + 1) +
                  " = " + format_number(J(r, c)));
  return J.diagonal();
}

bool nearly_equal(double a, double b) { return std::abs(a - b) <= 1e-12 * std::max(std::abs(a), std::abs(b)); }

AnyProblem parse_lagrange_top(const Node& p) {
  const Node inertia = p.at("inertia");
  const Vec3<double> I = read_principal_inertia(inertia, "principal axes, symmetry axis e3");
  if (!nearly_equal(I(0), I(1)))
    inertia.fail("a Lagrange top has I1 = I2 (symmetry axis e3), got I1 = " + format_number(I(0)) +
                 ", I2 = " + format_number(I(1)));
  LagrangeTop<double> top = LagrangeTop<double>::make(0.5 * (I(0) + I(1)), I(2), p.at("b").non_negative());
  if (auto k = p.find("k")) top.k = read_unit_vector(*k);
  return top;
}

AnyProblem parse_kovalevskaya_top(const Node& p) {
  const Node inertia = p.at("inertia");
  const Vec3<double> I = read_principal_inertia(inertia, "principal axes");
  if (!nearly_equal(I(0), I(1)) || !nearly_equal(I(0), 2 * I(2)))
    inertia.fail("a Kovalevskaya top has I1 = I2 = 2 I3, got " + format_number(I(0)) + ", " + format_number(I(1)) +
                 ", " + format_number(I(2)));
  KovalevskayaTop<double> top = KovalevskayaTop<double>::make((I(0) + I(1) + 2 * I(2)) / 6, p.at("b").non_negative());
  if (auto k = p.find("k")) top.k = read_unit_vector(*k);
  if (auto z0 = p.find("z0")) {
    Vec3<double> z = read_unit_vector(*z0);
    if (!(std::abs(z.z()) <= 1e-9))
      z0->fail("the centre of mass of a Kovalevskaya top lies in the equatorial plane: z0[2] must be 0 (to 1e-9), "
               "got " + format_number(z.z()));
    z.z() = 0;
    top.z0 = z.normalized();
  }
  return top;
}

AnyProblem parse_satellite(const Node& p) {
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

AnyProblem parse_potential(const Node& p) {
  FieldPotentialBody<double> body;
  body.inertia = read_inertia(p.at("inertia"));
  FieldPotential<double>& V = body.V;
  if (auto fields = p.find("fields")) {
    const std::size_t n = fields->size();
    if (n > static_cast<std::size_t>(FieldPotential<double>::max_terms))
      fields->fail("at most " + std::to_string(FieldPotential<double>::max_terms) + " uniform fields, got " +
                   std::to_string(n));
    for (std::size_t j = 0; j < n; ++j) {
      const Node f = fields->at(j);
      f.allow_only({"b", "k", "z0"}, "a uniform field");
      const int i = V.terms++;
      V.b[static_cast<std::size_t>(i)] = f.at("b").non_negative();
      V.k[static_cast<std::size_t>(i)] = read_unit_vector(f.at("k"));
      V.z[static_cast<std::size_t>(i)] = read_unit_vector(f.at("z0"));
    }
  }
  if (auto g = p.find("gradient")) {
    g->allow_only({"c", "axis", "tensor"}, "a field gradient");
    V.c = g->at("c").number();
    V.a = read_unit_vector(g->at("axis"));
    const Node q = g->at("tensor");
    const bool matrix = !(q.size() == 3 && !q.value()[0].is_array());
    const Mat3<double> Q = matrix ? q.mat3() : Mat3<double>(q.vec3().asDiagonal());
    const double scale = Q.cwiseAbs().maxCoeff();
    for (int r = 0; r < 3; ++r)
      for (int c = r + 1; c < 3; ++c)
        if (std::abs(Q(r, c) - Q(c, r)) > 1e-12 * scale)
          q.fail("the tensor must be symmetric: Q" + std::to_string(r + 1) + std::to_string(c + 1) + " = " +
                 format_number(Q(r, c)) + " but Q" + std::to_string(c + 1) + std::to_string(r + 1) + " = " +
                 format_number(Q(c, r)));
    V.Q = 0.5 * (Q + Q.transpose());
  }
  return body;
}

}  // namespace

std::vector<ProblemInfo> library_problem_infos() {
  return {
      {"lagrange_top",
       "Lagrange top: J = diag(I1, I1, I3), centre of mass on the symmetry axis e3; invariants m.k, m_psi = I3 Omega3",
       {"type", "inertia", "b", "k"},
       parse_lagrange_top},
      {"kovalevskaya_top",
       "Kovalevskaya top: J = diag(2 I3, 2 I3, I3), centre of mass z0 in the equatorial plane; Kovalevskaya's integral",
       {"type", "inertia", "b", "k", "z0"},
       parse_kovalevskaya_top},
      {"satellite",
       "satellite on a circular orbit (rate n) under the gravity-gradient torque 3 n^2 rho x J rho, rho = R^T r(t)",
       {"type", "inertia", "n", "radial", "normal"},
       parse_satellite},
      {"potential",
       "body defined by its potential alone, V = sum b_j k_j.(R z_j) + c/2 a.(R Q R^T a); torque by automatic "
       "differentiation",
       {"type", "inertia", "fields", "gradient"},
       parse_potential},
  };
}

}  // namespace lgi::app
