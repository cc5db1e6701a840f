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
// data) — because each pair costs ~25 s of compile CPU. The library (lgi::fit) takes any of them.
#include "fit_command.hpp"

#include "command.hpp"
#include "json_reader.hpp"
#include "scene.hpp"

#ifdef LGI_HAVE_FIT
#include "fit_instances.hpp"
#endif

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
#include <variant>
#include <vector>

namespace lgi::app {

#ifndef LGI_HAVE_FIT

int fit_command(const FitCommandOptions& options) {
  return fail(exit_bad_input, options.fit_file + ": this lgi was built without Ceres (LGI_BUILD_FIT=OFF): no fitting");
}

#else

namespace {

// The fit section, read and checked.
struct FitSpec {
  Scene scene;
  std::vector<fit::Unknown> unknowns;
  std::vector<bool> unknown_is_string;     // given as "name" rather than {"name": ...}
  std::vector<fit::Observation> observations;
  std::vector<std::string> observation_where;  // "/fit/observations/3" or "obs.csv:12"
  bool observations_from_csv = false;
  fit::FitOptions options;
  bool periodic = false;
  fit::PeriodicOptions periodic_options;
  double period = 0, phase = 0;
};

// Thrown for bad CSV input (already "file:line: message").
struct CsvError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) cells.push_back(cell);
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

std::string trim(std::string s) {
  const auto not_space = [](unsigned char c) { return !std::isspace(c); };
  s.erase(s.begin(), std::find_if(s.begin(), s.end(), not_space));
  s.erase(std::find_if(s.rbegin(), s.rend(), not_space).base(), s.end());
  return s;
}

// Reads an `lgi run`-style CSV: a header row, then rows of numbers. `lines[i]` is the file line of row i.
void read_csv(const std::string& path, std::vector<std::string>& header, std::vector<std::vector<double>>& rows,
              std::vector<int>& lines) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw CsvError(path + ": cannot read the observations file: " + ec.message());
  if (size > max_input_bytes)
    throw CsvError(path + ": file of " + std::to_string(size) + " bytes, more than the " + std::to_string(max_input_bytes) +
                   " an observations file may have");
  std::ifstream in(path);
  if (!in) throw CsvError(path + ": cannot read the observations file");
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (trim(line).empty()) continue;
    std::vector<std::string> cells = split_csv_line(line);
    if (header.empty()) {
      for (std::string& c : cells) header.push_back(trim(c));
      continue;
    }
    if (cells.size() != header.size())
      throw CsvError(path + ":" + std::to_string(number) + ": row has " + std::to_string(cells.size()) +
                     " values, the header " + std::to_string(header.size()));
    std::vector<double> row;
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const std::string c = trim(cells[i]);
      char* end = nullptr;
      const double v = std::strtod(c.c_str(), &end);
      if (c.empty() || end != c.c_str() + c.size() || !std::isfinite(v))
        throw CsvError(path + ":" + std::to_string(number) + ": column " + header[i] + ": not a finite number: \"" + c +
                       "\"");
      row.push_back(v);
    }
    rows.push_back(std::move(row));
    lines.push_back(number);
  }
  if (header.empty()) throw CsvError(path + ": empty observations file (no header row)");
  if (rows.empty()) throw CsvError(path + ": no data rows after the header");
}

fit::Observation read_observation(const Node& o) {
  o.allow_only({"t", "R", "q", "omega", "axis", "direction", "sigma", "loss", "loss_scale"}, "an observation");
  const double t = o.at("t").number();
  const double sigma = o.at("sigma").number();  // > 0 is checked by the library, naming the observation
  const bool R = o.find("R").has_value(), q = o.find("q").has_value(), w = o.find("omega").has_value(),
             a = o.find("axis").has_value() || o.find("direction").has_value();
  if (R + q + w + a != 1)
    o.fail("an observation gives exactly one of \"R\", \"q\", \"omega\", or \"axis\" with \"direction\"");
  fit::Observation obs;
  if (R) {
    obs = fit::Observation::attitude(t, o.at("R").mat3(), sigma);
  } else if (q) {
    const Node qn = o.at("q");
    if (!qn.is_array() || qn.size() != 4) qn.fail("expected an array of 4 numbers (w, x, y, z), got " + describe(qn.value()));
    Eigen::Vector4d v;
    for (std::size_t i = 0; i < 4; ++i) v(static_cast<int>(i)) = qn.at(i).number();
    if (v.norm() == 0) qn.fail("the zero quaternion is not a rotation");
    obs = fit::Observation::attitude_quaternion(t, v, sigma);
  } else if (w) {
    obs = fit::Observation::angular_velocity(t, o.at("omega").vec3(), sigma);
  } else {
    obs = fit::Observation::body_axis(t, o.at("axis").vec3(), o.at("direction").vec3(), sigma);
  }
  if (const auto loss = o.find("loss")) {
    try {
      obs.loss = fit::loss_from_name(loss->string());
    } catch (const fit::FitInputError& e) {
      loss->fail(std::string(e.what()).substr(e.field().size() + 2));
    }
    if (obs.loss == fit::Loss::none && o.find("loss_scale")) o.at("loss_scale").fail("given without a robust \"loss\"");
  } else if (o.find("loss_scale")) {
    o.at("loss_scale").fail("given without a robust \"loss\"");
  }
  if (const auto scale = o.find("loss_scale")) obs.loss_scale = scale->number();
  return obs;
}

// Bounds: numbers, or null for "none".
std::vector<double> read_bounds(const Node& n, double none) {
  if (!n.is_array()) n.fail("expected an array of numbers (null for no bound), got " + describe(n.value()));
  std::vector<double> v;
  for (std::size_t i = 0; i < n.size(); ++i) {
    const Node e = n.at(i);
    v.push_back(e.value().is_null() ? none : e.number());
  }
  return v;
}

fit::Unknown read_unknown(const Node& u) {
  if (u.value().is_string()) return fit::Unknown(u.string());
  if (!u.is_object()) u.fail("expected a name (\"initial.omega\", ...) or an object with \"name\", got " + describe(u.value()));
  u.allow_only({"name", "fixed", "lower", "upper"}, "an unknown");
  fit::Unknown out(u.at("name").string());
  if (const auto f = u.find("fixed")) {
    if (!f->is_array()) f->fail("expected an array of component indices (0, 1, 2), got " + describe(f->value()));
    for (std::size_t i = 0; i < f->size(); ++i) out.fixed.push_back(static_cast<int>(f->at(i).integer(0, 2)));
  }
  const double inf = std::numeric_limits<double>::infinity();
  if (const auto l = u.find("lower")) out.lower = read_bounds(*l, -inf);
  if (const auto h = u.find("upper")) out.upper = read_bounds(*h, inf);
  return out;
}

FitSpec read_fit_file(const std::string& file) {
  json document = read_json_file(file);
  const Node root(document, "", file);
  if (!root.is_object()) root.fail("expected an object (a scene with a \"fit\" section), got " + describe(document));
  const Node fit_node = root.at("fit");
  fit_node.allow_only({"unknowns", "observations", "continuation", "periodic", "solver", "covariance"}, "the fit section");

  FitSpec spec;
  // Periodic orbits need no t_end: it defaults to the period guess.
  const auto periodic = fit_node.find("periodic");
  if (periodic) {
    periodic->allow_only({"period", "steps", "phase", "tolerance", "symmetry"}, "a periodic fit");
    spec.periodic = true;
    spec.period = periodic->at("period").positive();
    // h = T/steps; without "steps", the scene's dt sets it (steps = round(T/dt)).
    if (const auto s = periodic->find("steps")) spec.periodic_options.steps = static_cast<int>(s->integer(1, 100000000));
    else spec.periodic_options.steps = 0;
    if (const auto p = periodic->find("phase")) spec.phase = p->number();
    if (const auto t = periodic->find("tolerance")) spec.periodic_options.tolerance = t->positive();
    if (const auto s = periodic->find("symmetry")) {
      const std::string name = s->string();
      if (name == "automatic") spec.periodic_options.symmetry = fit::PeriodicSymmetry::automatic;
      else if (name == "none") spec.periodic_options.symmetry = fit::PeriodicSymmetry::none;
      else if (name == "about_k") spec.periodic_options.symmetry = fit::PeriodicSymmetry::about_k;
      else if (name == "body_omega") spec.periodic_options.symmetry = fit::PeriodicSymmetry::body_omega;
      else s->fail("unknown symmetry \"" + name + "\" (known: automatic, none, about_k, body_omega)");
    }
    if (fit_node.find("observations")) fit_node.at("observations").fail("a periodic fit takes no observations");
    if (fit_node.find("continuation")) fit_node.at("continuation").fail("continuation is for fits to observations");
    if (fit_node.find("covariance")) fit_node.at("covariance").fail("a periodic fit computes no covariance");
  }

  // The scene: everything but "fit".
  json scene_doc = document;
  scene_doc.erase("fit");
  if (spec.periodic && !scene_doc.contains("t_end")) scene_doc["t_end"] = spec.period;
  spec.scene = parse_scene(scene_doc, file);

  // Unknowns.
  const Node unknowns = fit_node.at("unknowns");
  if (!unknowns.is_array() || unknowns.size() == 0)
    unknowns.fail("expected a non-empty array of unknowns (\"initial.omega\", \"initial.R\", \"problem.inertia\", ...)");
  for (std::size_t i = 0; i < unknowns.size(); ++i) {
    spec.unknowns.push_back(read_unknown(unknowns.at(i)));
    spec.unknown_is_string.push_back(unknowns.at(i).value().is_string());
  }

  // Observations.
  if (!spec.periodic) {
    const Node obs = fit_node.at("observations");
    if (obs.is_array()) {
      for (std::size_t i = 0; i < obs.size(); ++i) {
        spec.observations.push_back(read_observation(obs.at(i)));
        spec.observation_where.push_back(obs.at(i).where());
      }
    } else if (obs.is_object()) {
      obs.allow_only({"csv", "sigma_attitude", "sigma_omega"}, "an observations table");
      fit::TableOptions table;
      if (const auto s = obs.find("sigma_attitude")) table.sigma_attitude = s->positive();
      if (const auto s = obs.find("sigma_omega")) table.sigma_omega = s->positive();
      if (table.sigma_attitude == 0 && table.sigma_omega == 0)
        obs.fail("give \"sigma_attitude\" (for the R columns) and/or \"sigma_omega\" (for the omega columns)");
      std::filesystem::path csv = obs.at("csv").string();
      if (csv.is_relative()) csv = std::filesystem::path(file).parent_path() / csv;
      std::vector<std::string> header;
      std::vector<std::vector<double>> rows;
      std::vector<int> lines;
      read_csv(csv.string(), header, rows, lines);
      table.field = obs.where();
      try {
        spec.observations = fit::observations_from_table(header, rows, table);
      } catch (const fit::FitInputError& e) {
        throw CsvError(csv.string() + ": " + std::string(e.what()).substr(e.field().size() + 2));
      }
      // One or two observations per row, in row order: attitude then angular velocity.
      const std::size_t per_row = spec.observations.size() / rows.size();
      for (std::size_t i = 0; i < spec.observations.size(); ++i)
        spec.observation_where.push_back(csv.string() + ":" + std::to_string(lines[i / per_row]));
      spec.observations_from_csv = true;
    } else {
      obs.fail("expected an array of observations or {\"csv\": FILE, ...}, got " + describe(obs.value()));
    }
    if (const auto c = fit_node.find("continuation")) {
      if (!c->is_array()) c->fail("expected an array of fractions in (0, 1), got " + describe(c->value()));
      for (std::size_t i = 0; i < c->size(); ++i) spec.options.continuation.push_back(c->at(i).number());
    }
    if (const auto c = fit_node.find("covariance")) {
      if (!c->value().is_boolean()) c->fail("expected true or false, got " + describe(c->value()));
      spec.options.compute_covariance = c->value().get<bool>();
    }
  }

  // Solver.
  fit::SolverOptions& solver = spec.periodic ? spec.periodic_options.solver : spec.options.solver;
  if (const auto s = fit_node.find("solver")) {
    s->allow_only({"max_iterations", "function_tolerance", "gradient_tolerance", "parameter_tolerance", "threads"},
                  "the solver");
    if (const auto v = s->find("max_iterations")) solver.max_iterations = static_cast<int>(v->integer(1, 100000));
    if (const auto v = s->find("function_tolerance")) solver.function_tolerance = v->positive();
    if (const auto v = s->find("gradient_tolerance")) solver.gradient_tolerance = v->positive();
    if (const auto v = s->find("parameter_tolerance")) solver.parameter_tolerance = v->positive();
    if (const auto v = s->find("threads")) solver.num_threads = static_cast<int>(v->integer(1, 256));
  }

  if (spec.periodic && spec.periodic_options.steps == 0) {
    const double steps = std::round(spec.period / spec.scene.dt);
    if (steps > 1e8) root.at("integrator").at("dt").fail("period/dt = " + format_number(steps) + " steps, more than 1e8");
    spec.periodic_options.steps = std::max(1, static_cast<int>(steps));
  }
  spec.options.dt = spec.scene.dt;
  spec.options.t_end = spec.scene.t_end;
  spec.options.stepper = spec.scene.options;
  spec.periodic_options.stepper = spec.scene.options;
  return spec;
}

// The JSON path (or CSV line) of a FitInputError's field ("observations[3].t", "unknowns[1].name",
// "initial.R", "integrator.dt", "period", ...).
std::string where_of(const std::string& field, const FitSpec& spec) {
  const auto indexed = [&](std::string_view prefix) -> std::pair<std::size_t, std::string> {
    // "prefix[i].rest" → (i, "rest")
    const std::size_t close = field.find(']');
    const std::size_t i = std::stoul(field.substr(prefix.size() + 1, close - prefix.size() - 1));
    const std::string rest = close + 1 < field.size() ? field.substr(close + 2) : "";
    return {i, rest};
  };
  if (field.starts_with("observations[")) {
    const auto [i, rest] = indexed("observations");
    if (i < spec.observation_where.size()) {
      if (spec.observations_from_csv) {
        const std::string column = rest == "R" ? "columns R11..R33" : rest == "omega" ? "columns omega1..omega3"
                                                                                        : rest == "t" ? "column t"
                                                                                                      : rest;
        return spec.observation_where[i] + ": " + column;
      }
      return spec.observation_where[i] + (rest.empty() ? "" : "/" + rest);
    }
  }
  if (field.starts_with("unknowns[")) {
    const auto [i, rest] = indexed("unknowns");
    const bool bare = i < spec.unknown_is_string.size() && spec.unknown_is_string[i];
    return "/fit/unknowns/" + std::to_string(i) + (rest.empty() || bare ? "" : "/" + rest);
  }
  if (field == "observations" || field == "unknowns" || field == "continuation") return "/fit/" + field;
  if (field == "period" || field == "steps" || field == "symmetry" || field == "phase") return "/fit/periodic/" + field;
  std::string path = "/" + field;  // initial.R → /initial/R, integrator.dt → /integrator/dt
  std::replace(path.begin(), path.end(), '.', '/');
  return path;
}

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
  out["termination"] = r.termination_type;
  out["message"] = r.message;
  out["iterations"] = r.iterations;
  out["integrations"] = r.integrations;
  out["seconds"] = r.seconds;
  out["residuals"] = r.residuals;
  out["initial_cost"] = r.initial_cost;
  out["final_cost"] = r.final_cost;
  out["max_residual"] = r.max_residual;
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
  const std::string stages = spec.options.continuation.empty() || spec.periodic
                                 ? std::string()
                                 : " (" + std::to_string(spec.options.continuation.size()) +
                                       " continuation stages first; the cost is the full arc's)";
  std::snprintf(buf, sizeof buf, "  %s after %d iterations (%ld integrations, %.3g s); cost %.3g -> %.3g%s, max |r%s| %.3g\n",
                r.termination_type.c_str(), r.iterations, r.integrations, r.seconds, r.initial_cost, r.final_cost,
                stages.c_str(), spec.periodic ? "" : "/sigma", r.max_residual);
  s += buf;
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
  if (r.termination != ceres::CONVERGENCE)
    return "the solver did not converge (" + r.termination_type + ": " + r.message + ")";
  if (!std::isfinite(r.final_cost)) return "the final cost is not finite";
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
constexpr std::string_view fit_problems = "free_body, heavy_top";

}  // namespace

int fit_command(const FitCommandOptions& options) {
  const std::string& file = options.fit_file;
  FitSpec spec;
  try {
    spec = read_fit_file(file);
  } catch (const InputError& e) {
    return fail(exit_bad_input, e.what());
  } catch (const CsvError& e) {
    return fail(exit_bad_input, file + ": " + e.what());
  }
  const std::string method(spec.scene.method->traits.name);
  if (method != "lgvi" && method != "rkmk4")
    return fail(exit_bad_input, file + ": /integrator/method: lgi fit offers the methods " + std::string(fit_methods) +
                                    " (got \"" + method + "\"; the library lgi::fit takes any, see docs/fitting.md)");
  spec.options.solver.progress = false;
  spec.periodic_options.solver.progress = false;

  // An unwritable output path fails before the (possibly long) solve; the file itself is created after it,
  // so that a fit killed mid-way leaves no temporary file behind.
  if (!options.output.empty()) {
    try {
      AtomicOutput probe(options.output);
    } catch (const std::exception& e) {
      return fail(exit_io_error, e.what());
    }
  }

  json result;
  std::string report, full_report, reason;
  bool usable = false;
  try {
    const bool offered = std::visit(
        [&](const auto& problem) {
          using P = std::decay_t<decltype(problem)>;
          if constexpr (std::is_same_v<P, FreeBody<double>> || std::is_same_v<P, HeavyTop<double>>) {
            const fit::FitResult<P> r =
                method == "lgvi" ? solve<Lgvi>(problem, spec) : solve<Rkmk4>(problem, spec);
            result = result_json(spec, r, file);
            report = brief(spec, r, file);
            full_report = r.full_report;
            usable = r.usable;
            if (!usable) reason = unusable_reason(spec, r);
            return true;
          } else {
            return false;
          }
        },
        spec.scene.problem);
    if (!offered)
      return fail(exit_bad_input, file + ": /problem/type: lgi fit offers the problems " + std::string(fit_problems) +
                                      " (a Lagrange or Kovalevskaya top is a heavy_top with its data; the library lgi::fit "
                                      "takes any problem)");
  } catch (const fit::FitInputError& e) {
    return fail(exit_bad_input, file + ": " + where_of(e.field(), spec) + ": " +
                                    std::string(e.what()).substr(e.field().size() + 2));
  }

  const std::string text = result.dump(2, ' ', false, json::error_handler_t::replace) + "\n";
  std::unique_ptr<AtomicOutput> out;
  if (!options.output.empty()) {
    try {
      out = std::make_unique<AtomicOutput>(options.output);
    } catch (const std::exception& e) {
      return fail(exit_io_error, e.what());
    }
  }
  std::FILE* f = out ? out->file() : stdout;
  if (std::fputs(text.c_str(), f) < 0 || std::ferror(f))
    return fail(exit_io_error, (out ? options.output : std::string("stdout")) + ": write error");
  if (out && !out->commit()) return fail(exit_io_error, options.output + ": cannot write the output file: " + std::strerror(errno));
  if (!out && std::fflush(stdout) != 0) return fail(exit_io_error, "stdout: write error");
  if (options.verbose) std::fputs(full_report.c_str(), stderr);
  if (!options.quiet) std::fputs(report.c_str(), stderr);
  if (!usable)
    return fail(exit_fit_unusable, file + ": the solution is not usable: " + reason + " (result written" +
                                       (out ? " to " + options.output : std::string()) + ", \"usable\": false)");
  return 0;
}

#endif  // LGI_HAVE_FIT

}  // namespace lgi::app
