// lgi/apps/problems/potential.cpp — the `potential` problem type of scenes: its parser and its registration (every method
// that applies to it is compiled here, problem_model.hpp).
#include "../problem_model.hpp"

#include <lgi/problems/potential_problem.hpp>

#include <cmath>
#include <string>

namespace lgi::app {
namespace {

FieldPotentialBody<double> parse(const Node& p) {
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

LGI_DEFINE_PROBLEM(potential, FieldPotentialBody<double>, "body defined by its potential alone, V = sum b_j k_j.(R z_j) + c/2 a.(R Q R^T a); torque by automatic "
                   "differentiation", ({"type", "inertia", "fields", "gradient"}), parse)

}  // namespace lgi::app
