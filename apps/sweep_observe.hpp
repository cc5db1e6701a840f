// lgi/apps/sweep_observe.hpp — what `lgi sweep` records during a member's run (docs/sweep.md, "Records taken
// during the run"): extrema of state functions, Poincaré crossings of a section, a largest-Lyapunov-exponent
// estimate. Each is computed only when the sweep file records it; a member records them through the runner's
// in-run observation (runner.hpp, RunObserver), which leaves the member's trajectory bit for bit as it is.
//
// State functions (StateFunction), by name: R11 … R33 (entries of R), omega1 … omega3 (Ω), pi1 … pi3 (JΩ, the
// body angular momentum), and for tops (problems with gravity: k and z0) gamma1 … gamma3 (Γ = Rᵀk, the upward
// vertical seen from the body), height (k·R z0, the cosine of the tilt) and tilt (the angle between the centre
// of mass axis R z0 and k, in [0, π], as atan2(|k × R z0|, k·R z0)).
//
// Extrema: the least and greatest value of each function over the states of the run — t = 0, every step
// (fixed steps: every grid step and the final side-step; adaptive runs: every accepted step). Sampled at the
// steps: between steps the function may go beyond them by up to ⅛ h² max|f''|.
//
// Crossings: the section f(x) = value, in a direction (increasing: f goes from below value to value or above;
// decreasing: the reverse; both). A step (t_n, t_{n+1}] whose end values straddle the section contains a
// crossing, located by side-steps from the state at t_n: τ ∈ (0, h] with f(step(x_n, τ)) = value, by the Illinois
// variant of regula falsi on τ, to |f − value| at the rounding level of f (or the bracket down to a few ulps of
// τ). The crossing's state is the method's own state for a step τ from x_n — as accurate as the run itself, the
// time to the rounding level. Two crossings inside one step cancel and are missed: the step must resolve f.
// Fixed-step runs only.
//
// Lyapunov: Benettin's two-trajectory estimate of the largest exponent. A shadow trajectory starts at
// x0 ⊕ d0·u (u = (1, 1, 1, 1, 1, 1)/√6 in the coordinates below) and is stepped with the member's method and steps;
// every `interval` of time (at the first step at or past it) the distance d between the two is measured, ln(d/d0)
// added up, and the shadow moved back to distance d0 along the same direction; at the end the last partial
// interval is measured too. Distance on SO(3) × R³: δ = (log(Rᵀ R_s), s·(Ω_s − Ω)), d = |δ|, with s =
// omega_scale (a time: Ω's weight against the angle); x ⊕ δ = (R exp(δ_R), Ω + δ_Ω / s). The estimate is
// Σ ln(d_k/d0) / T over the time T it covers (lyapunov_t: the run's end, or the last renormalisation before a
// step of the shadow failed). Fixed-step runs only. Limits: finite T (a regular orbit gives ≈ ln(T)/T, not 0);
// d0 must be small enough to stay linear over an interval (d0 e^{λ·interval} ≪ 1) and large enough above the
// rounding of the states (≫ 1e-16 |x|).
#pragma once

#include "json_reader.hpp"
#include "runner.hpp"

#include <lgi/core/scalar.hpp>
#include <lgi/core/state.hpp>

#include <charconv>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace lgi::app {

// Appends ",x" as the runner's RowWriter writes x: std::to_chars, general, 17 significant digits.
inline void append_csv_number(std::string& out, double x) {
  char buf[40];
  buf[0] = ',';
  const auto r = std::to_chars(buf + 1, buf + sizeof buf, x, std::chars_format::general, 17);
  out.append(buf, r.ptr);
}

// What a member's problem gives the state functions (registry.hpp, BodyData).
BodyData body_data(const Scene& scene);

struct StateFunction {
  enum class Kind : std::uint8_t { R, omega, pi, gamma, height, tilt };
  std::string name;
  Kind kind = Kind::R;
  int i = 0, j = 0;  // R: row and column; omega, pi, gamma: the component
  bool needs_gravity() const { return kind == Kind::gamma || kind == Kind::height || kind == Kind::tilt; }
  double operator()(const State<double>& x, const BodyData& body) const;
};
// The function named at `node` (a string); needs_gravity() functions on a problem without gravity: an error
// naming the problem type.
StateFunction read_state_function(const Node& node, const BodyData& body, const std::string& problem_type);

struct SectionSpec {
  StateFunction f;
  double value = 0;
  int direction = 1;  // +1 increasing, −1 decreasing, 0 both
  std::int64_t max_crossings = 0;  // 0: no limit; else the member's first max_crossings are written
};

struct LyapunovSpec {
  double d0 = 1e-8;
  double interval = 1.0;
  double omega_scale = 1.0;
};

struct ObserveSpec {
  std::vector<StateFunction> extrema;
  std::optional<SectionSpec> section;
  std::optional<LyapunovSpec> lyapunov;
  bool any() const { return !extrema.empty() || section || lyapunov; }
};

// The observer of one member's run: extrema, crossings (rows appended to a string), Lyapunov sums.
class MemberObserver final : public RunObserver {
 public:
  // crossing_prefix: the start of each crossing row ("member,").
  MemberObserver(const ObserveSpec& spec, const BodyData& body, std::string crossing_prefix);

  void start(const State<double>& x0, StepAccess& access) override;
  void step(double t_prev, double t, const State<double>& x, StepAccess& access) override;
  void finish(double t, const State<double>& x, StepAccess& access) override;

  // The columns of each group, each preceded by a comma.
  void append_extrema(std::string& row) const;
  void append_lyapunov(std::string& row) const;
  void append_crossing_count(std::string& row) const;
  // The crossing rows (each ending in a newline).
  std::string& crossing_rows() { return crossings_; }

 private:
  void crossing(double t_prev, double t, const State<double>& x, StepAccess& access);
  void renormalise(double t, const State<double>& x, StepAccess& access, bool reset);

  const ObserveSpec& spec_;
  BodyData body_;
  std::string prefix_;
  std::vector<double> min_, max_;
  // crossings
  double g_prev_ = 0;  // f − value at the previous state
  std::int64_t crossings_written_ = 0;
  std::string crossings_;
  // Lyapunov
  bool lyap_active_ = false;
  double lyap_sum_ = 0, lyap_t_ = 0, lyap_last_ = 0;
};

}  // namespace lgi::app
