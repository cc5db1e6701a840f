#include "registry.hpp"

namespace lgi::app {
namespace {

AnyProblem parse_free_body(const Node& p) { return FreeBody<double>{read_inertia(p.at("inertia"))}; }

AnyProblem parse_heavy_top(const Node& p) {
  HeavyTop<double> top;
  top.inertia = read_inertia(p.at("inertia"));
  top.b = p.at("b").non_negative();
  if (auto k = p.find("k")) top.k = read_unit_vector(*k);
  if (auto z0 = p.find("z0")) top.z0 = read_unit_vector(*z0);
  return top;
}

}  // namespace

std::vector<ProblemInfo> foundation_problem_infos() {
  return {
      {"free_body", "free rigid body (Euler-Poinsot), J Omega' = (J Omega) x Omega", {"type", "inertia"},
       parse_free_body},
      {"heavy_top", "heavy top, seed paper eqs. (s4)-(s5): torque b (R^T k) x z0", {"type", "inertia", "b", "k", "z0"},
       parse_heavy_top},
  };
}

}  // namespace lgi::app
