// lgi/apps/problems/rigid_body.cpp — the `rigid_body` problem type of scenes (problems/torqued_body.hpp): a body under
// optional uniform gravity and a list of torque terms; its parser and its registration (every method that applies to
// it is compiled here, problem_model.hpp). The format is documented in docs/scenes.md, "rigid_body".
#include "../problem_model.hpp"

#include <lgi/problems/torqued_body.hpp>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <string>

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
  } else {
    term.at("type").fail("unknown torque term " + quoted_input(type) +
                         did_you_mean(type, {"constant", "damping", "attitude_control"}) +
                         " (known: constant, damping, attitude_control)");
  }
}

TorquedBody<double> parse(const Node& p) {
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

}  // namespace

LGI_DEFINE_PROBLEM(rigid_body, TorquedBody<double>, "rigid body under optional gravity and torque terms: constant (body or lab frame), damping -C Omega, PD attitude control", ({"type", "inertia", "gravity", "torques"}), parse)

}  // namespace lgi::app
