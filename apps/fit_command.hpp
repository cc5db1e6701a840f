// lgi/apps/fit_command.hpp — `lgi fit FITFILE [-o RESULT.json] [-v] [-q]`: a scene plus a "fit" section in,
// fitted values with standard deviations out (README "Fitting", docs/fitting.md "The lgi fit command").
#pragma once

#include "json_reader.hpp"

#include <string>

namespace lgi::app {

struct FitCommandOptions {
  std::string fit_file;
  // When set, the fit is this document (parse_fit_document), not fit_file's contents: fit_file then only names it in
  // messages, and file names in it resolve from fit_file's directory (the current one for a name without one, such
  // as "<dict>"). The Python package's lgi.fit.
  const json* document = nullptr;
  std::string output;    // the result JSON; empty: stdout
  bool verbose = false;  // Ceres' full report and per-iteration progress on stderr
  bool quiet = false;    // nothing on stderr but errors
  bool progress = false;  // progress lines also when stderr is not a terminal (on a terminal it always shows)
};

// Runs the command; returns the exit status (command.hpp).
int fit_command(const FitCommandOptions& options);

}  // namespace lgi::app
