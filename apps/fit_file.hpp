// lgi/apps/fit_file.hpp — fit files (fit_command.cpp has the format) and observation tables, read and checked before
// anything is solved. Needs lgi::fit (Ceres).
#pragma once

#include "csv_reader.hpp"
#include "json_reader.hpp"
#include "scene.hpp"

#include <lgi/fit/fit.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace lgi::app {

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
  // What the readers changed to make the observations exact (registry.hpp, input_defect_bound): inline attitudes,
  // quaternions and unit vectors one by one, a table's attitudes as one line per file. The scene's own are in
  // scene.adjustments.
  std::vector<InputAdjustment> adjustments;
};

// Reads a fit file: the scene, the unknowns, the observations (inline or from a CSV file beside it), the solver.
// Throws InputError (naming the file and the JSON path) or CsvError (naming the CSV file and line).
FitSpec read_fit_file(const std::string& file);
FitSpec parse_fit_document(const json& document, const std::string& file);

// The JSON path (or CSV line) of a FitInputError's field ("observations[3].t", "unknowns[1].name", ...).
std::string where_of(const std::string& field, const FitSpec& spec);

}  // namespace lgi::app
