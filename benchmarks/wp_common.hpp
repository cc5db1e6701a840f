// benchmarks/wp_common.hpp — shared pieces of the work-precision benchmark (work_precision.cpp): the
// cases, the configured runs ("trials") of lgi's methods and of the peer libraries, the error measure.
// Not part of the library.
//
// Every solver integrates the same body,
//     J Ω' = (JΩ) × Ω + b Γ × z0,   Γ = Rᵀk,   R' = R hat(Ω)      (seed paper (s4)–(s5); b = 0: free body),
// lgi's methods on SO(3) × R³, the peers (Boost.Odeint, GSL, SUNDIALS) on the unit quaternion q of R and
// the body momentum Π = JΩ (7 entries, right-hand side in wp_peers.cpp), the reference on the 12 entries
// of R and Ω in long double (wp_reference.cpp).
//
// Error of a run at the evaluation time T (the case's t_end unless the chaos guard shortened it):
//     err = |log(R_refᵀ R)| + |Ω − Ω_ref|          (rotation angle between the attitudes + Euclidean norm)
// the peers' q normalised before R is formed (their |q| drift is reported separately on long runs).
#pragma once

#include <lgi/core/state.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>
#include <lgi/problems/lagrange_top.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace wp {

using Mat3 = lgi::Mat3<double>;
using Vec3 = lgi::Vec3<double>;
using State = lgi::State<double>;

enum class Kind { free_body, heavy_top, lagrange_top };

// The body every solver integrates: inertia J about the fixed point (or centre of mass), b = 0 for a free
// body, k the laboratory vertical, z0 the body vector to the centre of mass.
struct Body {
  Mat3 J = Mat3::Identity();
  double b = 0;
  Vec3 k = Vec3::UnitZ();
  Vec3 z0 = Vec3::UnitZ();
  bool torque() const { return b != 0; }
};

// One benchmark case, read from a scene file (scenes/bench/*.json) with apps/scene.hpp.
struct Case {
  std::string name;  // the file's stem
  std::string file;
  std::string problem_type;  // the scene's problem.type
  Kind kind = Kind::free_body;
  Body body;
  lgi::FreeBody<double> free_body;        // kind free_body
  lgi::HeavyTop<double> heavy_top;        // kind heavy_top, and lagrange_top as a heavy top with z0 = e3
  lgi::LagrangeTop<double> lagrange_top;  // kind lagrange_top
  State x0;
  double t_end = 0;
};

// A state observed during a run: t, the state (peers: q normalised), ‖RᵀR − I‖_F of the solver's own
// attitude (peers: of R(q) formed from the unnormalised q, i.e. √3 ||q|⁴ − 1|).
struct Sample {
  double t = 0;
  State x;
  double orthogonality = 0;
};

// A configured run. Constructing it (solver allocation, stepper construction) and reset() (back to the
// initial state, solver re-initialisation) are not timed; run() is. run() integrates from 0 through every
// output time and fills samples() (the initial state first, then one Sample per output time).
class Trial {
 public:
  virtual ~Trial() = default;
  virtual void reset() = 0;
  virtual bool run() = 0;  // false: the solver failed (its samples stop there)
  virtual std::int64_t steps() const = 0;  // steps of the last run (adaptive: accepted steps)
  const std::vector<Sample>& samples() const { return samples_; }

 protected:
  std::vector<Sample> samples_;  // reserved at construction: no allocation while running
};

// A method as the benchmark sees it. make(case, output times, param): param is the number of steps N over
// [0, times.back()] (fixed steps: h = times.back()/N) or the tolerance (adaptive: rtol = atol = param).
struct Method {
  std::string name;
  std::string library;  // "lgi", "boost_odeint", "gsl", "sundials"
  std::string description;
  int order = 0;  // on this case's problem (0: the exact solution, or a variable order)
  bool exact_solution = false;  // lgi's `exact`: no truncation error
  bool adaptive = false;
  bool symplectic = false;
  bool projected = false;  // lgi: the invariant projection after every step (integrators/projection.hpp)
  std::function<std::unique_ptr<Trial>(const Case&, std::span<const double> times, double param)> make;
};

// lgi's methods that apply to the case, through the engine of `lgi run` (wp_lgi.cpp).
std::vector<Method> lgi_methods(const Case& c);
// The peers compiled in (wp_peers.cpp), and their versions ("boost_odeint": "1.74", ...).
std::vector<Method> peer_methods(const Case& c);
std::vector<std::pair<std::string, std::string>> peer_versions();
// Largest relative difference between the peers' analytic Jacobian (GSL rk4imp) and central differences.
double jacobian_check(const Case& c);
// Seconds per call of the peers' right-hand side, one value per batch of `calls` calls (wp_peers.cpp).
std::vector<double> peer_rhs_seconds(const Case& c, int batches, long calls);

// The reference at the evaluation time (wp_reference.cpp). Free bodies: the exact solution
// (problems/free_body_exact.hpp, long double inside), cross-checked against the integration below. Tops: an
// integration of the 12 entries of R and Ω in long double by Boost.Odeint's runge_kutta_fehlberg78 with N
// and 2N fixed steps (h·ω ≈ 0.005 and 0.0025, ω a bound on |Ω|); the 2N result is the reference, the
// distance between the two its error bar. Chaos guard: a second reference from Ω0·(1 + `perturbation`) gives
// the amplification A(t) = divergence(t)/|δΩ0| of an early error; a double-precision solver's round-off alone
// then reaches ≈ A·1e-16 at t, so pointwise errors are evaluated at T = the last of 20 equally spaced times up
// to which A ≤ `max_amplification` = 1e4 (round-off ≤ 1e-12, 100× below the smallest target 1e-10); T =
// t_end when that holds throughout.
struct Reference {
  std::string kind;  // "exact" or "integration"
  std::string method;
  double t_eval = 0;
  State x;
  double error_bar = 0;
  double cross_check = -1;  // exact cases: |exact − integration| at t_eval (−1: not computed)
  std::int64_t steps_coarse = 0, steps_fine = 0;
  double perturbation = 1e-12, max_amplification = 1e4;
  std::vector<double> guard_times, divergence;
  double amplification = 0;  // divergence / perturbation at t_end
  std::string scene_hash;    // FNV-1a of the scene file the reference belongs to
  bool from_cache = false;
};
// reduced: steps / 8 (smoke runs without a cached reference).
Reference compute_reference(const Case& c, bool reduced);

// Initial step of adaptive runs, the same for every library: 0.1/|Ω0| (0.1 rad of rotation).
double initial_step(const Case& c);

// err = |log(R_aᵀ R_b)| + |Ω_a − Ω_b|.
double state_error(const State& a, const State& b);
// ‖RᵀR − I‖_F
double orthogonality(const Mat3& R);

}  // namespace wp
