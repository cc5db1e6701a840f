// lgi/apps/fit_file.cpp — reading fit files and observation tables (fit_file.hpp).
#include "fit_file.hpp"

#include <lgi/core/so3.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace lgi::app {

namespace {

// A table's quaternions (q_w..q_z, when it has them all and no R columns) normalised, as in scenes: each within
// input_defect_bound of unit length, one adjustment for the file; beyond the bound a CsvError naming the line.
void make_quaternions_exact(const std::string& path, const std::vector<std::string>& header,
                            std::vector<std::vector<double>>& rows, const std::vector<int>& lines,
                            std::vector<InputAdjustment>& adjustments) {
  static constexpr std::string_view names[4] = {"q_w", "q_x", "q_y", "q_z"};
  std::size_t column[4];
  for (int i = 0; i < 4; ++i) {
    column[i] = static_cast<std::size_t>(std::find(header.begin(), header.end(), names[i]) - header.begin());
    if (column[i] == header.size()) return;  // observations_from_table names what is missing
  }
  std::size_t normalised = 0;
  double largest = 0;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (rows[r].size() != header.size()) continue;  // observations_from_table names the row
    double n2 = 0;
    for (const std::size_t c : column) n2 += rows[r][c] * rows[r][c];
    const double norm = std::sqrt(n2), defect = std::abs(norm - 1);
    if (!(defect <= input_defect_bound))
      throw CsvError(path + ":" + std::to_string(lines[r]) + ": columns q_w..q_z: not a unit quaternion (to " +
                     format_number(input_defect_bound) + "): its length is " + format_number(norm));
    if (defect <= input_note_defect) continue;
    for (const std::size_t c : column) rows[r][c] /= norm;
    ++normalised;
    largest = std::max(largest, defect);
  }
  if (normalised > 0)
    adjustments.push_back({path, std::to_string(normalised) + " of " + std::to_string(rows.size()) +
                                     " quaternions normalised (largest ||q| - 1| " + format_defect(largest) + ")",
                           largest});
}

// A table's attitudes (R11..R33, when it has them all) made exact as in scenes: each within input_defect_bound of a
// rotation replaced by the nearest one, one adjustment for the file; beyond the bound a CsvError naming the line.
void make_attitudes_exact(const std::string& path, const std::vector<std::string>& header,
                          std::vector<std::vector<double>>& rows, const std::vector<int>& lines,
                          std::vector<InputAdjustment>& adjustments) {
  static constexpr std::string_view names[9] = {"R11", "R12", "R13", "R21", "R22", "R23", "R31", "R32", "R33"};
  std::size_t column[9];
  for (int e = 0; e < 9; ++e) {
    column[e] = static_cast<std::size_t>(std::find(header.begin(), header.end(), names[e]) - header.begin());
    if (column[e] == header.size()) return make_quaternions_exact(path, header, rows, lines, adjustments);
  }
  std::size_t projected = 0;
  double largest = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (rows[i].size() != header.size()) continue;  // observations_from_table names the row
    Mat3<double> R;
    for (int e = 0; e < 9; ++e) R(e / 3, e % 3) = rows[i][column[e]];
    const double defect = so3::orthogonality_error(R);
    if (!(defect <= input_defect_bound) || !(R.determinant() > 0))
      throw CsvError(path + ":" + std::to_string(lines[i]) + ": columns R11..R33: not a rotation matrix (to " +
                     format_number(input_defect_bound) + "): |R^T R - I| = " + format_number(defect) +
                     ", det R = " + format_number(R.determinant()));
    if (defect <= input_note_defect) continue;
    const Mat3<double> exact = nearest_rotation(R);
    for (int e = 0; e < 9; ++e) rows[i][column[e]] = exact(e / 3, e % 3);
    ++projected;
    largest = std::max(largest, defect);
  }
  if (projected > 0)
    adjustments.push_back({path, std::to_string(projected) + " of " + std::to_string(rows.size()) +
                                     " attitudes projected onto SO(3), the nearest rotations (largest |R^T R - I| " +
                                     format_defect(largest) + ")",
                           largest});
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
  // Rounded attitudes, quaternions and unit vectors are made exact as in scenes (read_rotation, read_unit_vector);
  // values exact to 1e-12 go to the library as given.
  if (R) {
    const Node Rn = o.at("R");
    const Mat3<double> given = Rn.mat3();
    obs = fit::Observation::attitude(
        t, so3::orthogonality_error(given) <= input_note_defect && given.determinant() > 0 ? given : read_rotation(Rn),
        sigma);
  } else if (q) {
    const Node qn = o.at("q");
    if (!qn.is_array() || qn.size() != 4) qn.fail("expected an array of 4 numbers (w, x, y, z), got " + describe(qn.value()));
    Eigen::Vector4d v;
    for (std::size_t i = 0; i < 4; ++i) v(static_cast<int>(i)) = qn.at(i).number();
    if (v.norm() == 0) qn.fail("the zero quaternion is not a rotation");
    const double defect = std::abs(v.norm() - 1);
    if (!(defect <= input_defect_bound))
      qn.fail("must be a unit quaternion (to " + format_number(input_defect_bound) + "), its length is " +
              format_number(v.norm()));
    if (defect > input_note_defect) {
      qn.adjusted(std::string("normalised (its length was 1 ") + (v.norm() < 1 ? "- " : "+ ") +
                      format_defect(defect) + ")",
                  defect);
      v.normalize();
    }
    obs = fit::Observation::attitude_quaternion(t, v, sigma);
  } else if (w) {
    obs = fit::Observation::angular_velocity(t, o.at("omega").vec3(), sigma);
  } else {
    obs = fit::Observation::body_axis(t, read_unit_vector(o.at("axis")), read_unit_vector(o.at("direction")), sigma);
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

// An unknown's name, one of fit::block_info's.
std::string read_unknown_name(const Node& n) {
  const std::string name = n.string();
  std::vector<std::string_view> names;
  for (const fit::BlockInfo& b : fit::block_info) names.push_back(b.name);
  if (std::find(names.begin(), names.end(), name) == names.end())
    n.fail("unknown unknown " + quoted_input(name) + did_you_mean(name, names) + " (known: " + fit::known_unknowns() +
           ")");
  return name;
}

fit::Unknown read_unknown(const Node& u) {
  if (u.value().is_string()) return fit::Unknown(read_unknown_name(u));
  if (!u.is_object()) u.fail("expected a name (\"initial.omega\", ...) or an object with \"name\", got " + describe(u.value()));
  u.allow_only({"name", "fixed", "lower", "upper"}, "an unknown");
  fit::Unknown out(read_unknown_name(u.at("name")));
  if (const auto f = u.find("fixed")) {
    if (!f->is_array()) f->fail("expected an array of component indices (0, 1, 2), got " + describe(f->value()));
    for (std::size_t i = 0; i < f->size(); ++i) out.fixed.push_back(static_cast<int>(f->at(i).integer(0, 2)));
  }
  const double inf = std::numeric_limits<double>::infinity();
  if (const auto l = u.find("lower")) out.lower = read_bounds(*l, -inf);
  if (const auto h = u.find("upper")) out.upper = read_bounds(*h, inf);
  return out;
}

}  // namespace

FitSpec parse_fit_document(const json& document, const std::string& file) {
  FitSpec spec;
  const Node root(document, "", file, &spec.adjustments);
  if (!root.is_object()) root.fail("expected an object (a scene with a \"fit\" section), got " + describe(document));
  const Node fit_node = root.at("fit");
  fit_node.allow_only({"unknowns", "observations", "continuation", "periodic", "solver", "covariance"}, "the fit section");

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
      else
        s->fail("unknown symmetry " + quoted_input(name) +
                did_you_mean(name, {"automatic", "none", "about_k", "body_omega"}) +
                " (known: automatic, none, about_k, body_omega)");
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
      if (table.sigma_attitude > 0) make_attitudes_exact(csv.string(), header, rows, lines, spec.adjustments);
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
  // limits.max_wall_seconds is the fit's budget (the solver's and every integration's); max_steps is a run's.
  spec.options.solver.max_seconds = spec.periodic_options.solver.max_seconds = spec.scene.max_wall_seconds;
  if (spec.scene.max_steps > 0)
    root.at("limits").at("max_steps").fail("a fit's integrations take the steps its data need: use "
                                           "/limits/max_wall_seconds or /fit/solver/max_iterations to bound a fit");
  spec.periodic_options.stepper = spec.scene.options;
  return spec;
}

FitSpec read_fit_file(const std::string& file) { return parse_fit_document(read_json_file(file), file); }

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

}  // namespace lgi::app
