// lgi/apps/fit_command.hpp — `lgi fit FITFILE [-o RESULT.json] [-v] [-q]`: a scene plus a "fit" section in,
// fitted values with standard deviations out (README "Fitting", docs/fitting.md "The lgi fit command").
#pragma once

#include <string>

namespace lgi::app {

struct FitCommandOptions {
  std::string fit_file;
  std::string output;    // the result JSON; empty: stdout
  bool verbose = false;  // Ceres' full report and per-iteration progress on stderr
  bool quiet = false;    // nothing on stderr but errors
  bool progress = false;  // progress lines also when stderr is not a terminal (on a terminal it always shows)
};

// Runs the command; returns the exit status (command.hpp).
int fit_command(const FitCommandOptions& options);

}  // namespace lgi::app
