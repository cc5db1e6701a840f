// lgi/apps/problems/gyrostat.cpp — the `gyrostat` problem type of scenes (problems/gyrostat.hpp): a rigid_body's
// inertia, gravity and torque terms, plus rotors and an optional PD law through them; its parser, its methods
// (integrators/gyrostat.hpp: `lgvi` and its compositions, the RKMK tableaus with fixed steps) and its rows. The format
// is documented in docs/scenes.md, "gyrostat".
#include "torqued_body_reader.hpp"

#include "../problem_model.hpp"

#include <lgi/integrators/composition.hpp>
#include <lgi/integrators/gyrostat.hpp>
#include <lgi/problems/gyrostat.hpp>

#include <cmath>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

namespace lgi::app {
namespace {

using G = Gyrostat<double>;

// The composition coefficients behind a method `lgvi_<coefficients>`: set for Composition<C, Lgvi, P>.
template <class S>
struct lgvi_composition : std::false_type {};
template <const auto& C, class P>
struct lgvi_composition<Composition<C, Lgvi, P>> : std::true_type {
  static constexpr const auto& coefficients = C;
};

// f.template operator()<S>(name) for every method of the registry that a gyrostat takes, as its gyrostat stepper S:
// lgvi, its compositions, and the RKMK tableaus (exponential chart).
template <class F>
void for_each_gyrostat_method(F&& f) {
  const auto one = [&]<template <class> class M>() {
    if constexpr (requires { typename M<FreeBody<double>>; }) {
      using MF = M<FreeBody<double>>;
      constexpr std::string_view name = MF::traits.name;
      if constexpr (std::is_same_v<MF, Lgvi<FreeBody<double>>>) {
        if (method_enabled(name)) f.template operator()<GyrostatLgvi<G>>(name);
      } else if constexpr (lgvi_composition<MF>::value) {
        if (method_enabled(name))
          f.template operator()<Composition<lgvi_composition<MF>::coefficients, GyrostatLgvi, G>>(name);
      } else if constexpr (rkmk_tableau<MF>::value) {
        if (method_enabled(name)) f.template operator()<GyrostatRkmk<rkmk_tableau<MF>::tableau, G>>(name);
      }
    }
  };
  [&]<template <class> class... Ms>(MethodList<Ms...>) { (one.template operator()<Ms>(), ...); }(Methods{});
}

std::vector<std::string_view> gyrostat_methods() {
  std::vector<std::string_view> names;
  for_each_gyrostat_method([&]<class S>(std::string_view name) { names.push_back(name); });
  return names;
}

// The rows: t, R, Ω, the energy, ‖RᵀR − I‖, then R H = R Rᵀ m (the spatial momentum as the state gives it), |H| and
// the rotors' relative rates.
class GyrostatRunner final : public runner_detail::ProblemRunner {
 public:
  explicit GyrostatRunner(const G& g) : dyn_(g) {}
  std::unique_ptr<Integrator> integrator(const Scene& scene) const override {
    std::unique_ptr<Integrator> engine;
    for_each_gyrostat_method([&]<class S>(std::string_view name) {
      if (!engine && name == scene.method->traits.name) engine = make_integrator<S>(dyn_.problem(), scene.options);
    });
    if (!engine) throw std::logic_error("lgi: method registry out of sync (gyrostat)");
    return engine;
  }
  void columns(double t, const Integrator& engine, Slot s, std::vector<double>& out) const override {
    GyrostatState<double> y;
    std::array<double, number_count<GyrostatState<double>>()> numbers;
    engine.save(s, numbers);
    std::size_t i = 0;
    visit_numbers(y, [&](double& v) { v = numbers[i++]; });
    state_columns(t, y, dyn_.omega(y.R, y.m, y.h), out);
  }
  // The initial state as given (Ω without a round trip through m and h).
  void initial_columns(const Scene& scene, double t, std::vector<double>& out) const override {
    state_columns(t, dyn_.state(scene.initial.R, scene.initial.Omega), scene.initial.Omega, out);
  }

 private:
  void state_columns(double t, const GyrostatState<double>& y, const Vec3<double>& Omega, std::vector<double>& out) const {
    out.push_back(t);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) out.push_back(y.R(r, c));
    for (int i = 0; i < 3; ++i) out.push_back(Omega(i));
    out.push_back(dyn_.energy(y));
    out.push_back(so3::orthogonality_error(y.R));
    const Vec3<double> H = y.R.transpose() * y.m, RH = y.R * H;
    for (int i = 0; i < 3; ++i) out.push_back(RH(i));
    out.push_back(H.norm());
    const auto rates = dyn_.rotor_rates(y.h, Omega);
    for (int i = 0; i < dyn_.problem().rotor_count; ++i) out.push_back(rates(i));
  }

  GyrostatDynamics<double> dyn_;
};

class GyrostatModel final : public ProblemModel {
 public:
  explicit GyrostatModel(const G& g) : g_(g), dyn_(g) {
    names_.assign(momentum_column_names.begin(), momentum_column_names.end());
    for (int i = 0; i < g.rotor_count; ++i) {
      labels_.push_back("rotor_rate_" + std::to_string(i + 1));
    }
    for (const std::string& l : labels_) names_.push_back(l);
  }
  std::string_view type_name() const override { return G::name; }
  std::vector<std::string_view> invariant_names() const override { return names_; }
  // Without external torque R H and |H| are integrals (the rotor torques are internal).
  std::size_t integral_count() const override { return dyn_.has_external() ? 0 : 4; }
  bool on_group() const override { return false; }  // SO(3) × R^(3+N): fixed steps, no integrator options
  std::string coordinates() const override {
    return ", on SO(3) with " + std::to_string(g_.rotor_count) + (g_.rotor_count == 1 ? " rotor" : " rotors");
  }
  std::string methods_note() const override {
    return " (its rotors are stepped with the body by the gyrostat's methods: lgvi and its compositions, and the RKMK "
           "tableaus in the exponential chart, with fixed steps)";
  }
  bool torque_free() const override { return false; }
  bool reads_omega() const override { return dyn_.reads_state(); }
  bool projectable() const override { return false; }
  BodyData body() const override {
    BodyData d;
    d.J = g_.body.inertia;
    d.has_gravity = true;
    d.k = g_.body.k;
    d.z0 = g_.body.z0;
    d.b = g_.body.b;
    for (int i = 0; i < g_.rotor_count; ++i) d.rotor_axes.push_back(g_.rotors[i].axis);
    return d;
  }
  double time_limit() const override { return g_.time_limit(); }
  std::vector<std::pair<std::string, std::uint64_t>> input_files() const override { return g_.input_files(); }
  std::unique_ptr<runner_detail::ProblemRunner> runner() const override { return std::make_unique<GyrostatRunner>(g_); }
  void state_columns(double, const State<double>&, std::vector<double>&) const override {
    throw std::logic_error("lgi: state_columns of a gyrostat (its rotors are not in (R, Omega))");
  }
  const void* get(const std::type_info& type) const override { return type == typeid(G) ? &g_ : nullptr; }

 private:
  G g_;
  GyrostatDynamics<double> dyn_;
  std::vector<std::string> labels_;
  std::vector<std::string_view> names_;
};

// "rotors": [{"axis": unit, "inertia": > 0, "friction": ≥ 0, "motor_torque": g0, "rate": ω_s(0)}, ...], 1 … 6 of them.
void read_rotors(const Node& list, G& g) {
  if (!list.is_array()) list.fail("expected an array of rotors {\"axis\": [x, y, z], \"inertia\": ...}, got " + describe(list.value()));
  const std::size_t n = list.size();
  if (n < 1 || n > static_cast<std::size_t>(G::max_rotors))
    list.fail("a gyrostat carries 1 to " + std::to_string(G::max_rotors) + " rotors, got " + std::to_string(n));
  g.rotor_count = static_cast<int>(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Node r = list.at(i);
    if (!r.is_object()) r.fail("expected a rotor {\"axis\": [x, y, z], \"inertia\": ...}, got " + describe(r.value()));
    r.allow_only({"axis", "inertia", "friction", "motor_torque", "rate"}, "a rotor");
    Rotor<double>& rotor = g.rotors[i];
    rotor.axis = read_unit_vector(r.at("axis"));
    rotor.inertia = r.at("inertia").positive();
    if (auto c = r.find("friction")) rotor.friction = c->non_negative();
    if (auto m = r.find("motor_torque")) rotor.motor = m->number();
    if (auto w = r.find("rate")) rotor.rate = w->number();
  }
  // J_b = J − Σ I_s a aᵀ must stay positive definite (a rotor's axial inertia is part of the body's about that axis):
  // its leading minors positive (Sylvester), to 1e-12 of J's scale.
  const Mat3<double> Jb = g.body_inertia();
  const double scale = g.body.inertia.trace();
  const double minors[3] = {Jb(0, 0), Jb(0, 0) * Jb(1, 1) - Jb(0, 1) * Jb(1, 0), Jb.determinant()};
  for (int k = 0; k < 3; ++k)
    if (!(minors[k] > 1e-12 * std::pow(scale, k + 1)))
      list.fail("the rotors' axial inertias leave the body no inertia about some axis (J - sum I_s a a^T is not "
                "positive definite: its leading " + std::to_string(k + 1) + "x" + std::to_string(k + 1) + " minor is " +
                format_number(minors[k]) + "; the problem's inertia is the whole body's with the rotors locked)");
}

// "wheel_control": {"target": attitude, "target_omega": [..], "k_R": ≥ 0, "k_Omega": ≥ 0}: the PD law through the rotors.
void read_wheel_control(const Node& w, G& g) {
  if (!w.is_object()) w.fail("expected {\"target\": ..., \"k_R\": ..., \"k_Omega\": ...}, got " + describe(w.value()));
  w.allow_only({"target", "target_omega", "k_R", "k_Omega"}, "wheel_control");
  g.target = read_target_attitude(w.at("target"));
  if (auto o = w.find("target_omega")) g.target_omega = o->vec3();
  g.k_R = w.at("k_R").non_negative();
  g.k_Omega = w.at("k_Omega").non_negative();
  Eigen::Matrix<double, 3, G::max_rotors> A = Eigen::Matrix<double, 3, G::max_rotors>::Zero();
  for (int i = 0; i < g.rotor_count; ++i) A.col(i) = g.rotors[i].axis;
  // A Aᵀ = Σ a_i a_iᵀ invertible: det ≥ 1e-6 (axes at 0.1° from a plane give about 1e-6 per pair of axes).
  const double det = Mat3<double>(A * A.transpose()).determinant();
  if (!(det > 1e-6))
    w.fail("the rotors' axes do not span three dimensions (det(A A^T) = " + format_number(det) +
           "): the wheels cannot apply every torque the law asks for");
  g.wheel_control = true;
}

// "motor_table": {"file": CSV, "interpolation": "linear" | "cubic"}: columns t, g1 … gN (N the rotor count), each
// rotor's commanded motor torque, added to its motor_torque.
void read_motor_table(const Node& m, G& g) {
  if (!m.is_object()) m.fail("expected {\"file\": CSV, \"interpolation\": ...}, got " + describe(m.value()));
  m.allow_only({"file", "interpolation"}, "motor_table");
  std::vector<std::string> names{"t"};
  for (int i = 0; i < g.rotor_count; ++i) names.push_back(std::string(1, 'g').append(std::to_string(i + 1)));
  g.motor_table = read_sample_table<G::max_rotors>(m, names, "motor table");
}

std::shared_ptr<const ProblemModel> parse(const Node& p) {
  G g;
  g.body = read_torqued_body(p);
  read_rotors(p.at("rotors"), g);
  if (auto w = p.find("wheel_control")) read_wheel_control(*w, g);
  if (auto m = p.find("motor_table")) read_motor_table(*m, g);
  return std::make_shared<GyrostatModel>(g);
}

}  // namespace

const ProblemInfo& problem_info_gyrostat() {
  static const ProblemInfo info{
      G::name,
      "rigid body with 1-6 rotors (reaction or momentum wheels, dampers): friction, motor torques, PD control through "
      "the wheels, and rigid_body's gravity and torque terms",
      {"type", "inertia", "gravity", "torques", "rotors", "wheel_control", "motor_table"},
      parse,
      gyrostat_methods(),
      false};
  return info;
}

}  // namespace lgi::app
