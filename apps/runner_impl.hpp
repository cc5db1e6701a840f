// lgi/apps/runner_impl.hpp — the per-problem part of a run: the scene's method as an lgi::Integrator (every method
// that applies to the problem; projection a run-time switch of Projected), the row columns and the problem's hooks. Included by
// problem_model.hpp: a problem's registration (apps/problems/ID.cpp, or a plugin) instantiates make_problem_runner.
#pragma once

#include "runner_detail.hpp"

#include <lgi/core/engine.hpp>
#include <lgi/core/invariants.hpp>
#include <lgi/integrators/adaptive.hpp>
#include <lgi/integrators/projection.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

namespace lgi::app {
namespace runner_detail {

// The methods a problem type compiles for itself: every method that applies to P, less, for a problem type whose
// motion is a heavy top's (P::as_heavy_top(): the Kovalevskaya and the Lagrange top), those the heavy top takes —
// they run the heavy top's instantiation (integrator_of). What remains is the methods only P takes (lagrange_split
// and its compositions: axisymmetric problems only).
template <template <class> class M, class P>
inline constexpr bool own_method_v = [] {
  if constexpr (requires(const P& p) { p.as_heavy_top(); })
    return method_applies_v<M, P> && !method_applies_v<M, HeavyTop<double>>;
  else
    return method_applies_v<M, P>;
}();

// The scene's method on problem P among P's own methods (own_method_v): Method<P>, or Projected<Method<P>> with the
// projection switched by the scene where the method takes one; null when the scene's method is none of them.
template <class P, template <class> class... Ms>
std::unique_ptr<Integrator> integrator_for(const P& problem, const Scene& scene, MethodList<Ms...>) {
  std::unique_ptr<Integrator> engine;
  const auto try_method = [&]<template <class> class M>() {
    if constexpr (own_method_v<M, P>) {
      if (!engine && M<P>::traits.name == scene.method->traits.name) {
        if constexpr (ProjectableStepper<M<P>>)  // one instantiation, the projection switched by the scene
          engine = make_integrator<Projected<M<P>>>(problem, scene.options, scene.options.projection);
        else if (scene.options.projection)  // the scene accepts "projection" only where traits list it
          throw std::logic_error("lgi: projection asked of a method that does not take it");
        else
          engine = make_integrator<M<P>>(problem, scene.options);
      }
    }
  };
  (try_method.template operator()<Ms>(), ...);
  return engine;
}

// The scene's method on P. A problem type whose motion is a heavy top's, operation for operation (P::as_heavy_top():
// the same equations with the same floating-point operations, up to the sign of zero terms), runs the heavy top's
// instantiation — the one heavy_top.cpp defines and the other problems' files declare extern — for every method
// the heavy top takes, and its own (integrator_for) for the rest; the rows are P's.
template <class P>
std::unique_ptr<Integrator> integrator_of(const P& problem, const Scene& scene) {
  std::unique_ptr<Integrator> engine = integrator_for(problem, scene, Methods{});
  if constexpr (requires { problem.as_heavy_top(); })
    if (!engine) return integrator_of(problem.as_heavy_top(), scene);
  if (!engine) throw std::logic_error("lgi: method registry out of sync");
  return engine;
}

// The columns of a row (csv_header) of a problem on SO(3) at (t, x): t, R row by row, Ω, the energy, ‖RᵀR − I‖_F
// and the problem's invariants.
template <class P>
void append_state_columns(const P& problem, double t, const State<double>& x, std::vector<double>& out) {
  out.push_back(t);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out.push_back(x.R(r, c));
  for (int i = 0; i < 3; ++i) out.push_back(x.Omega(i));
  out.push_back(energy_at(problem, t, x));
  out.push_back(so3::orthogonality_error(x.R));
  for (const double v : invariants_at(problem, t, x)) out.push_back(v);
}

// A problem on SO(3): its rows are append_state_columns'.
template <class P>
class ProblemRunnerOf final : public ProblemRunner {
 public:
  explicit ProblemRunnerOf(const P& problem) : problem_(problem) {}
  std::unique_ptr<Integrator> integrator(const Scene& scene) const override { return integrator_of(problem_, scene); }
  void columns(double t, const Integrator& engine, Slot s, std::vector<double>& out) const override {
    state_columns(t, engine.state(s), out);
  }
  void initial_columns(const Scene& scene, double t, std::vector<double>& out) const override {
    state_columns(t, scene.initial, out);
  }

 private:
  void state_columns(double t, const State<double>& x, std::vector<double>& out) const {
    append_state_columns(problem_, t, x, out);
  }
  P problem_;
};

// The seed paper's Euler-angle top (problems/euler_angle_top.hpp): its state (φ, θ, ψ, φ', θ', m_ψ, Φ, Ψ) is not on SO(3):
// the scene's RKMK tableau runs as plain Runge–Kutta on the angles (integrators/euclidean_rk.hpp,
// apps/problems/euler_angle_methods.hpp), with the library's domain-checked step (CheckedEuclideanStep: a step that takes sin θ
// below min_sin_theta fails, the state untouched, and says so) and the problem's map to (R, Ω). Its columns are the
// standard ones (R by (6.3), Ω from the angle rates, the total energy) and the problem's own, from the angles. A
// step that leaves the domain ends the run (status `stopped`, a warning with the time on stderr, the last admissible
// state kept); an initial attitude already outside it runs no step at all.
template <const auto& Tableau>
class EulerAngleSteps : public CheckedEuclideanStep<EuclideanRk<Tableau, EulerAngleTop<double>>> {
 public:
  using Rk = EuclideanRk<Tableau, EulerAngleTop<double>>;
  using Internal = typename Rk::Vector;
  static constexpr MethodTraits traits = Rk::traits;
  EulerAngleSteps(const EulerAngleTop<double>& problem, const StepperOptions&)
      : CheckedEuclideanStep<Rk>(rk_), rk_(problem), problem_(problem) {}
  EulerAngleSteps(const EulerAngleSteps& other)
      : CheckedEuclideanStep<Rk>(rk_), rk_(other.rk_), problem_(other.problem_) {}
  EulerAngleSteps& operator=(const EulerAngleSteps&) = delete;
  Internal to_internal(const State<double>& x, double) const { return problem_.from_state(x); }
  State<double> to_state(const Internal& y) const { return problem_.to_state(y); }

 private:
  Rk rk_;
  EulerAngleTop<double> problem_;
};

class EulerAngleRunner final : public ProblemRunner {
 public:
  explicit EulerAngleRunner(const EulerAngleTop<double>& problem) : problem_(problem) {}
  std::unique_ptr<Integrator> integrator(const Scene& scene) const override {
    std::unique_ptr<Integrator> engine;
    const auto try_method = [&]<template <class> class M>() {
      if constexpr (method_applies_v<M, EulerAngleTop<double>>) {
        using Tab = rkmk_tableau<M<FreeBody<double>>>;
        if (!engine && Tab::tableau.name == scene.method->traits.name)
          engine = make_integrator<EulerAngleSteps<Tab::tableau>>(problem_, scene.options);
      }
    };
    [&]<template <class> class... Ms>(MethodList<Ms...>) { (try_method.template operator()<Ms>(), ...); }(Methods{});
    if (!engine) throw std::logic_error("lgi: method registry out of sync");
    return engine;
  }
  void columns(double t, const Integrator& engine, Slot s, std::vector<double>& out) const override {
    EulerAngleTop<double>::Vector y;
    engine.save(s, std::span<double>(y.data(), static_cast<std::size_t>(y.size())));
    angle_columns(t, y, out);
  }
  void initial_columns(const Scene& scene, double t, std::vector<double>& out) const override {
    angle_columns(t, problem_.from_state(scene.initial), out);
  }
  bool start(const Scene& scene, RunReport& report) const override {
    const EulerAngleTop<double>::Vector y0 = problem_.from_state(scene.initial);
    if (problem_.admissible(y0)) return true;
    report.summary.status = RunStatus::stopped;
    report.stop_reason = StopReason::left_domain;
    std::fprintf(stderr,
                 "lgi: warning: %s: at t = 0 sin(theta) = %.3g < min_sin_theta = %s: the initial attitude is at the Euler "
                 "angles' coordinate singularity (symmetry axis near the laboratory e3); the run stops at t = 0 (the "
                 "same motion runs on SO(3) as problem.type heavy_top, or lower /problem/min_sin_theta)\n",
                 scene.file.c_str(), std::sin(y0[1]), format_number(problem_.min_sin_theta).c_str());
    report.final_state = scene.initial;
    // The angle rates (hence the angle-form energy) are undefined at sin θ = 0: the energy of the same state on
    // SO(3) instead.
    report.energy_initial = report.energy_final = energy(problem_.heavy_top(), scene.initial);
    angle_columns(0.0, y0, report.final_columns);
    return false;
  }
  void finish(const Scene& scene, const Integrator& engine, RunReport& report) const override {
    report.final_state = engine.state(Slot::current);  // through the angles, as every row
    double t_outside = 0;
    if (engine.left_domain(t_outside) && report.summary.status == RunStatus::step_failed) {
      // t_outside: the time of the rejected state (sin θ < min_sin_theta); the last admissible one is kept.
      report.summary.status = RunStatus::stopped;
      report.summary.step_status = StepStatus::ok;
      report.stop_reason = StopReason::left_domain;
      EulerAngleTop<double>::Vector y;
      engine.save(Slot::current, std::span<double>(y.data(), static_cast<std::size_t>(y.size())));
      std::fprintf(stderr,
                   "lgi: warning: %s: at t = %s sin(theta) falls below min_sin_theta = %s: the Euler angles are near "
                   "their coordinate singularity (symmetry axis near the laboratory e3); the run stops at t = %s, the "
                   "last admissible state (sin(theta) = %.3g there; the same motion runs on SO(3) as problem.type "
                   "heavy_top, or lower /problem/min_sin_theta)\n",
                   scene.file.c_str(), format_number(t_outside).c_str(), format_number(problem_.min_sin_theta).c_str(),
                   format_number(report.summary.t).c_str(), std::sin(y[1]));
    }
  }

 private:
  void angle_columns(double t, const EulerAngleTop<double>::Vector& y, std::vector<double>& out) const {
    const State<double> x = problem_.to_state(y);
    out.push_back(t);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) out.push_back(x.R(r, c));
    for (int i = 0; i < 3; ++i) out.push_back(x.Omega(i));
    out.push_back(problem_.energy(y));
    out.push_back(so3::orthogonality_error(x.R));
    for (const double v : problem_.invariants(y)) out.push_back(v);
  }
  EulerAngleTop<double> problem_;
};

}  // namespace runner_detail

namespace runner_detail {
template <class P>
std::unique_ptr<ProblemRunner> make_problem_runner(const P& problem) {
  if constexpr (std::is_same_v<P, EulerAngleTop<double>>)
    return std::make_unique<EulerAngleRunner>(problem);
  else
    return std::make_unique<ProblemRunnerOf<P>>(problem);
}
}  // namespace runner_detail

}  // namespace lgi::app
