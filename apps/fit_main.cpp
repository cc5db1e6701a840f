// lgi-fit — the program behind `lgi fit` (apps/fit_command.hpp): `lgi fit ARGS...` runs `lgi-fit ARGS...` from the
// directory of the lgi executable, so the command that runs scenes is built and installed without Ceres and without
// the fit's instantiations in Jet arithmetic (apps/fit_instances.hpp).
//
//   lgi-fit FITFILE [-o FILE] [-v] [-q] [--plugin FILE]...
//
// Exit statuses and messages: those of `lgi fit` (apps/main.cpp).
#include "command.hpp"
#include "command_line.hpp"
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
  add_fit_options(app, options);
  std::vector<std::string> plugins;
  add_plugin_option(app, plugins);
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
