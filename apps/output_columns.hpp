// lgi/apps/output_columns.hpp — "output": {"columns": [...]}: the CSV columns `lgi run` writes, chosen by group
// (docs/scenes.md), each computed from the standard row (csv_header: t, R11..R33, omega1..omega3, energy,
// orthogonality_error, the problem's invariant columns). Without "columns" a run writes the standard row.
//
//   group                 columns                                  from
//   t                     t
//   R                     R11 … R33                                 (row by row)
//   quaternion            q_w, q_x, q_y, q_z                        R (core/attitude.hpp's convention), its sign
//                                                                   continuous along the run (below)
//   omega                 omega1 … omega3                           (body frame)
//   euler_zxz[_deg]       zxz_phi, zxz_theta, zxz_psi[_deg]         R: θ ∈ [0, π], φ, ψ ∈ (−π, π]
//   euler_zyx[_deg]       yaw, pitch, roll[_deg]                    R: pitch ∈ [−π/2, π/2], yaw, roll ∈ (−π, π]
//   energy                energy
//   orthogonality_error   orthogonality_error                       ‖RᵀR − I‖_F
//   invariants            the problem's invariant columns
//
// The quaternion of the first row has w ≥ 0 (the first non-zero component positive when w = 0); every later row
// takes the sign that makes q·q_previous ≥ 0, so that q(t) is continuous where R(t) is. The previous row's q is
// part of a checkpoint (a resumed run writes the same bytes).
#pragma once

#include "json_reader.hpp"

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace lgi::app {

enum class ColumnGroup : std::uint8_t {
  t, R, quaternion, omega, euler_zxz, euler_zxz_deg, euler_zyx, euler_zyx_deg, energy, orthogonality_error, invariants
};

// Reads "columns": a non-empty array of distinct group names; an unknown one is an InputError naming it (with the
// nearest name).
std::vector<ColumnGroup> read_column_groups(const Node& node);

// The header of the chosen columns (`invariant_names`: the problem's invariant columns).
std::string column_header(std::span<const ColumnGroup> groups, std::span<const std::string_view> invariant_names);

// Maps standard rows to the chosen columns, row after row (the quaternion's sign follows the previous row's).
class ColumnMapper {
 public:
  explicit ColumnMapper(std::vector<ColumnGroup> groups) : groups_(std::move(groups)) {}
  // Appends the chosen columns of the standard row `standard` to `out`.
  void map(std::span<const double> standard, std::vector<double>& out);
  // The previous row's quaternion (empty before the first row or without a quaternion group): for checkpoints.
  std::vector<double> previous_quaternion() const;
  // Continues after a row whose quaternion was `q` (4 numbers; empty: none yet).
  void set_previous_quaternion(std::span<const double> q);

 private:
  std::vector<ColumnGroup> groups_;
  std::array<double, 4> previous_{};
  bool has_previous_ = false;
};

}  // namespace lgi::app
