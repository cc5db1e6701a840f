// lgi/apps/runner_impl.hpp — the runner's templates: a scene's stepper through the drivers, CSV rows at the
// output times, the run report. Included only by the runner parts (runner_part.cpp.in), each of which
// instantiates run_problem for one problem; see runner_detail.hpp for why.
#pragma once

#include "runner_detail.hpp"

#include <lgi/core/invariants.hpp>
#include <lgi/integrators/adaptive.hpp>
#include <lgi/integrators/projection.hpp>

#include <cmath>
#include <span>
#include <stdexcept>
#include <vector>

namespace lgi::app {
namespace runner_detail {

// An adaptive run (the scene gave rtol and atol): output times from the dense output, output.every N as every
// N accepted steps, dt the initial step. The summary's steps are the accepted ones.
template <class S, class Observer>
IntegrationSummary run_adaptive(S& stepper, State<double>& x, const Scene& scene, Observer& observe,
                                const RunOptions& options) {
  std::vector<double> times = scene.output_times;
  if (times.empty() || times.back() < scene.t_end) times.push_back(scene.t_end);
  AdaptiveOptions adaptive;
  if (scene.output_times.empty() && scene.output_every > 0) adaptive.every = scene.output_every;
  Progress monitor{false, 0, options.stop};  // interruption only: there is no step total to show progress against
  const AdaptiveSummary a =
      integrate_adaptive(stepper, x, 0.0, scene.dt, std::span<const double>(times), observe, adaptive, monitor);
  IntegrationSummary summary;
  summary.status = a.status;
  summary.step_status = a.step_status;
  summary.steps = a.accepted;
  summary.t = a.t;
  return summary;
}

// The scene's stepper S: Method<P>, or Projected<Method<P>> when the scene asks for projection.
template <class S, class P>
RunReport run_stepper(S& stepper, const P& problem, const Scene& scene, const RunOptions& options) {
  RunReport report;
  report.expected_steps = static_cast<std::int64_t>(std::ceil(scene.t_end / scene.dt - 1e-9));
  RowWriter row(options.csv);
  if (options.csv) {
    const std::string h = header_for<P>() + "\n";
    if (std::fwrite(h.data(), 1, h.size(), options.csv) != h.size()) report.write_failed = true;
  }
  auto observe = [&](double t, const State<double>& x) {
    if (!options.csv) return;
    row.add(t);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) row.add(x.R(r, c));
    for (int i = 0; i < 3; ++i) row.add(x.Omega(i));
    row.add(energy_at(problem, t, x));
    row.add(so3::orthogonality_error(x.R));
    for (const double v : invariants_at(problem, t, x)) row.add(v);
    row.end_row();
  };
  Progress progress{options.progress, report.expected_steps, options.stop};

  State<double> x = scene.initial;
  report.energy_initial = energy_at(problem, 0.0, x);
  const auto inv0 = invariants_at(problem, 0.0, x);
  const auto start = Clock::now();
  if (scene.options.rtol > 0) {
    if constexpr (AdaptiveStepper<S>)
      report.summary = run_adaptive(stepper, x, scene, observe, options);
    else
      throw std::logic_error("lgi: rtol given to a method without an embedded pair");
  } else if (!scene.output_times.empty()) {
    std::vector<double> times = scene.output_times;
    if (times.back() < scene.t_end) times.push_back(scene.t_end);
    report.summary = integrate_times(stepper, x, 0.0, scene.dt, std::span<const double>(times), observe, progress);
  } else {
    const std::int64_t every = scene.output_every > 0 ? scene.output_every : std::int64_t{1} << 62;
    report.summary = integrate_every(stepper, x, 0.0, scene.dt, scene.t_end, every, observe, progress);
  }
  report.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  progress.finish();

  report.final_state = x;
  report.energy_final = energy_at(problem, report.summary.t, x);
  const auto inv1 = invariants_at(problem, report.summary.t, x);
  for (std::size_t i = 0; i < inv0.size(); ++i)
    report.invariants.push_back({std::string(P::invariant_names[i]), inv0[i], inv1[i]});
  if constexpr (requires { stepper.newton_iterations(); }) report.newton_iterations = stepper.newton_iterations();
  report.write_failed = report.write_failed || row.failed();
  return report;
}

template <template <class> class Method, class P>
RunReport run_with(const P& problem, const Scene& scene, const RunOptions& options) {
  if (scene.options.projection) {
    if constexpr (ProjectableStepper<Method<P>>) {  // the scene accepts "projection" only where traits list it
      Projected<Method<P>> stepper(problem, scene.options);
      return run_stepper(stepper, problem, scene, options);
    } else {
      throw std::logic_error("lgi: projection asked of a method that does not take it");
    }
  }
  Method<P> stepper(problem, scene.options);
  return run_stepper(stepper, problem, scene, options);
}

template <class P, template <class> class... Ms>
RunReport dispatch(const P& problem, const Scene& scene, const RunOptions& options, MethodList<Ms...>) {
  RunReport report;
  bool found = false;
  const auto try_method = [&]<template <class> class M>() {
    if constexpr (method_applies_v<M, P>) {
      if (!found && M<P>::traits.name == scene.method->traits.name) {
        report = run_with<M>(problem, scene, options);
        found = true;
      }
    }
  };
  (try_method.template operator()<Ms>(), ...);
  if (!found) throw std::logic_error("lgi: method registry out of sync");
  return report;
}

// The seed paper's Euler-angle top (problems/euler_angle_top.hpp): its state (φ, θ, ψ, φ', θ', m_ψ) is not
// on SO(3), so it runs on its own path — the scene's RKMK tableau as plain Runge–Kutta on the angles
// (integrators/euclidean_rk.hpp, apps/problems_paper.hpp) — with the standard columns (R by (6.3), Ω from
// the angle rates, the total energy) and the problem's own. A step that takes sin θ below min_sin_theta
// ends the run (status `stopped`, a warning with the time on stderr, the last admissible state kept).
template <const auto& Tableau>
RunReport run_euler_angles(const EulerAngleTop<double>& problem, const Scene& scene, const RunOptions& options) {
  using Vector = EulerAngleTop<double>::Vector;
  RunReport report;
  report.expected_steps = static_cast<std::int64_t>(std::ceil(scene.t_end / scene.dt - 1e-9));
  const EuclideanRk<Tableau, EulerAngleTop<double>> stepper(problem);
  RowWriter row(options.csv);
  if (options.csv) {
    const std::string h = header_for<EulerAngleTop<double>>() + "\n";
    if (std::fwrite(h.data(), 1, h.size(), options.csv) != h.size()) report.write_failed = true;
  }
  auto observe = [&](double t, const Vector& y) {
    if (!options.csv) return;
    const State<double> x = problem.to_state(y);
    row.add(t);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) row.add(x.R(r, c));
    for (int i = 0; i < 3; ++i) row.add(x.Omega(i));
    row.add(problem.energy(y));
    row.add(so3::orthogonality_error(x.R));
    for (const double v : problem.invariants(y)) row.add(v);
    row.end_row();
  };
  // t: the time of the rejected state (sin θ < min_sin_theta); t_kept and sin_theta: the last admissible one.
  const auto warn = [&](double t, double sin_theta, double t_kept) {
    std::fprintf(stderr,
                 "lgi: warning: %s: at t = %s sin(theta) falls below min_sin_theta = %s: the Euler angles are near "
                 "their coordinate singularity (symmetry axis near the laboratory e3); the run stops at t = %s, the "
                 "last admissible state (sin(theta) = %.3g there; the same motion runs on SO(3) as problem.type "
                 "heavy_top, or lower /problem/min_sin_theta)\n",
                 scene.file.c_str(), format_number(t).c_str(), format_number(problem.min_sin_theta).c_str(),
                 format_number(t_kept).c_str(), sin_theta);
  };
  constexpr std::array<int, 2> integrals{0, 1};  // momentum_k, momentum_psi (the integrals among the columns)
  Vector y = problem.from_state(scene.initial);
  report.energy_initial = problem.energy(y);
  const auto inv0 = problem.invariants(y);
  if (!problem.admissible(y)) {  // already at t = 0: no admissible state at all
    report.summary.status = RunStatus::stopped;
    std::fprintf(stderr,
                 "lgi: warning: %s: at t = 0 sin(theta) = %.3g < min_sin_theta = %s: the initial attitude is at the Euler "
                 "angles' coordinate singularity (symmetry axis near the laboratory e3); the run stops at t = 0 (the "
                 "same motion runs on SO(3) as problem.type heavy_top, or lower /problem/min_sin_theta)\n",
                 scene.file.c_str(), std::sin(value_of(y[1])), format_number(problem.min_sin_theta).c_str());
    report.final_state = scene.initial;
    // The angle rates (hence the angle-form energy) are undefined at sin θ = 0: the energy of the same state
    // on SO(3) instead.
    report.energy_initial = report.energy_final = energy(problem.heavy_top(), scene.initial);
    return report;
  }
  Progress progress{options.progress, report.expected_steps, options.stop};
  const auto start = Clock::now();
  EuclideanSummary summary;
  if (!scene.output_times.empty()) {
    std::vector<double> times = scene.output_times;
    if (times.back() < scene.t_end) times.push_back(scene.t_end);
    summary = integrate_times_euclidean(stepper, y, 0.0, scene.dt, std::span<const double>(times), observe, progress);
  } else {
    const std::int64_t every = scene.output_every > 0 ? scene.output_every : std::int64_t{1} << 62;
    summary = integrate_every_euclidean(stepper, y, 0.0, scene.dt, scene.t_end, every, observe, progress);
  }
  report.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  progress.finish();
  if (summary.left_domain) warn(summary.t_outside, std::sin(y[1]), summary.t);
  report.summary = summary;
  report.final_state = problem.to_state(y);
  report.energy_final = problem.energy(y);
  const auto inv1 = problem.invariants(y);
  for (const int i : integrals)
    report.invariants.push_back({std::string(EulerAngleTop<double>::invariant_names[static_cast<std::size_t>(i)]),
                                 inv0[static_cast<std::size_t>(i)], inv1[static_cast<std::size_t>(i)]});
  report.write_failed = report.write_failed || row.failed();
  return report;
}

template <template <class> class... Ms>
RunReport dispatch(const EulerAngleTop<double>& problem, const Scene& scene, const RunOptions& options,
                   MethodList<Ms...>) {
  RunReport report;
  bool found = false;
  const auto try_method = [&]<template <class> class M>() {
    if constexpr (method_applies_v<M, EulerAngleTop<double>>) {
      using Tab = rkmk_tableau<M<FreeBody<double>>>;
      if (!found && Tab::tableau.name == scene.method->traits.name) {
        report = run_euler_angles<Tab::tableau>(problem, scene, options);
        found = true;
      }
    }
  };
  (try_method.template operator()<Ms>(), ...);
  if (!found) throw std::logic_error("lgi: method registry out of sync");
  return report;
}

}  // namespace runner_detail

template <class P>
RunReport run_problem(const P& problem, const Scene& scene, const RunOptions& options) {
  return runner_detail::dispatch(problem, scene, options, Methods{});
}

}  // namespace lgi::app
