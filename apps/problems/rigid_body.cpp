// lgi/apps/problems/rigid_body.cpp — the `rigid_body` problem type of scenes (problems/torqued_body.hpp): a body under
// optional uniform gravity and a list of torque terms; its parser and its registration (every method that applies to
// it is compiled here, problem_model.hpp). The format is documented in docs/scenes.md, "rigid_body".
#include "torqued_body_reader.hpp"

#include "../csv_reader.hpp"
#include "../problem_model.hpp"

#include <lgi/problems/torqued_body.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

namespace lgi::app {
namespace {

// "gravity": {"b": b ≥ 0, "k": unit (default e3), "z0": unit (default e3)} — the heavy top's.
void read_gravity(const Node& g, TorquedBody<double>& body) {
  if (!g.is_object()) g.fail("expected {\"b\": ..., \"k\": [x, y, z], \"z0\": [x, y, z]}, got " + describe(g.value()));
  g.allow_only({"b", "k", "z0"}, "gravity");
  body.b = g.at("b").non_negative();
  if (auto k = g.find("k")) body.k = read_unit_vector(*k);
  if (auto z0 = g.find("z0")) body.z0 = read_unit_vector(*z0);
}

// A damping matrix: symmetric to 1e-12 of its largest entry (then symmetrised exactly) and positive semi-definite
// (its smallest eigenvalue ≥ −1e-12 of its largest).
Mat3<double> read_damping_matrix(const Node& node) {
  const Mat3<double> C = node.mat3();
  const double scale = C.cwiseAbs().maxCoeff();
  const double asymmetry = (C - C.transpose()).cwiseAbs().maxCoeff();
  if (!(asymmetry <= 1e-12 * scale))
    node.fail("the damping matrix must be symmetric (largest |C_ij - C_ji| = " + format_number(asymmetry) + ")");
  const Mat3<double> S = (C + C.transpose()) / 2;
  const double smallest = Eigen::SelfAdjointEigenSolver<Mat3<double>>(S, Eigen::EigenvaluesOnly).eigenvalues()(0);
  if (!(smallest >= -1e-12 * scale))
    node.fail("the damping matrix must be positive semi-definite (it would feed energy in): smallest eigenvalue " +
              format_number(smallest));
  return S;
}

// "target": {"R": ...} | {"quaternion": [w, x, y, z]} | {"axis_angle": {...}} (the forms of "initial").
Mat3<double> read_target(const Node& t) {
  if (!t.is_object()) t.fail("expected {\"R\": ...}, {\"quaternion\": ...} or {\"axis_angle\": ...}, got " + describe(t.value()));
  t.allow_only({"R", "quaternion", "axis_angle"}, "target");
  const auto R = t.find("R"), q = t.find("quaternion"), a = t.find("axis_angle");
  if ((R ? 1 : 0) + (q ? 1 : 0) + (a ? 1 : 0) != 1) t.fail("give the target attitude once, as R, quaternion or axis_angle");
  if (R) return read_rotation(*R);
  if (q) return read_quaternion(*q);
  return read_axis_angle(*a);
}

}  // namespace

// {"file": CSV, "interpolation": "linear" (default) | "cubic"} (and the caller's keys): the CSV (relative to the
// scene's directory) has the columns `names` (t first) in any order, at least 2 rows, t strictly increasing from at
// most 0 (the run's start); sample component k is column names[k + 1], the rest 0.
template <int D>
std::shared_ptr<const SampleTable<D>> read_sample_table(const Node& term, const std::vector<std::string>& names,
                                                        const std::string& what) {
  const Node file = term.at("file");
  std::filesystem::path path = file.string();
  if (path.is_relative()) path = std::filesystem::path(term.directory()) / path;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    file.fail("cannot read the " + what + " " + path.string() + (ec ? ": " + ec.message() : ": not a regular file"));
  TableInterpolation interpolation = TableInterpolation::linear;
  if (const auto i = term.find("interpolation")) {
    const std::string name = i->string();
    if (name == "cubic")
      interpolation = TableInterpolation::cubic;
    else if (name != "linear")
      i->fail("unknown interpolation " + quoted_input(name) + did_you_mean(name, {"linear", "cubic"}) +
              " (known: linear, cubic)");
  }
  const std::string csv = path.string();
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::vector<int> lines;
  std::uint64_t digest = 0;
  read_csv(csv, header, rows, lines, what, &digest);
  std::string have, want;
  for (const std::string& h : header) have += (have.empty() ? "" : ", ") + h;
  for (const std::string& n : names) want += (want.empty() ? "" : ", ") + n;
  for (const std::string& h : header)
    if (std::find(names.begin(), names.end(), h) == names.end())
      throw CsvError(csv + ": unknown column " + quoted_input(h) + " in the header (a " + what + " has the columns " +
                     want + ")");
  std::vector<std::size_t> column(names.size());
  for (std::size_t i = 0; i < names.size(); ++i) {
    column[i] = static_cast<std::size_t>(std::find(header.begin(), header.end(), names[i]) - header.begin());
    if (column[i] == header.size())
      throw CsvError(csv + ": missing column " + names[i] + " (the header has " + have + "; a " + what + " has " + want +
                     ")");
  }
  if (rows.size() < 2)
    throw CsvError(csv + ": a " + what + " needs at least 2 rows to interpolate, it has " + std::to_string(rows.size()));
  if (const double t0 = rows[0][column[0]]; t0 > 0)
    throw CsvError(csv + ":" + std::to_string(lines[0]) + ": the table starts at t = " + format_number(t0) +
                   ", after the run's start t = 0 (the torque would be undefined there)");
  std::vector<double> t;
  std::vector<typename SampleTable<D>::Sample> M;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const double tr = rows[r][column[0]];
    if (r > 0 && !(tr > t.back()))
      throw CsvError(csv + ":" + std::to_string(lines[r]) + ": t = " + format_number(tr) +
                     " does not come after the previous row's t = " + format_number(t.back()) + " (a " + what +
                     "'s times increase strictly)");
    t.push_back(tr);
    typename SampleTable<D>::Sample sample = SampleTable<D>::Sample::Zero();
    for (std::size_t k = 1; k < names.size(); ++k) sample(static_cast<Eigen::Index>(k - 1)) = rows[r][column[k]];
    M.push_back(sample);
  }
  return std::make_shared<const SampleTable<D>>(std::move(t), std::move(M), interpolation, csv, digest);
}
template std::shared_ptr<const SampleTable<3>> read_sample_table<3>(const Node&, const std::vector<std::string>&,
                                                                    const std::string&);
template std::shared_ptr<const SampleTable<6>> read_sample_table<6>(const Node&, const std::vector<std::string>&,
                                                                    const std::string&);

namespace {

void read_term(const Node& term, TorquedBody<double>& body, bool& has_controller) {
  if (!term.is_object()) term.fail("expected a torque term {\"type\": ...}, got " + describe(term.value()));
  const std::string type = term.at("type").string();
  if (type == "constant") {
    term.allow_only({"type", "frame", "torque"}, "a constant torque");
    const std::string frame = term.at("frame").string();
    const Vec3<double> M = term.at("torque").vec3();
    if (frame == "body") {
      body.body_torque += M;
    } else if (frame == "lab") {
      body.lab_torque += M;
    } else {
      term.at("frame").fail("unknown frame " + quoted_input(frame) + did_you_mean(frame, {"body", "lab"}) +
                            " (known: body, lab)");
    }
    body.has_constant = true;
  } else if (type == "table") {
    term.allow_only({"type", "file", "frame", "interpolation"}, "a torque table");
    if (body.table) term.fail("one table term per body");
    const std::string frame = term.at("frame").string();
    if (frame != "body" && frame != "lab")
      term.at("frame").fail("unknown frame " + quoted_input(frame) + did_you_mean(frame, {"body", "lab"}) +
                            " (known: body, lab)");
    body.table = read_sample_table<3>(term, {"t", "M1", "M2", "M3"}, "torque table");
    body.table_in_lab = frame == "lab";
  } else if (type == "damping") {
    term.allow_only({"type", "coefficient", "matrix"}, "damping");
    const auto c = term.find("coefficient"), C = term.find("matrix");
    if ((c ? 1 : 0) + (C ? 1 : 0) != 1) term.fail("give the damping once, as a coefficient c (C = c I) or a matrix C");
    body.damping += c ? Mat3<double>(c->non_negative() * Mat3<double>::Identity()) : read_damping_matrix(*C);
    body.has_damping = true;
  } else if (type == "attitude_control") {
    term.allow_only({"type", "target", "target_omega", "k_R", "k_Omega"}, "attitude_control");
    if (has_controller) term.fail("one attitude_control term per body");
    has_controller = true;
    body.target = read_target(term.at("target"));
    if (auto w = term.find("target_omega")) body.target_omega = w->vec3();
    body.k_R = term.at("k_R").non_negative();
    body.k_Omega = term.at("k_Omega").non_negative();
    body.has_control = true;
  } else if (type == "gravity_gradient") {
    term.allow_only({"type", "n", "radial", "normal"}, "gravity_gradient");
    if (body.has_gravity_gradient) term.fail("one gravity_gradient term per body");
    const CircularOrbit orbit = read_circular_orbit(term);
    body.orbit_rate = orbit.n;
    body.radial = orbit.radial;
    body.normal = orbit.normal;
    body.has_gravity_gradient = true;
  } else {
    term.at("type").fail("unknown torque term " + quoted_input(type) +
                         did_you_mean(type, {"constant", "table", "damping", "attitude_control", "gravity_gradient"}) +
                         " (known: constant, table, damping, attitude_control, gravity_gradient)");
  }
}

}  // namespace

TorquedBody<double> read_torqued_body(const Node& p) {
  TorquedBody<double> body;
  body.inertia = read_inertia(p.at("inertia"));
  if (auto g = p.find("gravity")) read_gravity(*g, body);
  if (auto torques = p.find("torques")) {
    if (!torques->is_array()) torques->fail("expected an array of torque terms, got " + describe(torques->value()));
    bool has_controller = false;
    for (std::size_t i = 0; i < torques->size(); ++i) read_term(torques->at(i), body, has_controller);
  }
  return body;
}

Mat3<double> read_target_attitude(const Node& t) { return read_target(t); }

CircularOrbit read_circular_orbit(const Node& p) {
  CircularOrbit o;
  o.n = p.at("n").positive();
  if (auto nu = p.find("normal")) o.normal = read_unit_vector(*nu);
  if (auto r = p.find("radial")) {
    const Vec3<double> r0 = read_unit_vector(*r);
    const double c = r0.dot(o.normal);
    if (!(std::abs(c) <= 1e-9))
      r->fail("the radial direction must be perpendicular to the orbit normal (to 1e-9), radial . normal = " +
              format_number(c));
    o.radial = (r0 - c * o.normal).normalized();
  } else if (std::abs(o.normal.dot(o.radial)) > 1e-9) {
    p.at("normal").fail("the default radial direction e1 is not perpendicular to this orbit normal: give \"radial\"");
  } else {
    o.radial = (o.radial - o.normal.dot(o.radial) * o.normal).normalized();
  }
  return o;
}

LGI_DEFINE_PROBLEM(rigid_body, TorquedBody<double>, "rigid body under optional gravity and torque terms: constant or tabulated (body or lab frame), damping -C Omega, PD attitude control, gravity gradient", ({"type", "inertia", "gravity", "torques"}), read_torqued_body)

}  // namespace lgi::app
