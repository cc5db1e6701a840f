#include "registry.hpp"

#include <lgi/core/attitude.hpp>
#include <lgi/core/inertia.hpp>
#include <lgi/core/so3.hpp>

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
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

namespace {
// Records a defect removed from `node` when it is above input_note_defect.
void note(const Node& node, const std::string& what, double defect) {
  if (defect > input_note_defect) node.adjusted(what, defect);
}

}  // namespace

std::string format_defect(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g", x);
  return buf;
}

Vec3<double> read_unit_vector(const Node& node) {
  const Vec3<double> v = node.vec3();
  const double norm = v.norm(), defect = std::abs(norm - 1);
  if (!(defect <= input_defect_bound))
    node.fail("must be a unit vector (to " + format_number(input_defect_bound) + "), its length is " +
              format_number(norm));
  note(node, std::string("normalised (its length was 1 ") + (norm < 1 ? "- " : "+ ") + format_defect(defect) + ")", defect);
  return v / norm;
}

Mat3<double> read_rotation(const Node& node) {
  const Mat3<double> R = node.mat3();
  const double orth = so3::orthogonality_error(R);
  const double det = R.determinant();
  if (!(orth <= input_defect_bound) || !(det > 0))
    node.fail("must be a rotation matrix (to " + format_number(input_defect_bound) +
              "): |R^T R - I| = " + format_number(orth) + ", det R = " + format_number(det));
  note(node, "projected onto SO(3), the nearest rotation (|R^T R - I| was " + format_defect(orth) + ")", orth);
  return nearest_rotation(R);
}

Mat3<double> nearest_rotation(const Mat3<double>& M) {
  const Eigen::JacobiSVD<Mat3<double>> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
  return svd.matrixU() * svd.matrixV().transpose();
}

Mat3<double> read_quaternion(const Node& node) {
  if (!node.is_array() || node.size() != 4)
    node.fail("expected a quaternion [w, x, y, z] (4 numbers, scalar first), got " + describe(node.value()));
  double q[4];
  for (std::size_t i = 0; i < 4; ++i) q[i] = node.at(i).number();
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]), defect = std::abs(norm - 1);
  if (!(defect <= input_defect_bound))
    node.fail("must be a unit quaternion (to " + format_number(input_defect_bound) + "), its length is " +
              format_number(norm));
  note(node, std::string("normalised (its length was 1 ") + (norm < 1 ? "- " : "+ ") + format_defect(defect) + ")", defect);
  // q and −q are the same rotation: the same bits too (w ≥ 0, or the first non-zero component positive).
  const double* lead = std::find_if(q, q + 4, [](double c) { return c != 0; });
  if (lead != q + 4 && *lead < 0)
    for (double& c : q) c = -c;
  return rotation_from_quaternion(q[0], q[1], q[2], q[3]);
}

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

// The built-in problem types (apps/problems/ID.cpp).
#ifndef LGI_PROBLEM_LIST
#define LGI_PROBLEM_LIST "problems/list.def"
#endif
#define LGI_PROBLEM(id) const ProblemInfo& problem_info_##id();
#include LGI_PROBLEM_LIST
#undef LGI_PROBLEM

namespace {

template <template <class> class... Ms>
std::vector<MethodInfo> method_table(MethodList<Ms...>) {
  std::vector<MethodInfo> table;
  ((method_enabled(Ms<FreeBody<double>>::traits.name) ? table.push_back(MethodInfo{Ms<FreeBody<double>>::traits})
                                                      : void()),
   ...);
  return table;
}

std::vector<ProblemInfo>& problem_table() {
  static std::vector<ProblemInfo> table = {
#define LGI_PROBLEM(id) problem_info_##id(),
#include LGI_PROBLEM_LIST
#undef LGI_PROBLEM
  };
  return table;
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

std::span<const ProblemInfo> problem_registry() { return problem_table(); }

bool add_problem(const ProblemInfo& info) {
  if (find_problem(info.name)) return false;
  problem_table().push_back(info);
  return true;
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
  const ProblemInfo* p = find_problem(problem);
  return p && std::find(p->methods.begin(), p->methods.end(), method) != p->methods.end();
}

std::string known_methods(std::string_view problem) { return join_names(method_registry(), problem); }
std::string known_problems() { return join_names(problem_registry()); }

// "unit" of an angle: "rad" (the default) or "deg"; returns the factor to radians.
double read_angle_unit(const std::optional<Node>& unit) {
  if (!unit) return 1;
  const std::string u = unit->string();
  if (u == "rad") return 1;
  if (u == "deg") return std::numbers::pi / 180;
  unit->fail("unknown unit " + quoted_input(u) + did_you_mean(u, {"rad", "deg"}) + " (known: rad, deg)");
}

// "axis_angle": {"axis": [x, y, z] (any length but 0), "angle": θ, "unit": "rad" | "deg"}.
Mat3<double> read_axis_angle(const Node& node) {
  if (!node.is_object()) node.fail("expected {\"axis\": [x, y, z], \"angle\": ...}, got " + describe(node.value()));
  node.allow_only({"axis", "angle", "unit"}, "axis_angle");
  const Node axis_node = node.at("axis");
  const Vec3<double> axis = axis_node.vec3();
  if (!(axis.norm() > 0)) axis_node.fail("must not be zero");
  const double angle = node.at("angle").number() * read_angle_unit(node.find("unit"));
  return rotation_from_axis_angle(axis, angle);
}

}  // namespace lgi::app
