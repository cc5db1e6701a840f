// lgi/apps/fit_command.cpp — `lgi fit FITFILE [-o RESULT.json] [-v] [-q]` (docs/fitting.md, "The lgi fit command").
//
// A fit file is a scene (problem, initial, integrator, t_end; DESIGN.md §3) plus a "fit" section:
//
//   "fit": {
//     "unknowns": ["initial.omega", {"name": "problem.inertia", "fixed": [2], "lower": [..], "upper": [..]}],
//     "observations": [ {"t": 0.2, "R": [[..], [..], [..]], "sigma": 1e-3},          attitude (body → lab)
//                       {"t": 0.2, "q": [w, x, y, z], "sigma": 1e-3},                attitude quaternion
//                       {"t": 0.4, "omega": [..], "sigma": 1e-2},                    gyro (body frame)
//                       {"t": 0.6, "axis": [..], "direction": [..], "sigma": 1e-3},  a body axis's lab direction
//                       ... each optionally with "loss": "huber" | "cauchy", "loss_scale": c (in σ) ],
//     or "observations": {"csv": "FILE.csv", "sigma_attitude": 1e-3, "sigma_omega": 1e-2}
//                       (columns named as `lgi run` writes them: t, R11..R33, omega1..omega3; the path is
//                       relative to the fit file),
//     "continuation": [0.1, 0.3],                                  horizon continuation (optional)
//     "periodic": {"period": T, "steps": 1000, "phase": 0, "tolerance": 1e-10, "symmetry": "automatic"},
//                                                                  a periodic orbit instead of observations
//                                                                  (h = T/steps; steps defaults to T/dt)
//     "solver": {"max_iterations": 100, "function_tolerance": 1e-14, "gradient_tolerance": 1e-14,
//                "parameter_tolerance": 1e-12, "threads": 1},
//     "covariance": true
//   }
//
// Output: a JSON object with the fitted values under the scene's names ("initial": {"omega", "R"},
// "problem": {"inertia", "b", "z0"}, "period", "phase"), their standard deviations under "sigma" (same
// nesting), the correlation and covariance of the free coordinates, the costs, iterations and Ceres'
// termination type, and "usable". Exit status 0 when usable, 5 when not (the result is still written), 1 on
// bad input (one message naming the file and JSON path or CSV line; nothing written), 3 on write errors.
//
// Methods and problems: `lgi fit` offers the (method, problem) pairs instantiated in fit_instances.hpp —
// lgvi and rkmk4 on free_body and heavy_top (Lagrange and Kovalevskaya tops are heavy_top scenes with their
// data) — because each pair costs tens of seconds of compile CPU. The library (lgi::fit) takes any of them.
#include "fit_command.hpp"

#include "command.hpp"
#include "json_reader.hpp"
#include "runner.hpp"
#include "scene.hpp"

#include "fit_file.hpp"
#include "fit_instances.hpp"

#include <glog/logging.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace lgi::app {


namespace {

// Nests a scene name ("initial.omega") into `out` ({"initial": {"omega": value}}).
void put(json& out, const std::string& name, json value) {
  const std::size_t dot = name.find('.');
  if (dot == std::string::npos) out[name] = std::move(value);
  else out[name.substr(0, dot)][name.substr(dot + 1)] = std::move(value);
}

template <class P>
json result_json(const FitSpec& spec, const fit::FitResult<P>& r, const std::string& file) {
  json out;
  out["fit_file"] = file;
  out["problem_type"] = std::string(P::name);
  out["method"] = std::string(spec.scene.method->traits.name);
  out["mode"] = spec.periodic ? "periodic" : "observations";
  if (spec.periodic) out["steps"] = spec.periodic_options.steps;
  else out["dt"] = spec.scene.dt;
  out["usable"] = r.usable;
  if (r.budget_exhausted) out["budget_exhausted"] = true;
  out["termination"] = r.termination_type;
  out["message"] = r.message;
  out["iterations"] = r.iterations;
  out["integrations"] = r.integrations;
  out["seconds"] = r.seconds;
  out["residuals"] = r.residuals;
  out["initial_cost"] = r.initial_cost;
  if (!spec.periodic) out["guess_cost"] = r.guess_cost;
  out["final_cost"] = r.final_cost;
  out["max_residual"] = r.max_residual;
  if (!spec.periodic) {
    out["chi_square"] = r.chi_square;
    out["degrees_of_freedom"] = r.degrees_of_freedom;
    out["p_value"] = r.p_value >= 0 ? json(r.p_value) : json(nullptr);
  }
  if (!spec.periodic) out["observations"] = spec.observations.size();
  json sigma = json::object();
  for (const fit::FittedValue& v : r.values) {
    json value = json(v.value);
    if (v.name == "initial.R") value = json::array({json::array({v.value[0], v.value[1], v.value[2]}),
                                                    json::array({v.value[3], v.value[4], v.value[5]}),
                                                    json::array({v.value[6], v.value[7], v.value[8]})});
    if (v.value.size() == 1) value = v.value[0];
    put(out, v.name, std::move(value));
    put(sigma, v.name, v.sigma.size() == 1 ? json(v.sigma[0]) : json(v.sigma));
  }
  if (r.covariance_ok) {
    out["sigma"] = sigma;
    json cov = json::array(), cor = json::array();
    for (Eigen::Index i = 0; i < r.covariance.rows(); ++i) {
      json crow = json::array(), rrow = json::array();
      for (Eigen::Index j = 0; j < r.covariance.cols(); ++j) {
        crow.push_back(r.covariance(i, j));
        rrow.push_back(r.correlation(i, j));
      }
      cov.push_back(crow);
      cor.push_back(rrow);
    }
    out["coordinates"] = r.labels;
    out["covariance"] = cov;
    out["correlation"] = cor;
  }
  if (r.find("problem.inertia") && !r.principal_axes.isIdentity(0)) {
    json axes = json::array();
    for (int i = 0; i < 3; ++i)
      axes.push_back(json::array({r.principal_axes(i, 0), r.principal_axes(i, 1), r.principal_axes(i, 2)}));
    out["principal_axes"] = axes;  // columns: the axes of problem.inertia's moments
  }
  return out;
}

std::string format_vector(const std::vector<double>& v) {
  std::string s = "[";
  char buf[40];
  for (std::size_t i = 0; i < v.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%s%.10g", i ? ", " : "", v[i]);
    s += buf;
  }
  return s + "]";
}

template <class P>
std::string brief(const FitSpec& spec, const fit::FitResult<P>& r, const std::string& file) {
  std::string s;
  char buf[512];
  const int free = static_cast<int>(r.labels.size());
  if (spec.periodic)
    std::snprintf(buf, sizeof buf, "lgi fit: %s: periodic orbit of %s, %s with %d steps a period, %d free coordinates\n",
                  file.c_str(), std::string(P::name).c_str(), std::string(spec.scene.method->traits.name).c_str(),
                  spec.periodic_options.steps, free);
  else
    std::snprintf(buf, sizeof buf, "lgi fit: %s: %s, %s h = %g, %zu observations (%d residuals), %d free coordinates\n",
                  file.c_str(), std::string(P::name).c_str(), std::string(spec.scene.method->traits.name).c_str(),
                  spec.scene.dt, spec.observations.size(), r.residuals, free);
  s += buf;
  for (const auto* list : {&spec.scene.adjustments, &spec.adjustments})
    for (const InputAdjustment& a : *list) s += "  input            " + a.where + " " + a.what + "\n";
  // The cost over the whole arc: at the guess, after the continuation stages (where there are any), at the solution.
  char costs[160];
  if (spec.options.continuation.empty() || spec.periodic)
    std::snprintf(costs, sizeof costs, "cost %.3g -> %.3g", r.initial_cost, r.final_cost);
  else
    std::snprintf(costs, sizeof costs, "cost %.3g at the guess, %.3g after %zu continuation stages -> %.3g",
                  r.guess_cost, r.initial_cost, spec.options.continuation.size(), r.final_cost);
  std::snprintf(buf, sizeof buf, "  %s after %d iterations (%ld integrations, %.3g s); %s, max |r%s| %.3g\n",
                r.termination_type.c_str(), r.iterations, r.integrations, r.seconds, costs,
                spec.periodic ? "" : "/sigma", r.max_residual);
  s += buf;
  if (r.p_value >= 0) {
    std::snprintf(buf, sizeof buf, "  chi^2 = %.4g for %d degrees of freedom (chi^2/nu = %.3g, p = %.3g)\n", r.chi_square,
                  r.degrees_of_freedom, r.chi_square / r.degrees_of_freedom, r.p_value);
    s += buf;
  }
  for (const fit::FittedValue& v : r.values) {
    s += "  " + v.name + " = " + format_vector(v.value);
    if (r.covariance_ok) s += "  sigma " + format_vector(v.sigma);
    s += "\n";
  }
  s += r.usable ? "  usable\n" : "  NOT usable\n";
  return s;
}

// Why a result is not usable (docs/fitting.md, "Uncertainty").
template <class P>
std::string unusable_reason(const FitSpec& spec, const fit::FitResult<P>& r) {
  if (spec.periodic)
    return "the periodicity residual " + format_number(r.max_residual) + " is above the tolerance " +
           format_number(spec.periodic_options.tolerance);
  if (r.budget_exhausted) return "stopped by /limits/max_wall_seconds";
  if (r.termination != ceres::CONVERGENCE)
    return "the solver did not converge (" + r.termination_type + ": " + r.message + ")";
  if (!std::isfinite(r.final_cost)) return "the final cost is not finite";
  if (r.p_value >= 0 && r.p_value < spec.options.min_p_value) {
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "the fit does not explain the data: chi^2 = %.4g for %d degrees of freedom (chi^2/nu = %.3g, "
                  "p = %.2g < %g; max |r/sigma| = %.3g): a local minimum, a wrong model or unknowns, or sigmas too "
                  "small (docs/fitting.md, \"Is the fit usable?\")",
                  r.chi_square, r.degrees_of_freedom, r.chi_square / r.degrees_of_freedom, r.p_value,
                  spec.options.min_p_value, r.max_residual);
    return buf;
  }
  return "no covariance: the Jacobian is rank deficient (a combination of the unknowns that the observations do "
         "not fix; see docs/fitting.md, \"What the data fix\")";
}

template <template <class> class Method, class P>
fit::FitResult<P> solve(const P& problem, const FitSpec& spec) {
  if (spec.periodic)
    return fit::fit_periodic<Method, 8>(problem, spec.scene.initial, spec.period, spec.unknowns, spec.periodic_options,
                                        spec.phase);
  return fit::fit_observations<Method, 8>(problem, spec.scene.initial, spec.unknowns, spec.observations, spec.options);
}

// The (method, problem) pairs `lgi fit` offers: those of LGI_FIT_OBSERVATION_FITS and LGI_FIT_PERIODIC_FITS.
constexpr std::string_view fit_methods = "lgvi, rkmk4";
constexpr std::string_view fit_problems = "free_body, heavy_top, rigid_body and gyrostat (lgvi, observations)";

}  // namespace

int fit_command(const FitCommandOptions& options) {
  // Ceres logs through glog to stderr (a rank-deficient covariance, a failed evaluation when a budget stops the
  // fit): what matters of it is in the one-line verdict; -v shows it.
  if (!options.verbose) FLAGS_minloglevel = google::GLOG_FATAL;
  const std::string& file = options.fit_file;
  FitSpec spec;
  try {
    spec = options.document ? parse_fit_document(*options.document, file) : read_fit_file(file);
  } catch (const CsvError& e) {
    return fail(exit_bad_input, file + ": " + e.what());
  } catch (const InputError& e) {
    return fail(exit_bad_input, e.what());
  }
  // Input made exact where it was further off than single precision's rounding: said before the fit, also with
  // -q (the report lists every change).
  for (const auto* list : {&spec.scene.adjustments, &spec.adjustments})
    for (const InputAdjustment& a : *list)
      if (a.defect > input_warn_defect)
        std::fprintf(stderr, "lgi: warning: %s: %s: %s\n", file.c_str(), a.where.c_str(), a.what.c_str());
  const std::string method(spec.scene.method->traits.name);
  if (method != "lgvi" && method != "rkmk4")
    return fail(exit_bad_input, file + ": /integrator/method: lgi fit offers the methods " + std::string(fit_methods) +
                                    " (got \"" + method + "\"; the library lgi::fit takes any, see docs/fitting.md)");
  spec.options.solver.progress = false;
  spec.periodic_options.solver.progress = false;
  // Progress (ProgressLine): the solver's iterations.
  ProgressLine progress(progress_mode(options.quiet, options.progress));
  if (progress.mode() != Progress::none) {
    const auto show = [&](int iteration, double cost, double gradient) {
      if (!progress.due()) return;
      char line[160];
      std::snprintf(line, sizeof line, "iteration %d: cost %.4g, max |gradient| %.3g, %.0f s elapsed", iteration, cost,
                    gradient, progress.elapsed());
      progress.show(line);
    };
    spec.options.solver.on_iteration = show;
    spec.periodic_options.solver.on_iteration = show;
  }

  // An unwritable output path fails before the (possibly long) solve; the file itself is created after it,
  // so that a fit killed mid-way leaves no temporary file behind.
  if (!options.output.empty()) {
    if (!is_streamed_path(options.output) && same_file(options.output, file))
      return fail(exit_bad_input, "-o " + options.output + " is the fit file itself: lgi does not replace its input");
    if (const std::string why = output_replaces_input(spec.scene, options.output); !why.empty())
      return fail(exit_bad_input, why);
    try {
      OutputFile probe(options.output);
    } catch (const OutputError& e) {
      return fail(exit_io_error, e.what());
    }
  }

  json result;
  std::string report, full_report, reason;
  bool usable = false, budget = false;
  try {
    const auto report_fit = [&](const auto& r) {
      result = result_json(spec, r, file);
      report = brief(spec, r, file);
      full_report = r.full_report;
      usable = r.usable;
      budget = r.budget_exhausted;
      if (!usable) reason = unusable_reason(spec, r);
    };
    const auto fit_with = [&](const auto& problem) {
      report_fit(method == "lgvi" ? solve<Lgvi>(problem, spec) : solve<Rkmk4>(problem, spec));
    };
    bool offered = true;
    if (const auto* body = problem_as<FreeBody<double>>(*spec.scene.problem)) {
      fit_with(*body);
    } else if (const auto* top = problem_as<HeavyTop<double>>(*spec.scene.problem)) {
      fit_with(*top);
    } else if (const auto* torqued = problem_as<TorquedBody<double>>(*spec.scene.problem)) {
      // Damping and control do work: no periodic orbits in general; one method (the forced LGVI) for compile time.
      if (spec.periodic)
        return fail(exit_bad_input, file + ": /fit/periodic: lgi fit offers rigid_body with observations only (its "
                                           "torque reads the angular velocity: no periodic orbits in general)");
      if (method != "lgvi")
        return fail(exit_bad_input, file + ": /integrator/method: lgi fit offers rigid_body with the method lgvi "
                                           "(got \"" + method + "\"; the library lgi::fit takes any)");
      report_fit(fit::fit_observations<Lgvi, 8>(*torqued, spec.scene.initial, spec.unknowns, spec.observations,
                                                spec.options));
    } else if (const auto* gyrostat = problem_as<Gyrostat<double>>(*spec.scene.problem)) {
      // As rigid_body: observations only, the gyrostat LGVI only.
      if (spec.periodic)
        return fail(exit_bad_input, file + ": /fit/periodic: lgi fit offers gyrostat with observations only (friction "
                                           "and motors do work: no periodic orbits in general)");
      if (method != "lgvi")
        return fail(exit_bad_input, file + ": /integrator/method: lgi fit offers gyrostat with the method lgvi (got \"" +
                                           method + "\"; the library lgi::fit takes any of the gyrostat's methods)");
      report_fit(fit::fit_observations<GyrostatLgvi, 8>(*gyrostat, spec.scene.initial, spec.unknowns,
                                                        spec.observations, spec.options));
    } else {
      offered = false;
    }
    if (!offered)
      return fail(exit_bad_input, file + ": /problem/type: lgi fit offers the problems " + std::string(fit_problems) +
                                      " (a Lagrange or Kovalevskaya top is a heavy_top with its data; the library lgi::fit "
                                      "takes any problem)");
  } catch (const fit::FitInputError& e) {
    return fail(exit_bad_input, file + ": " + where_of(e.field(), spec) + ": " +
                                    std::string(e.what()).substr(e.field().size() + 2));
  }

  progress.clear();
  const std::string text = result.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
  std::unique_ptr<OutputFile> out;
  try {
    out = std::make_unique<OutputFile>(options.output.empty() ? std::string("-") : options.output);
  } catch (const OutputError& e) {
    return fail(exit_io_error, e.what());
  }
  if (!out->write_record(text) || !out->commit())
    return fail(exit_io_error, out->display_name() + ": cannot write the result: " + out->error_text());
  if (options.verbose) std::fputs(full_report.c_str(), stderr);
  if (!options.quiet) std::fputs(report.c_str(), stderr);
  if (budget)
    return fail(exit_run_stopped, file + ": stopped by /limits/max_wall_seconds = " +
                                      format_number(spec.scene.max_wall_seconds) + ": the solution is not usable (result "
                                      "written to " + out->display_name() + ", \"usable\": false)");
  if (!usable)
    return fail(exit_fit_unusable, file + ": the solution is not usable: " + reason + " (result written to " +
                                       out->display_name() + ", \"usable\": false)");
  return 0;
}

}  // namespace lgi::app
