// lgi — the command: run scene files, list what lgi knows.
//
//   lgi run SCENE [-o FILE] [-q] [--checkpoint CK [--checkpoint-every N|Ns]]
//                                    integrate a scene; CSV to FILE (or stdout), a summary on stderr
//   lgi run --resume CK [-o FILE] [-q]   continue a stopped run from its checkpoint, bit for bit
//   lgi fit FITFILE [-o FILE] [-v]   fit initial conditions and parameters to observations (apps/fit_command.hpp)
//   lgi sweep SWEEPFILE -o FILE [--threads N] [--shard i/N] [--no-batch]   run a scene's members, one CSV row each
//   lgi merge PART... -o FILE        the shards of a sweep into the serial run's file (apps/sweep_command.hpp)
//   lgi list [--markdown]            problems and methods, with each method's order and structure
//
// Exit status: 0 success; 1 bad command line, scene or checkpoint (one message naming the file, JSON path and
// problem; nothing written); 2 the integration failed (a step did not converge, was not finite, or the
// adaptive step size underflowed; the Euler-angle top left its domain) — the time, the step and the last good
// state on stderr; 3 the output could not be written; 4 internal error; 5 (lgi fit) the solution is not usable
// (the result is written, with "usable": false); 6 a budget stopped the run (scene "limits": max_steps,
// max_wall_seconds); 128 + signal when interrupted by SIGINT or SIGTERM (checked every 1024 steps).
// `lgi run` after 2, 6 or 128 + signal: -o FILE holds the rows written so far, its last row the last good state
// (no row holds a NaN), renamed into place; with --checkpoint, 6 and 128 + signal also leave a checkpoint CK
// that `lgi run --resume CK` continues to the very output an uninterrupted run writes (apps/runner_checkpoint.hpp).
// lgi run is single-threaded: the same scene gives the same bytes on every run.
#include "registry.hpp"
#include "runner.hpp"
#include "scene.hpp"
#include "command.hpp"
#include "fit_command.hpp"
#include "sweep_command.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace {

using lgi::app::exit_bad_input;
using lgi::app::exit_internal_error;
using lgi::app::exit_io_error;
using lgi::app::exit_run_failed;
using lgi::app::fail;

volatile std::sig_atomic_t g_signal = 0;
extern "C" void on_signal(int signal) { g_signal = signal; }

// SIGINT and SIGTERM stop the run at the next monitor call (every 1024 steps) instead of killing the
// process, so that the rows so far are kept (and a checkpoint written, with --checkpoint).
void catch_interrupts() {
  struct sigaction action {};
  action.sa_handler = on_signal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

struct RunCommandOptions {
  std::string scene_file, output, checkpoint, checkpoint_every, resume;
  bool quiet = false;
};

// --checkpoint-every: "N" steps or "S s" seconds of wall time (e.g. 1000000, 30s, 0.5s).
bool parse_interval(const std::string& text, std::int64_t& steps, double& seconds) {
  if (text.empty()) return false;
  char* end = nullptr;
  if (text.back() == 's') {
    const std::string number = text.substr(0, text.size() - 1);
    seconds = std::strtod(number.c_str(), &end);
    return !number.empty() && end == number.c_str() + number.size() && std::isfinite(seconds) && seconds > 0;
  }
  if (text.find_first_not_of("0123456789") != std::string::npos || text.size() > 15) return false;
  steps = std::strtoll(text.c_str(), &end, 10);
  return steps > 0;
}

// The file holding a checkpoint's rows: its partial file (a SIGKILLed run's temporary file) or its target (a
// run stopped by a signal or a budget renamed its rows into place), whichever has the bytes the checkpoint
// counts with their hashes. Empty if neither.
std::string find_rows(const lgi::app::Checkpoint& ck) {
  for (const std::string& path : {ck.output.partial, ck.output.target}) {
    const int fd = open(path.c_str(), O_RDONLY);
    if (fd < 0) continue;
    struct stat st {};
    std::uint64_t head = 0, tail = 0;
    const bool ok = fstat(fd, &st) == 0 && static_cast<std::uint64_t>(st.st_size) >= ck.output.bytes &&
                    lgi::app::output_hashes(fd, ck.output.bytes, head, tail) && head == ck.output.head_hash &&
                    tail == ck.output.tail_hash;
    close(fd);
    if (ok) return path;
  }
  return {};
}

// Copies the first `bytes` bytes of `from` to `to`.
bool copy_prefix(const std::string& from, std::uint64_t bytes, std::FILE* to) {
  std::FILE* in = std::fopen(from.c_str(), "rb");
  if (!in) return false;
  std::vector<char> buffer(1 << 20);
  while (bytes > 0) {
    const std::size_t n = std::fread(buffer.data(), 1, std::min<std::uint64_t>(bytes, buffer.size()), in);
    if (n == 0 || std::fwrite(buffer.data(), 1, n, to) != n) break;
    bytes -= n;
  }
  std::fclose(in);
  return bytes == 0;
}

// A run's temporary output file (AtomicOutput: ".NAME.tmp-XXXXXX").
bool is_temporary(const std::string& path) {
  const std::string name = std::filesystem::path(path).filename().string();
  return name.size() > 1 && name[0] == '.' && name.find(".tmp-") != std::string::npos;
}

// Removes what a SIGKILLed earlier run of this checkpoint may have left: a checkpoint is written atomically
// through ".NAME.tmp-XXXXXX" beside it (runner.cpp), and a kill between its creation and the rename leaves that
// file. Called when the run the checkpoint belongs to is complete.
void remove_stale_temporaries(const std::string& checkpoint) {
  namespace fs = std::filesystem;
  const fs::path p(checkpoint);
  const std::string prefix = "." + p.filename().string() + ".tmp-";
  std::error_code ec;
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() == prefix.size() + 6 && name.compare(0, prefix.size(), prefix) == 0) fs::remove(it->path(), ec);
  }
}

int run_command(const RunCommandOptions& cmd) {
  using lgi::app::format_number;
  lgi::app::Scene scene;
  lgi::app::json document;
  lgi::app::Checkpoint resume;
  const bool resuming = !cmd.resume.empty();
  if (resuming == !cmd.scene_file.empty())
    return fail(exit_bad_input, "run: give a SCENE file, or --resume CHECKPOINT to continue a stopped run (not both)");
  std::int64_t every_steps = 0;
  double every_seconds = 0;
  if (!cmd.checkpoint_every.empty() && !parse_interval(cmd.checkpoint_every, every_steps, every_seconds))
    return fail(exit_bad_input, "--checkpoint-every: expected a number of steps (e.g. 100000) or of seconds (e.g. 30s), "
                                "got \"" + cmd.checkpoint_every + "\"");
  if (!resuming && cmd.checkpoint.empty() && !cmd.checkpoint_every.empty())
    return fail(exit_bad_input, "--checkpoint-every needs --checkpoint CHECKPOINT");
  if (!resuming && !cmd.checkpoint.empty() && cmd.output.empty())
    return fail(exit_bad_input, "--checkpoint needs -o FILE: a checkpoint continues the rows of an output file");
  try {
    if (resuming) {
      resume = lgi::app::read_checkpoint(cmd.resume);
      document = resume.scene;
      scene = lgi::app::parse_scene(document, resume.scene_file);
      if (resume.method != scene.method->traits.name)
        return fail(exit_bad_input, cmd.resume + ": /method: \"" + resume.method + "\" is not the scene's method \"" +
                                        std::string(scene.method->traits.name) + "\"");
    } else {
      document = lgi::app::read_json_file(cmd.scene_file);
      scene = lgi::app::parse_scene(document, cmd.scene_file);
    }
  } catch (const lgi::app::InputError& e) {
    return fail(exit_bad_input, e.what());
  }
  const std::string output = resuming && cmd.output.empty() ? resume.output.target : cmd.output;
  const std::string checkpoint = resuming && cmd.checkpoint.empty() ? cmd.resume : cmd.checkpoint;
  if (resuming && cmd.checkpoint_every.empty()) {
    every_steps = resume.every_steps;
    every_seconds = resume.every_seconds;
  }
  if (!checkpoint.empty() && every_steps == 0 && every_seconds == 0) every_seconds = 60;
  std::string rows;  // resuming: the file holding the rows so far
  if (resuming && (rows = find_rows(resume)).empty())
    return fail(exit_bad_input, cmd.resume + ": the rows it continues are in neither " + resume.output.partial + " nor " +
                                    resume.output.target + " (missing, shorter than " +
                                    std::to_string(resume.output.bytes) + " bytes, or changed)");

  std::unique_ptr<lgi::app::AtomicOutput> out;
  if (!output.empty()) {
    try {
      out = std::make_unique<lgi::app::AtomicOutput>(output);
    } catch (const std::exception& e) {
      return fail(exit_io_error, e.what());
    }
  }
  catch_interrupts();
  lgi::app::RunOptions options;
  options.csv = out ? out->file() : stdout;
  options.progress = !cmd.quiet && isatty(STDERR_FILENO);
  options.stop = &g_signal;
  options.checkpoint_path = checkpoint;
  options.checkpoint_every_steps = every_steps;
  options.checkpoint_every_seconds = every_seconds;
  options.scene_document = document;
  options.version = LGI_VERSION;
  if (out) options.output = {output, out->temp_path()};
  if (resuming) {
    // The rows so far into the new temporary file, on disk, and a checkpoint that points at it before the old
    // temporary file goes: a SIGKILL at any moment leaves a checkpoint whose rows exist.
    if (!copy_prefix(rows, resume.output.bytes, out->file()) || std::fflush(out->file()) != 0 ||
        fsync(fileno(out->file())) != 0)
      return fail(exit_io_error, output + ": cannot copy the rows so far from " + rows + ": " + std::strerror(errno));
    lgi::app::Checkpoint moved = resume;
    moved.output.target = output;
    moved.output.partial = out->temp_path();
    moved.every_steps = every_steps;
    moved.every_seconds = every_seconds;
    std::string error;
    if (lgi::app::write_checkpoint(checkpoint, moved, LGI_VERSION, error)) {
      if (rows != output && is_temporary(rows)) std::remove(rows.c_str());
    } else {
      std::fprintf(stderr, "lgi: warning: %s: cannot write the checkpoint (the run goes on): %s\n", checkpoint.c_str(),
                   error.c_str());
    }
    options.resume = &resume;
  }
  lgi::app::RunReport report;
  try {
    report = lgi::app::run_scene(scene, options);
  } catch (const lgi::app::InputError& e) {  // a checkpoint that does not fit the stepper
    return fail(exit_bad_input, e.what());
  }
  const std::string& name = resuming ? cmd.resume : cmd.scene_file;
  if (report.write_failed) return fail(exit_io_error, (output.empty() ? "stdout" : output) + ": write error");
  if (out && !out->commit()) return fail(exit_io_error, output + ": cannot write the output file: " + std::strerror(errno));
  if (!out && std::fflush(stdout) != 0) return fail(exit_io_error, "stdout: write error");
  if (!cmd.quiet) std::fputs(lgi::app::brief_report(scene, report).c_str(), stderr);

  const lgi::IntegrationSummary& s = report.summary;
  if (s.status == lgi::RunStatus::completed) {
    if (!checkpoint.empty()) {  // the run is complete: nothing to resume
      std::remove(checkpoint.c_str());
      remove_stale_temporaries(checkpoint);
    }
    if (report.rows_not_finite > 0)
      return fail(exit_run_failed, name + ": " + std::to_string(report.rows_not_finite) +
                                       " rows were not written: a column was not finite (energy or an invariant "
                                       "overflowed), the first at t = " + format_number(report.first_not_finite_t));
    return 0;
  }

  // An incomplete run: where, why, what was kept, how to continue.
  const std::string at = "t = " + format_number(s.t) + " after " + std::to_string(s.steps) + " steps";
  std::string message;
  int status = exit_run_failed;
  switch (report.stop_reason) {
    case lgi::app::StopReason::none:  // a failed step
      message = "the step from t = " + format_number(s.t) + " failed: " + std::string(lgi::to_string(s.step_status)) +
                " (step " + std::to_string(s.steps + 1) + " of the run";
      if (s.step_status == lgi::StepStatus::not_converged)
        message += "; try a smaller /integrator/dt, or raise /integrator/max_iterations)";
      else if (s.step_status == lgi::StepStatus::non_finite)
        message += "; the solution overflowed or the torque returned NaN; try a smaller /integrator/dt)";
      else if (s.step_status == lgi::StepStatus::step_size_underflow)
        message += "; raise /integrator/rtol or /integrator/atol)";
      else
        message += ")";
      break;
    case lgi::app::StopReason::left_domain:
      message = "stopped at " + at + ": the Euler angles left their domain (see the warning)";
      break;
    case lgi::app::StopReason::signal:
      status = 128 + g_signal;
      message = std::string("interrupted by ") + (g_signal == SIGINT ? "SIGINT" : "SIGTERM") + " at " + at;
      break;
    case lgi::app::StopReason::max_steps:
      status = lgi::app::exit_run_stopped;
      message = scene.max_steps > 0 ? "stopped by /limits/max_steps = " + std::to_string(scene.max_steps) + " at " + at
                                    : "stopped at " + at + ": the adaptive driver's limit of 1e9 attempted steps "
                                                           "(set /limits/max_steps)";
      break;
    case lgi::app::StopReason::max_wall_seconds:
      status = lgi::app::exit_run_stopped;
      message = "stopped by /limits/max_wall_seconds = " + format_number(scene.max_wall_seconds) + " at " + at;
      break;
  }
  const std::string where = out ? output + " holds" : "stdout got";
  if (report.has_rows)
    message += "; " + where + " the rows to t = " + format_number(s.t) +
               (report.final_row ? ", the last one the last good state" : "") + " (incomplete)";
  else
    message += "; " + where + " no rows (the header only)";
  const lgi::State<double>& x = report.final_state;
  char state[160];
  std::snprintf(state, sizeof state, "; last good state: omega = (%.17g, %.17g, %.17g)", x.Omega(0), x.Omega(1),
                x.Omega(2));
  message += state;
  if (!report.checkpoint_written.empty())
    message += "; checkpoint " + report.checkpoint_written + " (continue: lgi run --resume " + report.checkpoint_written + ")";
  else if (!checkpoint.empty() && report.stop_reason != lgi::app::StopReason::none &&
           report.stop_reason != lgi::app::StopReason::left_domain)
    message += "; no checkpoint: " + report.checkpoint_error;
  return fail(status, name + ": " + message);
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
  RunCommandOptions run_options;
  run->add_option("SCENE", run_options.scene_file, "Scene file (JSON, see README 'Scene files')");
  run->add_option("-o,--output", run_options.output,
                  "Write the CSV to FILE (a temporary file renamed into place at the end; an incomplete run's rows too, "
                  "with a non-zero exit status)");
  run->add_flag("-q,--quiet", run_options.quiet, "No summary and no progress on stderr");
  run->add_option("--checkpoint", run_options.checkpoint,
                  "Write checkpoints to CK (needs -o): periodically, and where a signal or a budget stops the run");
  run->add_option("--checkpoint-every", run_options.checkpoint_every,
                  "Checkpoint interval: N steps, or Ns seconds of wall time (default 60s)");
  run->add_option("--resume", run_options.resume,
                  "Continue the run checkpoint CK stopped, bit for bit (no SCENE; -o defaults to the run's FILE)");

  auto* fit = app.add_subcommand("fit", "Fit initial conditions and parameters to observations: result JSON to stdout (or -o FILE)");
  lgi::app::FitCommandOptions fit_options;
  fit->add_option("FITFILE", fit_options.fit_file, "Fit file: a scene plus a \"fit\" section (docs/fitting.md)")->required();
  fit->add_option("-o,--output", fit_options.output, "Write the result JSON to FILE (atomically: no file on bad input)");
  fit->add_flag("-v,--verbose", fit_options.verbose, "Ceres' full report and per-iteration progress on stderr");
  fit->add_flag("-q,--quiet", fit_options.quiet, "Nothing on stderr but errors");

  auto* sweep = app.add_subcommand("sweep", "Run a sweep file's members (grid or seeded random): one CSV row each");
  lgi::app::SweepCommandOptions sweep_options;
  sweep->add_option("SWEEPFILE", sweep_options.sweep_file, "Sweep file: a scene plus a \"sweep\" section (docs/sweep.md)")
      ->required();
  sweep->add_option("-o,--output", sweep_options.output, "Write the CSV to FILE (atomically: no file on bad input)")
      ->required();
  sweep->add_option("--threads", sweep_options.threads, "Worker threads (0: all cores; default 1); same bytes for any N");
  sweep->add_option("--shard", sweep_options.shard, "Run the members m with m mod N = i and write a part for lgi merge");
  sweep->add_flag("-q,--quiet", sweep_options.quiet, "Nothing on stderr but errors");
  bool no_batch = false;
  sweep->add_flag("--no-batch", no_batch,
                  "Run members one by one even when the sweep qualifies for the batched LGVI kernel (same bytes)");

  auto* merge = app.add_subcommand("merge", "Merge the part files of lgi sweep --shard into the serial run's CSV");
  lgi::app::MergeCommandOptions merge_options;
  merge->add_option("PART", merge_options.parts, "The N part files of one sweep (any order)")->required();
  merge->add_option("-o,--output", merge_options.output, "Write the CSV to FILE (atomically)")->required();
  merge->add_flag("-q,--quiet", merge_options.quiet, "Nothing on stderr but errors");

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
    if (run->parsed()) return run_command(run_options);
    if (fit->parsed()) return lgi::app::fit_command(fit_options);
    if (sweep->parsed()) {
      catch_interrupts();  // stop between members (and inside one) and remove the temporary output
      sweep_options.stop = &g_signal;
      sweep_options.batch = !no_batch;
      return lgi::app::sweep_command(sweep_options);
    }
    if (merge->parsed()) return lgi::app::merge_command(merge_options);
    if (list->parsed()) return list_command(markdown);
  } catch (const std::exception& e) {
    return fail(exit_internal_error, std::string("internal error: ") + e.what());
  }
  return 0;
}
