// lgi-fit — the program behind `lgi fit` (apps/fit_command.hpp): `lgi fit ARGS...` runs `lgi-fit ARGS...` from the
// directory of the lgi executable, so the command that runs scenes is built and installed without Ceres and without
// the fit's instantiations in Jet arithmetic (apps/fit_instances.hpp).
//
//   lgi-fit FITFILE [-o FILE] [-v] [-q] [--plugin FILE]...
//
// Exit statuses and messages: those of `lgi fit` (apps/main.cpp).
#include "command.hpp"
#include "fit_command.hpp"
#include "plugin_loader.hpp"
#include "scene.hpp"

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

int main(int argc, char** argv) {
  using namespace lgi::app;
  CLI::App app{"lgi fit: fit initial conditions and parameters to observations: result JSON to stdout (or -o FILE)",
               "lgi fit"};
  app.set_version_flag("--version", std::string("lgi ") + LGI_VERSION);
  FitCommandOptions options;
  app.add_option("FITFILE", options.fit_file, "Fit file: a scene plus a \"fit\" section (docs/fitting.md)")->required();
  app.add_option("-o,--output", options.output, "Write the result JSON to FILE (atomically: no file on bad input)");
  app.add_flag("-v,--verbose", options.verbose, "Ceres' full report and per-iteration progress on stderr");
  app.add_flag("-q,--quiet", options.quiet, "Nothing on stderr but errors");
  std::vector<std::string> plugins;
  app.add_option("--plugin", plugins, "Load the problem types of the lgi plugin FILE (repeatable)")
      ->type_name("FILE")
      ->allow_extra_args(false);  // one FILE per --plugin (repeat it): FITFILE after it is not a plugin
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return fail(exit_bad_input, std::string("lgi fit: ") + e.what() + " (lgi fit --help)");
  }
  try {
    for (const std::string& plugin : plugins) load_plugin(plugin);
  } catch (const InputError& e) {
    return fail(exit_bad_input, e.what());
  }
  return guarded([&] { return fit_command(options); });
}
