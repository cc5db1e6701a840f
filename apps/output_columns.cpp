#include "output_columns.hpp"

#include <lgi/core/attitude.hpp>
#include <lgi/core/so3.hpp>
#include <lgi/integrators/free_body_flows.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace lgi::app {
namespace {

struct GroupName {
  std::string_view name;
  ColumnGroup group;
};
constexpr GroupName group_names[] = {
    {"t", ColumnGroup::t},
    {"R", ColumnGroup::R},
    {"quaternion", ColumnGroup::quaternion},
    {"omega", ColumnGroup::omega},
    {"euler_zxz", ColumnGroup::euler_zxz},
    {"euler_zxz_deg", ColumnGroup::euler_zxz_deg},
    {"euler_zyx", ColumnGroup::euler_zyx},
    {"euler_zyx_deg", ColumnGroup::euler_zyx_deg},
    {"energy", ColumnGroup::energy},
    {"orthogonality_error", ColumnGroup::orthogonality_error},
    {"invariants", ColumnGroup::invariants},
};

// The standard row's layout (csv_header).
constexpr std::size_t col_t = 0, col_R = 1, col_omega = 10, col_energy = 13, col_orthogonality = 14, col_invariants = 15;

Mat3<double> rotation_of(std::span<const double> standard) {
  Mat3<double> R;
  for (int e = 0; e < 9; ++e) R(e / 3, e % 3) = standard[col_R + static_cast<std::size_t>(e)];
  return R;
}

}  // namespace

std::vector<ColumnGroup> read_column_groups(const Node& node) {
  if (!node.is_array() || node.size() == 0)
    node.fail("expected a non-empty array of column groups (t, R, quaternion, omega, euler_zxz, euler_zyx, ...), got " +
              describe(node.value()));
  std::vector<std::string_view> names;
  for (const GroupName& g : group_names) names.push_back(g.name);
  std::vector<ColumnGroup> groups;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const Node n = node.at(i);
    const std::string name = n.string();
    const auto it = std::find_if(std::begin(group_names), std::end(group_names),
                                 [&](const GroupName& g) { return g.name == name; });
    if (it == std::end(group_names)) {
      std::string known;
      for (const std::string_view k : names) known += (known.empty() ? "" : ", ") + std::string(k);
      n.fail("unknown column group " + quoted_input(name) + did_you_mean(name, names) + " (known: " + known + ")");
    }
    if (std::find(groups.begin(), groups.end(), it->group) != groups.end()) n.fail(quoted_input(name) + " twice");
    groups.push_back(it->group);
  }
  return groups;
}

std::string column_header(std::span<const ColumnGroup> groups, std::span<const std::string_view> invariant_names) {
  std::vector<std::string> names;
  for (const ColumnGroup g : groups) {
    switch (g) {
      case ColumnGroup::t: names.push_back("t"); break;
      case ColumnGroup::R:
        for (const char* r : {"1", "2", "3"})
          for (const char* c : {"1", "2", "3"}) names.push_back(std::string("R") + r + c);
        break;
      case ColumnGroup::quaternion: names.insert(names.end(), {"q_w", "q_x", "q_y", "q_z"}); break;
      case ColumnGroup::omega: names.insert(names.end(), {"omega1", "omega2", "omega3"}); break;
      case ColumnGroup::euler_zxz: names.insert(names.end(), {"zxz_phi", "zxz_theta", "zxz_psi"}); break;
      case ColumnGroup::euler_zxz_deg: names.insert(names.end(), {"zxz_phi_deg", "zxz_theta_deg", "zxz_psi_deg"}); break;
      case ColumnGroup::euler_zyx: names.insert(names.end(), {"yaw", "pitch", "roll"}); break;
      case ColumnGroup::euler_zyx_deg: names.insert(names.end(), {"yaw_deg", "pitch_deg", "roll_deg"}); break;
      case ColumnGroup::energy: names.push_back("energy"); break;
      case ColumnGroup::orthogonality_error: names.push_back("orthogonality_error"); break;
      case ColumnGroup::invariants:
        for (const std::string_view n : invariant_names) names.emplace_back(n);
        break;
    }
  }
  std::string h;
  for (const std::string& n : names) h += (h.empty() ? "" : ",") + n;
  return h;
}

void ColumnMapper::map(std::span<const double> standard, std::vector<double>& out) {
  constexpr double deg = 180 / std::numbers::pi;
  for (const ColumnGroup g : groups_) {
    switch (g) {
      case ColumnGroup::t: out.push_back(standard[col_t]); break;
      case ColumnGroup::R: out.insert(out.end(), standard.begin() + col_R, standard.begin() + col_R + 9); break;
      case ColumnGroup::quaternion: {
        const Quaternion<double> u = quat::from_matrix(rotation_of(standard));
        std::array<double, 4> q{u.w, u.v(0), u.v(1), u.v(2)};
        bool flip;
        if (has_previous_) {
          flip = q[0] * previous_[0] + q[1] * previous_[1] + q[2] * previous_[2] + q[3] * previous_[3] < 0;
        } else {
          const auto lead = std::find_if(q.begin(), q.end(), [](double c) { return c != 0; });
          flip = lead != q.end() && *lead < 0;
        }
        if (flip)
          for (double& c : q) c = -c;
        previous_ = q;
        has_previous_ = true;
        out.insert(out.end(), q.begin(), q.end());
        break;
      }
      case ColumnGroup::omega: out.insert(out.end(), standard.begin() + col_omega, standard.begin() + col_omega + 3); break;
      case ColumnGroup::euler_zxz:
      case ColumnGroup::euler_zxz_deg: {
        const Vec3<double> a = euler_from_rotation(EulerConvention::zxz, rotation_of(standard));
        for (int i = 0; i < 3; ++i) out.push_back(g == ColumnGroup::euler_zxz ? a(i) : a(i) * deg);
        break;
      }
      case ColumnGroup::euler_zyx:
      case ColumnGroup::euler_zyx_deg: {
        const Vec3<double> a = euler_from_rotation(EulerConvention::zyx, rotation_of(standard));
        for (int i = 0; i < 3; ++i) out.push_back(g == ColumnGroup::euler_zyx ? a(i) : a(i) * deg);
        break;
      }
      case ColumnGroup::energy: out.push_back(standard[col_energy]); break;
      case ColumnGroup::orthogonality_error: out.push_back(standard[col_orthogonality]); break;
      case ColumnGroup::invariants: out.insert(out.end(), standard.begin() + col_invariants, standard.end()); break;
    }
  }
}

std::vector<double> ColumnMapper::previous_quaternion() const {
  if (!has_previous_) return {};
  return {previous_.begin(), previous_.end()};
}

void ColumnMapper::set_previous_quaternion(std::span<const double> q) {
  has_previous_ = q.size() == 4;
  if (has_previous_) std::copy(q.begin(), q.end(), previous_.begin());
}

}  // namespace lgi::app
