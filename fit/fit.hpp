/// \file
/// lgi/fit/fit.hpp — fit initial conditions and body parameters to observations, or find periodic orbits, by
/// nonlinear least squares (Ceres) with derivatives through the integrator itself.
///
/// Observations (fit/observations.hpp): minimise ½ Σ_i ρ_i(|r_i(θ)/σ_i|²) over the unknowns θ
/// (fit/model.hpp), r_i the tangent-space error of observation i against the trajectory integrated by the
/// chosen method with fixed step dt from (R0, Ω0). Levenberg–Marquardt (Ceres' trust region), dense QR.
///
/// Uncertainty. With residuals whitened by their standard deviations the covariance of the estimate is, to
/// first order, C = (JᵀJ)⁻¹ with J the Jacobian of the whitened residuals in the tangent space of the unknowns
/// at the solution (Ceres, include/ceres/covariance.h: "the covariance ... is given by C(x*) = (J'(x*)J(x*))⁻¹";
/// Triggs-corrected J where robust losses are used). It is computed by ceres::Covariance (dense SVD; a Jacobian
/// whose σ_min/σ_max < 1e-7 is rank deficient — an unidentifiable combination, such as the scale of the
/// inertia of a free body — and yields no covariance, and the fit is reported not usable). Standard deviations
/// are √C_kk; correlations C_kl/√(C_kk C_ll). For R0 the coordinates are δ in R̂0 Exp(δ) (radians about the
/// body axes); for the moments, I_k = exp(ℓ_k) and C is mapped by the delta method, σ(I_k) = I_k σ(ℓ_k).
/// The residual scale is not re-estimated: the σ's given with the observations are taken as true.
///
/// Periodic orbits: solve r(θ) = 0 for the periodicity residual (fit/model.hpp, PeriodicSymmetry), with the
/// period T among the unknowns when listed ("period"; the step is T/steps) and the phase φ for heavy tops.
#pragma once

#include "model.hpp"

#include <ceres/covariance.h>
#include <ceres/problem.h>
#include <ceres/solver.h>

#include <boost/math/special_functions/gamma.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace lgi::fit {

/// The solver's limits and tolerances (Ceres' Levenberg–Marquardt, dense QR).
struct SolverOptions {
  int max_iterations = 100;            ///< Ceres' iterations (successful and not) at most
  double function_tolerance = 1e-14;   ///< Ceres: stop when |Δcost|/cost < this
  double gradient_tolerance = 1e-14;   ///< Ceres: stop when the projected gradient's max norm < this
  double parameter_tolerance = 1e-12;  ///< Ceres: stop when |Δθ| < this (|θ| + this)
  int num_threads = 1;                 ///< Ceres' threads for residual and Jacobian evaluations
  bool progress = false;               ///< Ceres' per-iteration table on stdout
  /// Called after every iteration of the solver (each continuation stage's too) with the iteration's number
  /// within its solve, the cost ½ Σ ρ and the largest gradient component; empty: not called. For progress
  /// displays (`lgi fit` on a terminal); it must not throw.
  std::function<void(int iteration, double cost, double gradient)> on_iteration = {};
  /// A wall-clock budget for the whole fit (continuation stages included), seconds; 0: none. When it is spent the
  /// integration under way stops within 1024 steps, the solver stops, and the result is not usable
  /// (FitResult::budget_exhausted).
  double max_seconds = 0;
};

/// The options of fit_observations: the integration, the solver, the covariance and the acceptance test.
struct FitOptions {
  double dt = 0;           ///< the integrator's fixed step (scene: integrator.dt)
  double t_end = -1;       ///< observations must lie in [0, t_end] (scene: t_end); < 0: no limit
  StepperOptions stepper;  ///< the integrator's options (Newton tolerance, ...); rtol/atol must be 0
  SolverOptions solver;            ///< the solver's limits and tolerances
  bool compute_covariance = true;  ///< compute FitResult::covariance; then a rank-deficient fit is not usable
  /// Goodness of fit: with observations that carry their true σ and a model that explains them, χ² = Σ (r/σ)² at
  /// the solution follows a χ² distribution with ν = residuals − free coordinates degrees of freedom. The fit is
  /// usable only if P(χ²_ν ≥ χ²) ≥ min_p_value (FitResult::p_value; the test is not applied with robust losses or
  /// when ν ≤ 0). 0 turns the test off.
  double min_p_value = 1e-3;
  /// Horizon continuation: fit first the observations with t ≤ f·t_last for each f here (increasing, in (0, 1)),
  /// each stage starting from the previous one's estimate, then all of them. A fast-spinning body observed over
  /// many turns has a cost with many local minima in Ω0 and the inertia; a short horizon has few.
  std::vector<double> continuation;
};

/// The options of fit_periodic.
struct PeriodicOptions {
  int steps = 1000;        ///< steps over one period: h = T/steps
  PeriodicSymmetry symmetry = PeriodicSymmetry::automatic;  ///< what "returns to itself" means
  double tolerance = 1e-10;  ///< usable when max |r| ≤ tolerance
  StepperOptions stepper;    ///< the integrator's options (fixed steps: rtol = atol = 0)
  /// A zero residual is the goal: stop on the step size, not on the relative decrease of a cost near 0.
  SolverOptions solver{.max_iterations = 100, .function_tolerance = 1e-30, .gradient_tolerance = 1e-30,
                       .parameter_tolerance = 1e-16};
};

/// One fitted unknown, under its scene name.
struct FittedValue {
  std::string name;           ///< the unknown's scene name
  std::vector<double> value;  ///< initial.R: 9 entries row by row (R11, R12, ..., R33); problem.z0: 3
  std::vector<double> sigma;  ///< standard deviations, one per tangent coordinate (initial.R: 3, rad, about the
                              ///< body axes; problem.z0: 2, rad, in the basis s2_basis(z0)); 0 for fixed ones
  std::vector<bool> free;     ///< per tangent coordinate
};

/// What a fit found, how well, and why it stopped. `usable` is the one flag to test before using the values.
template <class P>
struct FitResult {
  P problem;                 ///< the base problem with the fitted parameters
  State<double> initial;     ///< the fitted initial state
  ///@{
  /// Periodic orbits: the period T and phase φ (rad) of the result (the guesses where not fitted); 0 for
  /// observation fits.
  double period = 0, phase = 0;
  ///@}
  std::vector<FittedValue> values;      ///< the unknowns, in the order of block_info
  std::vector<std::string> labels;      ///< the free tangent coordinates, e.g. "initial.omega[1]", "initial.R[d3]"
  Eigen::MatrixXd covariance;           ///< over `labels` (empty when not computed or rank deficient)
  Eigen::MatrixXd correlation;          ///< C_kl/√(C_kk C_ll) over `labels` (empty with the covariance)
  Mat3<double> principal_axes = Mat3<double>::Identity();  ///< columns: the axes of problem.inertia's moments
  ///@{
  /// ½ Σ ρ(|r/σ|²) at the start of the last solve and at the solution (with continuation the last solve starts
  /// where the stages ended).
  double initial_cost = 0, final_cost = 0;
  ///@}
  /// ½ Σ ρ(|r/σ|²) over all observations at the caller's guess (initial_cost without continuation; observation fits).
  double guess_cost = 0;
  int iterations = 0;                       ///< Ceres' iterations (successful and not)
  ceres::TerminationType termination = ceres::FAILURE;  ///< Ceres' termination
  std::string termination_type;             ///< "CONVERGENCE", "NO_CONVERGENCE", "FAILURE", ...
  std::string message;                      ///< Ceres' message
  bool covariance_ok = false;           ///< the covariance was computed (Jacobian of full rank)
  bool usable = false;  ///< converged, finite cost, covariance fine and the data explained (or periodic residual fine)
  int residuals = 0;                        ///< the number of residual components
  double max_residual = 0;                  ///< max |r/σ| (periodic: max |r|)
  double chi_square = 0;                    ///< Σ (r/σ)² at the solution, before any robust loss (periodic: Σ r²)
  int degrees_of_freedom = 0;               ///< residuals − free tangent coordinates
  /// P(χ²_ν ≥ chi_square) (regularised upper incomplete gamma Q(ν/2, χ²/2)) where the goodness-of-fit test applies
  /// (observations without robust losses, ν > 0); −1 where it does not.
  double p_value = -1;
  bool budget_exhausted = false;            ///< SolverOptions::max_seconds ran out (the result is not usable)
  long integrations = 0;                    ///< integrations run (one per Jet pass)
  double seconds = 0;                       ///< wall time of the solve
  std::string report;                       ///< Ceres' BriefReport
  std::string full_report;                  ///< Ceres' FullReport and the per-iteration table

  /// The unknown `name` (scene name), or nullptr when it was not fitted.
  const FittedValue* find(std::string_view name) const {
    for (const FittedValue& v : values)
      if (v.name == name) return &v;
    return nullptr;
  }
  /// The unknown `name`; std::out_of_range when it was not fitted.
  const FittedValue& at(std::string_view name) const {
    if (const FittedValue* v = find(name)) return *v;
    throw std::out_of_range("lgi::fit::FitResult: no unknown '" + std::string(name) + "'");
  }
};

namespace detail {

inline ceres::Solver::Options solver_options(const SolverOptions& s) {
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::DENSE_QR;
  o.max_num_iterations = s.max_iterations;
  o.function_tolerance = s.function_tolerance;
  o.gradient_tolerance = s.gradient_tolerance;
  o.parameter_tolerance = s.parameter_tolerance;
  o.num_threads = s.num_threads;
  o.minimizer_progress_to_stdout = s.progress;
  o.logging_type = s.progress ? ceres::PER_MINIMIZER_ITERATION : ceres::SILENT;
  return o;
}

template <template <class> class Method, FitProblem P, int N>
FitResult<P> collect(Model<Method, P, N>& model, ceres::Problem& problem, const ceres::Solver::Summary& summary,
                     bool covariance, double seconds) {
  FitResult<P> res;
  res.initial_cost = summary.initial_cost;
  res.final_cost = summary.final_cost;
  res.iterations = static_cast<int>(summary.iterations.size()) - 1;  // iteration 0 is the starting point
  res.termination = summary.termination_type;
  res.termination_type = ceres::TerminationTypeToString(summary.termination_type);
  res.message = summary.message;
  res.report = summary.BriefReport();
  res.full_report = summary.FullReport() + "\n";
  {
    char line[160];
    std::snprintf(line, sizeof line, "%4s %-13s %-13s %-13s %-13s %s\n", "iter", "cost", "cost_change", "|gradient|",
                  "|step|", "tr_radius");
    res.full_report += line;
    for (const ceres::IterationSummary& it : summary.iterations) {
      std::snprintf(line, sizeof line, "%4d %-13.6e %-13.6e %-13.6e %-13.6e %.2e%s\n", it.iteration, it.cost, it.cost_change,
                    it.gradient_max_norm, it.step_norm, it.trust_region_radius, it.step_is_successful ? "" : "  (rejected)");
      res.full_report += line;
    }
  }
  res.residuals = summary.num_residuals;
  res.integrations = model.runs();
  res.seconds = seconds;
  res.principal_axes = model.principal_axes();

  // The fitted problem and state.
  const auto s = model.template seed<double>(nullptr, 0);
  res.problem = s.problem;
  res.initial = s.x0;
  res.period = s.period;
  res.phase = s.phase;

  // Covariance in the tangent space.
  const int n = model.tangent_size();
  std::vector<double*> blocks = model.parameter_blocks();
  if (covariance) {
    ceres::Covariance::Options co;
    co.algorithm_type = ceres::DENSE_SVD;
    co.num_threads = 1;
    ceres::Covariance cov(co);
    std::vector<const double*> cblocks(blocks.begin(), blocks.end());
    if (cov.Compute(cblocks, &problem)) {
      Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> C(n, n);
      if (cov.GetCovarianceMatrixInTangentSpace(cblocks, C.data()) && C.allFinite()) {
        res.covariance = C;
        res.covariance_ok = true;
      }
    }
  }
  // Delta method for the moments: d I_k = I_k dℓ_k.
  if (res.covariance_ok && model.is_active(Block::inertia)) {
    for (int k = 0; k < 3; ++k) {
      const int g = model.tangent_index(Block::inertia, k);
      if (g < 0) continue;
      const double I = std::exp(model.value(Block::inertia)[static_cast<std::size_t>(k)]);
      res.covariance.row(g) *= I;
      res.covariance.col(g) *= I;
    }
  }
  if (res.covariance_ok) {
    res.correlation = res.covariance;
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        res.correlation(i, j) = res.covariance(i, j) / std::sqrt(res.covariance(i, i) * res.covariance(j, j));
  }

  // Values and standard deviations by scene name.
  res.labels.assign(static_cast<std::size_t>(n), "");
  for (int b = 0; b < block_count; ++b) {
    const Block block = static_cast<Block>(b);
    if (!model.is_active(block)) continue;
    const BlockInfo& info = block_info[b];
    FittedValue v;
    v.name = std::string(info.name);
    const std::vector<double>& x = model.value(block);
    switch (block) {
      case Block::R:
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) v.value.push_back(res.initial.R(r, c));
        break;
      case Block::inertia:
        for (const double l : x) v.value.push_back(std::exp(l));
        break;
      case Block::rotor_friction:  // the rotors present
        v.value.assign(x.begin(), x.begin() + model.components(block));
        break;
      default:
        v.value = x;
    }
    for (int k = 0; k < model.components(block); ++k) {
      const int g = model.tangent_index(block, k);
      v.free.push_back(g >= 0);
      v.sigma.push_back(g >= 0 && res.covariance_ok ? std::sqrt(res.covariance(g, g)) : 0.0);
      if (g < 0) continue;
      std::string label = v.name;  // name[k] (Euclidean), name[dk] (tangent coordinate k of a manifold)
      if (!info.euclidean) label.append("[d").append(std::to_string(k + 1)).append("]");
      else if (info.tangent > 1) label.append("[").append(std::to_string(k)).append("]");
      res.labels[static_cast<std::size_t>(g)] = std::move(label);
    }
    res.values.push_back(std::move(v));
  }

  // Largest residual at the solution.
  double cost = 0;
  std::vector<double> r;
  if (problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, &r, nullptr, nullptr)) {
    for (const double e : r) {
      res.max_residual = std::max(res.max_residual, std::abs(e));
      res.chi_square += e * e;
    }
  } else {
    res.max_residual = res.chi_square = std::numeric_limits<double>::infinity();
  }
  res.degrees_of_freedom = res.residuals - n;
  return res;
}

// Builds the Ceres problem of `model`, solves it and collects the result (the caller sets `usable`).
using Clock = std::chrono::steady_clock;

// The instant a budget of `seconds` from now ends (none: the far future).
inline Clock::time_point deadline_after(double seconds) {
  return seconds > 0 ? Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds))
                     : Clock::time_point::max();
}

template <template <class> class Method, FitProblem P, int N>
FitResult<P> solve(Model<Method, P, N>& model, const SolverOptions& solver, bool covariance, Clock::time_point deadline) {
  ceres::Problem::Options po;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem cp(po);
  model.add_to(cp);
  const auto start = Clock::now();
  ceres::Solver::Summary summary;
  ceres::Solver::Options o = solver_options(solver);
  struct Callback final : ceres::IterationCallback {
    const SolverOptions& s;
    explicit Callback(const SolverOptions& options) : s(options) {}
    ceres::CallbackReturnType operator()(const ceres::IterationSummary& i) override {
      s.on_iteration(i.iteration, i.cost, i.gradient_max_norm);
      return ceres::SOLVER_CONTINUE;
    }
  } callback(solver);
  if (solver.on_iteration) o.callbacks.push_back(&callback);
  if (deadline != Clock::time_point::max())
    o.max_solver_time_in_seconds = std::max(0.0, std::chrono::duration<double>(deadline - start).count());
  ceres::Solve(o, &cp, &summary);
  const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
  FitResult<P> res = collect(model, cp, summary, covariance && Clock::now() < deadline, seconds);
  res.budget_exhausted = Clock::now() >= deadline;
  return res;
}

}  // namespace detail

namespace detail {

template <template <class> class Method, int N, FitProblem P>
FitResult<P> fit_observations_until(const P& problem, const State<double>& initial, std::span<const Unknown> unknowns,
                                    std::span<const Observation> observations, const FitOptions& options,
                                    Clock::time_point deadline);

}  // namespace detail

/// Fits the unknowns to the observations. `problem` and `initial` are the base scene (the initial guesses of
/// the unknowns, the fixed values of the rest); Method is any of the library's stepper templates (lgvi: Lgvi,
/// rkmk4: Rkmk4, ...) used with the fixed step options.dt; N the Jet size (derivatives are computed in passes
/// of N tangent coordinates). Throws FitInputError (a std::invalid_argument) on bad input.
/// A fit that runs but does not succeed is not an exception: FitResult::usable is false and termination, message,
/// p_value and budget_exhausted say why. Cost: one integration in double per new point of the solver, plus
/// ⌈free coordinates / N⌉ Jet integrations where derivatives are needed.
template <template <class> class Method, int N = 8, FitProblem P>
FitResult<P> fit_observations(const P& problem, const State<double>& initial, std::span<const Unknown> unknowns,
                              std::span<const Observation> observations, const FitOptions& options) {
  return detail::fit_observations_until<Method, N>(problem, initial, unknowns, observations, options,
                                                   detail::deadline_after(options.solver.max_seconds));
}

namespace detail {

template <template <class> class Method, int N, FitProblem P>
FitResult<P> fit_observations_until(const P& problem, const State<double>& initial, std::span<const Unknown> unknowns,
                                    std::span<const Observation> observations, const FitOptions& options,
                                    Clock::time_point deadline) {
  ModelOptions mo;
  mo.mode = Mode::observations;
  mo.dt = options.dt;
  mo.t_end = options.t_end;
  mo.stepper = options.stepper;
  mo.deadline = deadline;
  if (!options.continuation.empty()) {
    check_observations(observations, options.t_end < 0 ? std::numeric_limits<double>::max() : options.t_end);
    double previous = 0;
    for (const double f : options.continuation)
      if (!(f > previous && f < 1)) throw FitInputError("continuation", "fractions must increase within (0, 1)");
      else previous = f;
    FitOptions stage = options;
    stage.continuation.clear();
    stage.compute_covariance = false;
    P p = problem;
    State<double> x = initial;
    long integrations = 0;
    int iterations = 0;
    double seconds = 0;
    for (const double f : options.continuation) {
      const double t_cut = f * observations.back().t;
      std::size_t n = 0;
      while (n < observations.size() && observations[n].t <= t_cut) ++n;
      if (n == 0) continue;
      const FitResult<P> r = fit_observations_until<Method, N>(p, x, unknowns, observations.first(n), stage, deadline);
      if (!std::isfinite(r.final_cost) || r.budget_exhausted) break;
      p = r.problem;
      x = r.initial;
      integrations += r.integrations;
      iterations += r.iterations;
      seconds += r.seconds;
    }
    FitOptions last = options;
    last.continuation.clear();
    FitResult<P> res = fit_observations_until<Method, N>(p, x, unknowns, observations, last, deadline);
    // The cost at the guess over the whole arc (one integration in double).
    Model<Method, P, N> at_guess(problem, initial, unknowns, observations, mo);
    ceres::Problem::Options po;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem cp(po);
    at_guess.add_to(cp);
    if (!cp.Evaluate(ceres::Problem::EvaluateOptions(), &res.guess_cost, nullptr, nullptr, nullptr))
      res.guess_cost = std::numeric_limits<double>::infinity();
    res.integrations += integrations + 1;
    res.iterations += iterations;
    res.seconds += seconds;
    return res;
  }
  Model<Method, P, N> model(problem, initial, unknowns, observations, mo);
  FitResult<P> res = detail::solve(model, options.solver, options.compute_covariance, deadline);
  res.guess_cost = res.initial_cost;
  const bool robust = std::any_of(observations.begin(), observations.end(),
                                  [](const Observation& o) { return o.loss != Loss::none; });
  if (!robust && res.degrees_of_freedom > 0 && std::isfinite(res.chi_square)) {
    try {
      res.p_value = boost::math::gamma_q(0.5 * res.degrees_of_freedom, 0.5 * res.chi_square);
    } catch (const std::exception&) {  // Boost.Math's evaluation limits: far in a tail
      res.p_value = res.chi_square > res.degrees_of_freedom ? 0.0 : 1.0;
    }
  }
  res.usable = res.termination == ceres::CONVERGENCE && std::isfinite(res.final_cost) && !res.budget_exhausted &&
               (!options.compute_covariance || res.covariance_ok) &&
               (res.p_value < 0 || res.p_value >= options.min_p_value);
  return res;
}

}  // namespace detail

/// Finds a periodic orbit near the guess (problem, initial, period): the unknowns are listed as for
/// fit_observations, plus "period" and, for the about_k symmetry, "phase" (φ, rad; guess `phase`).
/// Throws FitInputError on bad input (a period ≤ 0 or not finite, steps < 1, an unknown that does not apply). The
/// result is usable when its cost is finite, max |r| ≤ options.tolerance and the budget was not exhausted; no
/// covariance is computed.
template <template <class> class Method, int N = 8, FitProblem P>
FitResult<P> fit_periodic(const P& problem, const State<double>& initial, double period, std::span<const Unknown> unknowns,
                          const PeriodicOptions& options, double phase = 0) {
  ModelOptions mo;
  mo.mode = Mode::periodic;
  mo.steps = options.steps;
  mo.stepper = options.stepper;
  mo.symmetry = options.symmetry;
  mo.deadline = detail::deadline_after(options.solver.max_seconds);
  Model<Method, P, N> model(problem, initial, unknowns, {}, mo, period, phase);
  FitResult<P> res = detail::solve(model, options.solver, false, mo.deadline);
  res.usable = std::isfinite(res.final_cost) && res.max_residual <= options.tolerance && !res.budget_exhausted;
  return res;
}

}  // namespace lgi::fit
