// lgi/apps/sweep_observe.cpp — extrema, Poincaré crossings and Lyapunov estimates of a sweep's members
// (sweep_observe.hpp has the definitions, docs/sweep.md the user's guide).
#include "sweep_observe.hpp"

#include <lgi/core/so3.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace lgi::app {

BodyData body_data(const Scene& scene) { return scene.problem->body(); }

double StateFunction::operator()(const State<double>& x, const BodyData& body) const {
  switch (kind) {
    case Kind::R: return x.R(i, j);
    case Kind::omega: return x.Omega(i);
    case Kind::pi: return body.J.row(i).dot(x.Omega);
    case Kind::gamma: return x.R.col(i).dot(body.k);  // (Rᵀk)_i
    case Kind::height: return body.k.dot(x.R * body.z0);
    case Kind::tilt: {
      const Vec3<double> axis = x.R * body.z0;
      return std::atan2(body.k.cross(axis).norm(), body.k.dot(axis));
    }
  }
  return 0;
}

StateFunction read_state_function(const Node& node, const BodyData& body, const std::string& problem_type) {
  const std::string name = node.string();
  StateFunction f;
  f.name = name;
  const auto component = [&](std::string_view prefix, StateFunction::Kind kind) {
    if (name.size() != prefix.size() + 1 || name.compare(0, prefix.size(), prefix) != 0) return false;
    const char c = name.back();
    if (c < '1' || c > '3') return false;
    f.kind = kind;
    f.i = c - '1';
    return true;
  };
  bool known = component("omega", StateFunction::Kind::omega) || component("pi", StateFunction::Kind::pi) ||
               component("gamma", StateFunction::Kind::gamma);
  if (!known && name.size() == 3 && name[0] == 'R' && name[1] >= '1' && name[1] <= '3' && name[2] >= '1' &&
      name[2] <= '3') {
    f.kind = StateFunction::Kind::R;
    f.i = name[1] - '1';
    f.j = name[2] - '1';
    known = true;
  }
  if (!known && name == "height") {
    f.kind = StateFunction::Kind::height;
    known = true;
  }
  if (!known && name == "tilt") {
    f.kind = StateFunction::Kind::tilt;
    known = true;
  }
  if (!known) {
    std::vector<std::string> all = {"height", "tilt"};
    for (const char* v : {"omega", "pi", "gamma"})
      for (const char i : {'1', '2', '3'}) all.push_back(v + std::string(1, i));
    for (const char i : {'1', '2', '3'})
      for (const char j : {'1', '2', '3'}) all.push_back(std::string("R") + i + j);
    node.fail("unknown state function " + quoted_input(name) +
              did_you_mean(name, std::vector<std::string_view>(all.begin(), all.end())) +
              " (known: R11 ... R33, omega1 ... omega3, pi1 ... pi3, and for tops gamma1 ... gamma3, height, tilt)");
  }
  if (f.needs_gravity() && !body.has_gravity)
    node.fail(name + " needs a top (a problem with gravity k and centre of mass z0: heavy_top, lagrange_top, "
                     "kovalevskaya_top, lagrange_top_euler_angles), not " + problem_type);
  return f;
}

MemberObserver::MemberObserver(const ObserveSpec& spec, const BodyData& body, std::string crossing_prefix)
    : spec_(spec), body_(body), prefix_(std::move(crossing_prefix)) {
  min_.assign(spec.extrema.size(), std::numeric_limits<double>::infinity());
  max_.assign(spec.extrema.size(), -std::numeric_limits<double>::infinity());
}

void MemberObserver::start(const State<double>& x0, StepAccess& access) {
  for (std::size_t i = 0; i < spec_.extrema.size(); ++i) min_[i] = max_[i] = spec_.extrema[i](x0, body_);
  if (spec_.section) g_prev_ = spec_.section->f(x0, body_) - spec_.section->value;
  if (spec_.lyapunov) {
    const LyapunovSpec& l = *spec_.lyapunov;
    const double u = l.d0 / std::sqrt(6.0);
    State<double> shadow;
    shadow.R = x0.R * so3::exp(Vec3<double>(u, u, u));
    shadow.Omega = x0.Omega + Vec3<double>(u, u, u) / l.omega_scale;
    access.shadow_set(shadow);
    lyap_active_ = access.shadow_ok();
    lyap_sum_ = lyap_t_ = lyap_last_ = 0;
  }
}

void MemberObserver::step(double t_prev, double t, const State<double>& x, StepAccess& access) {
  for (std::size_t i = 0; i < spec_.extrema.size(); ++i) {
    const double v = spec_.extrema[i](x, body_);
    min_[i] = std::min(min_[i], v);
    max_[i] = std::max(max_[i], v);
  }
  if (spec_.section) crossing(t_prev, t, x, access);
  if (lyap_active_) {
    if (!access.shadow_ok())
      lyap_active_ = false;  // a step of the shadow failed: the estimate covers [0, lyap_t_]
    else if (t - lyap_last_ >= spec_.lyapunov->interval * (1 - 1e-12))
      renormalise(t, x, access, true);
  }
}

void MemberObserver::finish(double t, const State<double>& x, StepAccess& access) {
  if (lyap_active_ && access.shadow_ok() && t > lyap_last_) renormalise(t, x, access, false);
  lyap_active_ = false;
}

// Measures the distance to the shadow: ln(d/d0) added over [lyap_last_, t]; with reset, the shadow goes back to
// distance d0 along the same direction.
void MemberObserver::renormalise(double t, const State<double>& x, StepAccess& access, bool reset) {
  const LyapunovSpec& l = *spec_.lyapunov;
  const State<double> s = access.shadow_state();
  const Vec3<double> dR = so3::log(Mat3<double>(x.R.transpose() * s.R));
  const Vec3<double> dW = l.omega_scale * (s.Omega - x.Omega);
  const double d = std::sqrt(dR.squaredNorm() + dW.squaredNorm());
  if (!(d > 0) || !std::isfinite(d)) {  // no direction left to follow: the estimate ends at lyap_t_
    lyap_active_ = false;
    return;
  }
  lyap_sum_ += std::log(d / l.d0);
  lyap_t_ = lyap_last_ = t;
  if (!reset) return;
  const double q = l.d0 / d;
  State<double> shadow;
  shadow.R = x.R * so3::exp(Vec3<double>(q * dR));
  shadow.Omega = x.Omega + (q / l.omega_scale) * dW;
  access.shadow_set(shadow);
}

// A crossing of the section in (t_prev, t]: located by side-steps from the state at t_prev (see the header).
void MemberObserver::crossing(double t_prev, double t, const State<double>& x, StepAccess& access) {
  const SectionSpec& s = *spec_.section;
  const double f1 = s.f(x, body_);
  const double g0 = g_prev_, g1 = f1 - s.value;
  g_prev_ = g1;
  const bool up = g0 < 0 && g1 >= 0, down = g0 > 0 && g1 <= 0;
  if (!((s.direction >= 0 && up) || (s.direction <= 0 && down))) return;
  if (s.max_crossings > 0 && crossings_written_ >= s.max_crossings) return;
  double tc = t;
  State<double> xc = x;
  if (g1 != 0) {
    // Illinois on τ ∈ [0, h]: g(0) = g0 and g(h) = g1 have opposite signs.
    const double h = access.step_size();
    constexpr double eps = std::numeric_limits<double>::epsilon();
    const double noise = 2 * eps * std::max({std::abs(g0 + s.value), std::abs(f1), std::abs(s.value)});
    double a = 0, fa = g0, b = h, fb = g1, best = std::abs(g1);
    int side = 0;
    for (int iteration = 0; iteration < 60 && best > noise && b - a > 4 * eps * h; ++iteration) {
      double c = b - fb * (b - a) / (fb - fa);
      if (!(c > a && c < b)) c = 0.5 * (a + b);
      State<double> xt;
      if (!access.side_step(c, xt)) break;  // keep the best so far
      const double fc = s.f(xt, body_) - s.value;
      if (std::abs(fc) < best) {
        best = std::abs(fc);
        tc = t_prev + c;
        xc = xt;
      }
      if (fc == 0) break;
      if ((fc > 0) == (fb > 0)) {
        b = c;
        fb = fc;
        if (side == -1) fa *= 0.5;
        side = -1;
      } else {
        a = c;
        fa = fc;
        if (side == +1) fb *= 0.5;
        side = +1;
      }
    }
  }
  ++crossings_written_;
  crossings_ += prefix_;
  crossings_ += std::to_string(crossings_written_ - 1);
  append_csv_number(crossings_, tc);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) append_csv_number(crossings_, xc.R(i, j));
  for (int i = 0; i < 3; ++i) append_csv_number(crossings_, xc.Omega(i));
  crossings_ += '\n';
}

void MemberObserver::append_extrema(std::string& row) const {
  for (std::size_t i = 0; i < spec_.extrema.size(); ++i) {
    append_csv_number(row, min_[i]);
    append_csv_number(row, max_[i]);
  }
}

void MemberObserver::append_lyapunov(std::string& row) const {
  append_csv_number(row, lyap_t_ > 0 ? lyap_sum_ / lyap_t_ : 0.0);
  append_csv_number(row, lyap_t_);
}

void MemberObserver::append_crossing_count(std::string& row) const {
  row += ',';
  row += std::to_string(crossings_written_);
}

}  // namespace lgi::app
