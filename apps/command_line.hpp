// lgi/apps/command_line.hpp — command-line options that more than one program of lgi declares (CLI11): `lgi fit`'s,
// parsed by `lgi` for help and errors and run by `lgi-fit` (fit_main.cpp), and --plugin.
#pragma once

#include "fit_command.hpp"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

namespace lgi::app {

// FITFILE, -o, -v, -q of `lgi fit` into `options`.
inline void add_fit_options(CLI::App& app, FitCommandOptions& options) {
  app.add_option("FITFILE", options.fit_file, "Fit file: a scene plus a \"fit\" section (docs/fitting.md)")->required();
  app.add_option("-o,--output", options.output, "Write the result JSON to FILE (atomically: no file on bad input)");
  app.add_flag("-v,--verbose", options.verbose, "Ceres' full report and per-iteration progress on stderr");
  app.add_flag("-q,--quiet", options.quiet, "Nothing on stderr but errors");
  app.add_flag("--progress", options.progress,
               "Progress on stderr also when it is not a terminal (a line every 2 s; on a terminal it always shows)");
}

// --plugin FILE, repeatable, into `plugins`: one FILE per occurrence (the scene after it is not a plugin).
inline void add_plugin_option(CLI::App& app, std::vector<std::string>& plugins) {
  app.add_option("--plugin", plugins, "Load the problem types of the lgi plugin FILE (repeatable)")
      ->type_name("FILE")
      ->allow_extra_args(false);
}

}  // namespace lgi::app
