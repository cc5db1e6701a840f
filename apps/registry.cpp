#include "registry.hpp"

#include <lgi/core/inertia.hpp>


#include <cmath>

namespace lgi::app {
namespace {

// "inertia": a symmetric 3×3 array, or [I1, I2, I3] for a diagonal tensor; checked to be physical.
Mat3<double> read_inertia(const Node& node) {
  const std::size_t n = node.size();
  Mat3<double> J;
  if (n == 3 && !node.value()[0].is_array()) {
    J = node.vec3().asDiagonal();
  } else {
    J = node.mat3();
  }
  int row = -1, col = -1;
  if (const auto defect = inertia_defect(J, &row, &col)) {
    if (row >= 0 && n == 3 && node.value()[0].is_array())
      node.at(static_cast<std::size_t>(row)).at(static_cast<std::size_t>(col)).fail(*defect);
    node.fail(*defect);
  }
  return 0.5 * (J + J.transpose());  // symmetric to the last bit (accepted within 1e-12)
}

// A unit vector, within 1e-9; returned normalised exactly.
Vec3<double> read_unit_vector(const Node& node) {
  const Vec3<double> v = node.vec3();
  const double norm = v.norm();
  if (!(std::abs(norm - 1) <= 1e-9))
    node.fail("must be a unit vector (to 1e-9), its length is " + format_number(norm));
  return v / norm;
}

AnyProblem parse_free_body(const Node& p) { return FreeBody<double>{read_inertia(p.at("inertia"))}; }

AnyProblem parse_heavy_top(const Node& p) {
  HeavyTop<double> top;
  top.inertia = read_inertia(p.at("inertia"));
  top.b = p.at("b").non_negative();
  if (auto k = p.find("k")) top.k = read_unit_vector(*k);
  if (auto z0 = p.find("z0")) top.z0 = read_unit_vector(*z0);
  return top;
}

const std::vector<ProblemInfo>& problems() {
  static const std::vector<ProblemInfo> table = {
      {"free_body", "free rigid body (Euler-Poinsot), J Omega' = (J Omega) x Omega", {"type", "inertia"},
       parse_free_body},
      {"heavy_top", "heavy top, seed paper eqs. (s4)-(s5): torque b (R^T k) x z0",
       {"type", "inertia", "b", "k", "z0"}, parse_heavy_top},
  };
  return table;
}

template <template <class> class... Ms>
std::vector<MethodInfo> method_table(MethodList<Ms...>) {
  return {MethodInfo{Ms<FreeBody<double>>::traits}...};
}

template <class T>
std::string join_names(const T& table) {
  std::string s;
  for (const auto& e : table) {
    if (!s.empty()) s += ", ";
    if constexpr (requires { e.traits; })
      s += e.traits.name;
    else
      s += e.name;
  }
  return s;
}

}  // namespace

std::span<const ProblemInfo> problem_registry() { return problems(); }

std::span<const MethodInfo> method_registry() {
  static const std::vector<MethodInfo> table = method_table(Methods{});
  return table;
}

const ProblemInfo* find_problem(std::string_view name) {
  for (const auto& p : problem_registry())
    if (p.name == name) return &p;
  return nullptr;
}

const MethodInfo* find_method(std::string_view name) {
  for (const auto& m : method_registry())
    if (m.traits.name == name) return &m;
  return nullptr;
}

std::string known_methods() { return join_names(method_registry()); }
std::string known_problems() { return join_names(problem_registry()); }

}  // namespace lgi::app
