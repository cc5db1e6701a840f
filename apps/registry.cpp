#include "registry.hpp"

#include <lgi/core/inertia.hpp>
#include <lgi/core/so3.hpp>

#include <Eigen/SVD>

#include <cmath>
#include <utility>

namespace lgi::app {

Mat3<double> read_inertia(const Node& node) {
  const std::size_t n = node.size();
  const bool matrix = !(n == 3 && !node.value()[0].is_array());
  const Mat3<double> J = matrix ? node.mat3() : Mat3<double>(node.vec3().asDiagonal());
  int row = -1, col = -1;
  if (const auto defect = inertia_defect(J, &row, &col)) {
    if (row >= 0 && matrix) node.at(static_cast<std::size_t>(row)).at(static_cast<std::size_t>(col)).fail(*defect);
    node.fail(*defect);
  }
  return 0.5 * (J + J.transpose());  // symmetric to the last bit (accepted within 1e-12)
}

Vec3<double> read_unit_vector(const Node& node) {
  const Vec3<double> v = node.vec3();
  const double norm = v.norm();
  if (!(std::abs(norm - 1) <= 1e-9))
    node.fail("must be a unit vector (to 1e-9), its length is " + format_number(norm));
  return v / norm;
}

Mat3<double> read_rotation(const Node& node) {
  const Mat3<double> R = node.mat3();
  const double orth = so3::orthogonality_error(R);
  const double det = R.determinant();
  if (!(orth <= 1e-9) || !(det > 0))
    node.fail("must be a rotation matrix (to 1e-9): |R^T R - I| = " + format_number(orth) +
              ", det R = " + format_number(det));
  const Eigen::JacobiSVD<Mat3<double>> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();  // polar factor: the nearest rotation
}

namespace {

template <template <class> class... Ms>
std::vector<MethodInfo> method_table(MethodList<Ms...>) {
  return {MethodInfo{Ms<FreeBody<double>>::traits}...};
}

// (method name, problem name) for every pair where the method applies.
template <class... Ps, template <class> class... Ms>
std::vector<std::pair<std::string_view, std::string_view>> applicability(ProblemList<Ps...>, MethodList<Ms...>) {
  std::vector<std::pair<std::string_view, std::string_view>> pairs;
  const auto add_problem = [&]<class P>() {
    ((method_applies_v<Ms, P> ? (void)pairs.emplace_back(Ms<FreeBody<double>>::traits.name, P::name) : (void)0), ...);
  };
  (add_problem.template operator()<Ps>(), ...);
  return pairs;
}

template <class T>
std::string join_names(const T& table, std::string_view problem = {}) {
  std::string s;
  for (const auto& e : table) {
    std::string_view name;
    if constexpr (requires { e.traits; })
      name = e.traits.name;
    else
      name = e.name;
    if (!problem.empty() && !method_applies(name, problem)) continue;
    if (!s.empty()) s += ", ";
    s += name;
  }
  return s;
}

}  // namespace

std::span<const ProblemInfo> problem_registry() {
  static const std::vector<ProblemInfo> table = [] {
    std::vector<ProblemInfo> all;
    for (auto family : {foundation_problem_infos(), library_problem_infos(), paper_problem_infos()})
      for (auto& info : family) all.push_back(std::move(info));
    return all;
  }();
  return table;
}

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

bool method_applies(std::string_view method, std::string_view problem) {
  static const auto pairs = applicability(Problems{}, Methods{});
  for (const auto& [m, p] : pairs)
    if (m == method && p == problem) return true;
  return false;
}

std::string known_methods(std::string_view problem) { return join_names(method_registry(), problem); }
std::string known_problems() { return join_names(problem_registry()); }

}  // namespace lgi::app
