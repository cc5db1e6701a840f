// lgi — the command: run scene files, list what lgi knows.
//
//   lgi run SCENE [-o FILE] [-q]     integrate a scene; CSV to FILE (or stdout), a summary on stderr
//   lgi list [--markdown]            problems and methods, with each method's order and structure
//
// Exit status: 0 success; 1 bad command line or scene (one message naming the file, JSON path and
// problem; nothing written); 2 the integration failed (a step's status, with the time and the last good
// state reported; no output file is left); 3 the output could not be written; 4 internal error;
// 128 + signal when interrupted by SIGINT or SIGTERM (no output file is left).
#include "registry.hpp"
#include "runner.hpp"
#include "scene.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>

namespace {

constexpr int exit_bad_input = 1;
constexpr int exit_run_failed = 2;
constexpr int exit_io_error = 3;
constexpr int exit_internal_error = 4;

volatile std::sig_atomic_t g_signal = 0;
extern "C" void on_signal(int signal) { g_signal = signal; }

// SIGINT and SIGTERM stop the run at the next monitor call (every 1024 steps) instead of killing the
// process, so that the temporary output file is removed.
void catch_interrupts() {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

int fail(int status, const std::string& message) {
  std::fprintf(stderr, "lgi: error: %s\n", message.c_str());
  return status;
}

// An output file written under a temporary name beside the target and renamed into place only when
// everything succeeded: a failed run leaves no partial file.
class AtomicOutput {
 public:
  explicit AtomicOutput(const std::string& target) : target_(target) {
    const std::filesystem::path p(target);
    std::error_code ec;
    if (std::filesystem::is_directory(p, ec) || (!target.empty() && target.back() == '/'))
      throw std::runtime_error(target + ": cannot write the output file: it is a directory");
    temp_ = (p.has_parent_path() ? p.parent_path() / "" : std::filesystem::path()).string() + "." +
            p.filename().string() + ".tmp-XXXXXX";
    const int fd = mkstemp(temp_.data());
    if (fd < 0) throw std::runtime_error(target + ": cannot create the output file: " + std::strerror(errno));
    const mode_t mask = umask(0);  // mkstemp makes 0600; give the file the mode a plain create would
    umask(mask);
    fchmod(fd, 0666 & ~mask);
    file_ = fdopen(fd, "w");
    if (!file_) throw std::runtime_error(target + ": cannot open the output file: " + std::strerror(errno));
    static char buffer[1 << 16];
    std::setvbuf(file_, buffer, _IOFBF, sizeof buffer);
  }
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;
  ~AtomicOutput() {
    if (file_) std::fclose(file_);
    if (!committed_) std::remove(temp_.c_str());
  }
  std::FILE* file() const { return file_; }
  // Closes and renames into place; false (with errno) on failure.
  bool commit() {
    const bool ok = std::fflush(file_) == 0 && std::ferror(file_) == 0 && fsync(fileno(file_)) == 0;
    const bool closed = std::fclose(file_) == 0;
    file_ = nullptr;
    if (!ok || !closed) return false;
    if (std::rename(temp_.c_str(), target_.c_str()) != 0) return false;
    committed_ = true;
    return true;
  }

 private:
  std::string target_, temp_;
  std::FILE* file_ = nullptr;
  bool committed_ = false;
};

int run_command(const std::string& scene_file, const std::string& output, bool quiet) {
  lgi::app::Scene scene;
  try {
    scene = lgi::app::load_scene(scene_file);
  } catch (const lgi::app::InputError& e) {
    return fail(exit_bad_input, e.what());
  }
  std::unique_ptr<AtomicOutput> out;
  if (!output.empty()) {
    try {
      out = std::make_unique<AtomicOutput>(output);
    } catch (const std::exception& e) {
      return fail(exit_io_error, e.what());
    }
  }
  lgi::app::RunOptions options;
  options.csv = out ? out->file() : stdout;
  options.progress = !quiet && isatty(STDERR_FILENO);
  options.stop = &g_signal;
  catch_interrupts();
  const lgi::app::RunReport report = lgi::app::run_scene(scene, options);
  if (g_signal != 0) {
    const int signal = g_signal;
    return fail(128 + signal, scene_file + ": interrupted by " + (signal == SIGINT ? "SIGINT" : "SIGTERM") +
                                  " at t = " + lgi::app::format_number(report.summary.t) +
                                  (out ? "; no output file written" : ""));
  }

  if (report.summary.status != lgi::RunStatus::completed) {
    const lgi::State<double>& x = report.final_state;
    std::string where = "the step from t = " + lgi::app::format_number(report.summary.t) + " failed: " +
                        std::string(lgi::to_string(report.summary.step_status));
    if (report.summary.status == lgi::RunStatus::stopped) where = "stopped at t = " + lgi::app::format_number(report.summary.t);
    std::string hint;
    if (report.summary.step_status == lgi::StepStatus::not_converged)
      hint = " (try a smaller /integrator/dt, or raise /integrator/max_iterations)";
    else if (report.summary.step_status == lgi::StepStatus::non_finite)
      hint = " (the solution overflowed or the torque returned NaN; try a smaller /integrator/dt)";
    char state[256];
    std::snprintf(state, sizeof state, "; last good state: omega = (%.17g, %.17g, %.17g)", x.Omega(0), x.Omega(1),
                  x.Omega(2));
    if (!quiet) std::fputs(lgi::app::brief_report(scene, report).c_str(), stderr);
    return fail(exit_run_failed, scene_file + ": " + where + hint + state + (out ? "; no output file written" : ""));
  }
  if (report.write_failed) return fail(exit_io_error, (output.empty() ? "stdout" : output) + ": write error");
  if (out && !out->commit()) return fail(exit_io_error, output + ": cannot write the output file: " + std::strerror(errno));
  if (!out && std::fflush(stdout) != 0) return fail(exit_io_error, "stdout: write error");
  if (!quiet) std::fputs(lgi::app::brief_report(scene, report).c_str(), stderr);
  return 0;
}

int list_command(bool markdown) {
  using lgi::app::method_registry;
  using lgi::app::problem_registry;
  const auto yes = [](bool b) { return b ? "yes" : "no"; };
  // "2", or "2 (free body 8)" where the method is of higher order on torque-free problems
  const auto order = [](const lgi::MethodTraits& t) {
    std::string s = std::to_string(t.order);
    if (t.free_body_order != 0 && t.free_body_order != t.order) s += " (free body " + std::to_string(t.free_body_order) + ")";
    return s;
  };
  if (markdown) {
    std::printf("| method | order | symplectic | symmetric | explicit | R on SO(3) | momentum | description |\n");
    std::printf("|---|---|---|---|---|---|---|---|\n");
    for (const auto& m : method_registry()) {
      const auto& t = m.traits;
      std::printf("| `%s` | %s | %s | %s | %s | %s | %s | %s |\n", std::string(t.name).c_str(), order(t).c_str(), yes(t.symplectic),
                  yes(t.symmetric), yes(t.explicit_method), yes(t.exact_on_group), yes(t.preserves_momentum),
                  std::string(t.title).c_str());
    }
    return 0;
  }
  int pw = 4;
  for (const auto& p : problem_registry()) pw = std::max(pw, static_cast<int>(p.name.size()));
  std::printf("problems (scene \"problem.type\"):\n");
  for (const auto& p : problem_registry()) {
    std::string keys;
    for (const auto& k : p.keys) keys += (keys.empty() ? "" : ", ") + std::string(k);
    std::printf("  %-*s %s\n  %-*s keys: %s\n", pw, std::string(p.name).c_str(), std::string(p.summary).c_str(), pw, "",
                keys.c_str());
  }
  int mw = 4;
  for (const auto& m : method_registry()) mw = std::max(mw, static_cast<int>(m.traits.name.size()));
  std::printf("\nmethods (scene \"integrator.method\"):\n");
  int ow = 5;
  for (const auto& m : method_registry()) ow = std::max(ow, static_cast<int>(order(m.traits).size()));
  std::printf("  %-*s %-*s  %-10s %-9s %-8s %-10s %-8s %s\n", mw, "name", ow, "order", "symplectic", "symmetric", "explicit",
              "R on SO(3)", "momentum", "description");
  for (const auto& m : method_registry()) {
    const auto& t = m.traits;
    std::printf("  %-*s %-*s  %-10s %-9s %-8s %-10s %-8s %s\n", mw, std::string(t.name).c_str(), ow, order(t).c_str(), yes(t.symplectic),
                yes(t.symmetric), yes(t.explicit_method), yes(t.exact_on_group), yes(t.preserves_momentum),
                std::string(t.title).c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"lgi: Lie-group geometric integrators for rigid bodies"};
  app.set_version_flag("--version", std::string("lgi ") + LGI_VERSION);
  app.require_subcommand(1);

  auto* run = app.add_subcommand("run", "Integrate a scene file: CSV rows to stdout (or -o FILE), a summary on stderr");
  std::string scene_file, output;
  bool quiet = false;
  run->add_option("SCENE", scene_file, "Scene file (JSON, see README 'Scene files')")->required();
  run->add_option("-o,--output", output, "Write the CSV to FILE (atomically: no file on failure)");
  run->add_flag("-q,--quiet", quiet, "No summary and no progress on stderr");

  auto* list = app.add_subcommand("list", "List the problems and methods lgi knows, with their properties");
  bool markdown = false;
  list->add_flag("--markdown", markdown, "Print the method table as markdown (the README's table)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : exit_bad_input;
  }
  try {
    if (run->parsed()) return run_command(scene_file, output, quiet);
    if (list->parsed()) return list_command(markdown);
  } catch (const std::exception& e) {
    return fail(exit_internal_error, std::string("internal error: ") + e.what());
  }
  return 0;
}
