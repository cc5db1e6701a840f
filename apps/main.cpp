// lgi — the command: run scene files, list what lgi knows.
//
//   lgi run SCENE [-o FILE] [-q] [--checkpoint CK [--checkpoint-every N|Ns]]
//                                    integrate a scene; CSV to FILE (or stdout), a summary on stderr
//   lgi run --resume CK [-o FILE] [-q]   continue a stopped run from its checkpoint, bit for bit
//   lgi fit FITFILE [-o FILE] [-v]   fit initial conditions and parameters to observations: runs lgi-fit from
//                                    this executable's directory (apps/fit_main.cpp, apps/fit_command.hpp)
//   lgi sweep SWEEPFILE -o FILE [--threads N] [--shard i/N] [--no-batch]   run a scene's members, one CSV row each
//   lgi merge PART... -o FILE        the shards of a sweep into the serial run's file (apps/sweep_command.hpp)
//   lgi list [--markdown]            problems and methods, with each method's order and structure
//
// Exit status: 0 success; 1 bad command line, scene or checkpoint (one message naming the file, JSON path and
// problem; nothing written, no existing file touched); 2 the integration failed (a step did not converge, was not
// finite, or the adaptive step size underflowed; the Euler-angle top left its domain) — the time, the step and the
// last good state on stderr; 3 an output could not be written (a full disk, ...) or the system refused a resource;
// 4 internal error; 5 (lgi fit) the solution is not usable (the result is written, with "usable": false); 6 a budget
// stopped the run (scene "limits": max_steps, max_wall_seconds); 128 + signal when interrupted by SIGINT or SIGTERM
// (seen within about 10 ms of work, or one step).
// `lgi run` after 2, 3, 6 or 128 + signal: -o FILE holds the rows written so far (3: those that reached the disk
// whole), renamed into place; after 2, 6 and 128 + signal its last row is the last good state (no row holds a NaN).
// With --checkpoint, 6 and 128 + signal also leave a checkpoint CK, and 3 keeps the last one written, that
// `lgi run --resume CK` continues to the very output an uninterrupted run writes (apps/runner_checkpoint.hpp).
// Outputs that are not regular files (-o -, /dev/null, a FIFO) are streamed to and never replaced
// (apps/output_file.hpp); --checkpoint never replaces or removes a file that is not this run's checkpoint.
// lgi run is single-threaded: the same scene gives the same bytes on every run.
#include "auto_method.hpp"
#include "hashing.hpp"
#include "plugin_loader.hpp"
#include "registry.hpp"
#include "run_messages.hpp"
#include "runner.hpp"
#include "scene.hpp"
#include "command.hpp"
#include "command_line.hpp"
#include "sweep_command.hpp"
#include "view.hpp"

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
#include <new>
#include <system_error>
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

// SIGINT and SIGTERM stop the run at the next monitor call (about every 10 ms of work) instead of killing the
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
  bool progress = false;  // --progress: progress lines also when stderr is not a terminal
  bool error_estimate = false;  // --error-estimate: a second run estimates the error at t_end (runner.hpp)
  bool no_error_estimate = false;  // --no-error-estimate: none for "auto" either
  double tol = 0;  // --tol: "method": "auto" with this tolerance in place of the scene's integrator
  bool tol_given = false;
  std::string html;  // --html: the page of lgi view of the rows written to -o
};

struct ViewCommandOptions {
  std::string csv, output, scene;
  int axis = 3;
  std::size_t max_frames = 20000;
  bool quiet = false;
};

// `lgi view RUN.csv [-o PAGE.html] [--scene SCENE]` (view.hpp).
int view_command(const ViewCommandOptions& cmd) {
  lgi::app::ViewInput input;
  input.csv = cmd.csv;
  input.axis = cmd.axis;
  input.max_frames = cmd.max_frames;
  std::vector<std::string> inputs;
  if (!cmd.scene.empty()) {
    try {
      input.body = lgi::app::view_body(lgi::app::load_scene(cmd.scene));
    } catch (const lgi::app::InputError& e) {
      return fail(exit_bad_input, e.what());
    }
    inputs.push_back(cmd.scene);
  }
  return lgi::app::write_view(input, cmd.output, inputs, LGI_VERSION, cmd.quiet);
}

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
// run stopped by a signal, a budget or a failed write renamed its rows into place), whichever has the bytes the
// checkpoint counts with their hashes. Empty if neither.
std::string find_rows(const lgi::app::Checkpoint& ck) {
  for (const std::string& path : {ck.output.partial, ck.output.target}) {
    struct stat st {};
    if (stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) continue;  // (opening a FIFO would block)
    const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) continue;
    std::uint64_t head = 0, tail = 0;
    const bool ok = fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && static_cast<std::uint64_t>(st.st_size) >= ck.output.bytes &&
                    lgi::app::output_hashes(fd, ck.output.bytes, head, tail) && head == ck.output.head_hash &&
                    tail == ck.output.tail_hash;
    close(fd);
    if (ok) return path;
  }
  return {};
}

// Copies the first `bytes` bytes of `from` to `to`, as whole records (the rows end in '\n').
bool copy_prefix(const std::string& from, std::uint64_t bytes, lgi::app::OutputFile& to) {
  std::FILE* in = std::fopen(from.c_str(), "rb");
  if (!in) return false;
  std::vector<char> buffer(1 << 20);
  std::string pending;  // the part of a row that reached the end of a buffer
  while (bytes > 0) {
    const std::size_t n = std::fread(buffer.data(), 1, std::min<std::uint64_t>(bytes, buffer.size()), in);
    if (n == 0) break;
    bytes -= n;
    pending.append(buffer.data(), n);
    const std::size_t end = pending.rfind('\n') + 1;  // 0 when there is no line end
    if (end > 0 && !to.write_record(std::string_view(pending.data(), end))) break;
    pending.erase(0, end);
  }
  std::fclose(in);
  return bytes == 0 && pending.empty() && !to.failed();
}

// A run's temporary output file (OutputFile: ".NAME.tmp-XXXXXX").
bool is_temporary(const std::string& path) {
  const std::string name = std::filesystem::path(path).filename().string();
  return name.size() > 1 && name[0] == '.' && name.find(".tmp-") != std::string::npos;
}

// Removes what a SIGKILLed earlier run of this checkpoint may have left: a checkpoint is written atomically
// through ".NAME.tmp-XXXXXX" beside it (checkpoint.cpp), and a kill between its creation and the rename leaves that
// file. Only files whose bytes are those a checkpoint begins with are removed. Called when the run the checkpoint
// belongs to is complete.
void remove_stale_temporaries(const std::string& checkpoint) {
  namespace fs = std::filesystem;
  const fs::path p(checkpoint);
  const std::string prefix = fs::path(lgi::app::temporary_prefix(checkpoint)).filename().string();  // ".NAME.tmp-"
  std::error_code ec;
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (name.size() == prefix.size() + 6 && name.compare(0, prefix.size(), prefix) == 0 &&
        lgi::app::is_checkpoint_temporary(it->path().string()))
      fs::remove(it->path(), ec);
  }
}

// The time of the last row of a CSV file (its first column), or "" when it has none.
std::string last_row_time(const lgi::app::OutputFile& out) {
  const std::uint64_t size = out.bytes_in_file();
  if (out.streamed() || size == 0) return {};
  const std::uint64_t span = std::min<std::uint64_t>(size, 4096);
  std::string tail(span, '\0');
  if (pread(out.fd(), tail.data(), span, static_cast<off_t>(size - span)) != static_cast<ssize_t>(span)) return {};
  tail.pop_back();  // the final '\n'
  const std::size_t start = tail.rfind('\n') + 1;
  const std::string t = tail.substr(start, tail.find(',', start) - start);
  if (t == "t") return {};  // the header: no rows
  char* end = nullptr;
  const double x = std::strtod(t.c_str(), &end);
  return end == t.c_str() + t.size() ? lgi::app::format_number(x) : t;
}

// Why --checkpoint CK cannot be used, or "" (a new file, or the checkpoint this run resumes from).
std::string checkpoint_path_problem(const std::string& checkpoint, const std::string& output, const std::string& resume) {
  if (lgi::app::is_streamed_path(checkpoint))
    return "--checkpoint " + checkpoint + ": not a regular file (a checkpoint is written beside it and renamed into place)";
  struct stat st {};
  const bool exists = stat(checkpoint.c_str(), &st) == 0;
  if (exists && S_ISDIR(st.st_mode)) return "--checkpoint " + checkpoint + ": a directory";
  if (checkpoint == output || lgi::app::same_file(checkpoint, output))
    return "--checkpoint " + checkpoint + " and -o name the same file";
  if (!exists || (!resume.empty() && lgi::app::same_file(checkpoint, resume))) return {};
  try {
    const lgi::app::Checkpoint other = lgi::app::read_checkpoint(checkpoint);
    return "--checkpoint " + checkpoint + ": holds the checkpoint of a stopped run of " + other.scene_file +
           " (t = " + lgi::app::format_number(other.t) + "): continue it with lgi run --resume " + checkpoint +
           ", or remove it to start afresh";
  } catch (const lgi::app::InputError&) {
    return "--checkpoint " + checkpoint + ": the file exists and is not a checkpoint of lgi run; lgi does not replace "
           "it (give another name)";
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
  if (!resuming && !cmd.checkpoint.empty() && (cmd.output.empty() || lgi::app::is_streamed_path(cmd.output)))
    return fail(exit_bad_input, "--checkpoint needs -o FILE, a regular file: a checkpoint continues the rows of an output "
                                "file");
  if (cmd.tol_given && resuming)
    return fail(exit_bad_input, "--tol applies to a SCENE: a resumed run continues with its own method");
  if (cmd.tol_given && !(cmd.tol >= lgi::app::auto_min_tolerance && cmd.tol <= lgi::app::auto_max_tolerance))
    return fail(exit_bad_input, "--tol: must be in [" + format_number(lgi::app::auto_min_tolerance) + ", " +
                                    format_number(lgi::app::auto_max_tolerance) + "], got " + format_number(cmd.tol));
  if (cmd.error_estimate && cmd.no_error_estimate)
    return fail(exit_bad_input, "give --error-estimate or --no-error-estimate, not both");
  if (!cmd.html.empty() && cmd.output.empty() && !resuming)
    return fail(exit_bad_input, "--html needs -o FILE: the page is made from the rows written there");
  try {
    if (resuming) {
      resume = lgi::app::read_checkpoint(cmd.resume);
      document = resume.scene;
      scene = lgi::app::parse_scene(document, resume.scene_file);
      if (resume.method != scene.method->traits.name)
        return fail(exit_bad_input, cmd.resume + ": /method: \"" + resume.method + "\" is not the scene's method \"" +
                                        std::string(scene.method->traits.name) + "\"");
      // The files the scene reads (a torque table) must be those the run started with.
      for (const auto& [file, digest] : scene.problem->input_files()) {
        const auto was = std::find_if(resume.inputs.begin(), resume.inputs.end(),
                                      [&](const auto& in) { return in.first == file; });
        if (was != resume.inputs.end() && was->second == digest) continue;
        const std::string then = was == resume.inputs.end() ? "none recorded" : lgi::app::hex64(was->second);
        return fail(exit_bad_input, file + ": changed since the checkpoint " + cmd.resume + " was written (fnv1a64 " +
                                        then + " then, " + lgi::app::hex64(digest) +
                                        " now): the resumed run would not continue the same motion");
      }
    } else {
      document = lgi::app::read_json_file(cmd.scene_file);
      // --tol: the scene's integrator replaced by "auto" (recorded so in checkpoints: a resume chooses the same).
      // Rows every N steps of the scene's dt become rows every N dt.
      if (cmd.tol_given && document.is_object()) {
        lgi::app::json& out = document["output"];
        if (out.is_object() && out.contains("every") && out["every"].is_number() && document["integrator"].is_object() &&
            document["integrator"].contains("dt") && document["integrator"]["dt"].is_number()) {
          out["interval"] = out["every"].get<double>() * document["integrator"]["dt"].get<double>();
          out.erase("every");
        }
        if (out.is_null()) document.erase("output");
        document["integrator"] = lgi::app::json{{"method", "auto"}, {"tolerance", cmd.tol}};
      }
      scene = lgi::app::parse_scene(document, cmd.scene_file);
    }
  } catch (const lgi::app::InputError& e) {
    return fail(exit_bad_input, e.what());
  }
  // Input made exact where it was further off than single precision's rounding: said before the run, also with
  // -q (the summary lists every change).
  if (!resuming)
    for (const lgi::app::InputAdjustment& a : scene.adjustments)
      if (a.defect > lgi::app::input_warn_defect)
        std::fprintf(stderr, "lgi: warning: %s: %s: %s\n", cmd.scene_file.c_str(), a.where.c_str(), a.what.c_str());
  const std::string output = resuming && cmd.output.empty() ? resume.output.target : cmd.output;
  const std::string checkpoint = resuming && cmd.checkpoint.empty() ? cmd.resume : cmd.checkpoint;
  if (!cmd.html.empty() && lgi::app::is_streamed_path(output))
    return fail(exit_bad_input, "--html needs -o FILE, a regular file: the page is made from the rows written there, "
                                "and " + output + " is not one");
  if (!cmd.html.empty() && (cmd.html == output || lgi::app::same_file(cmd.html, output)))
    return fail(exit_bad_input, "--html " + cmd.html + " is the -o file: give the page a name of its own");
  if (resuming && lgi::app::is_streamed_path(output))
    return fail(exit_bad_input, "--resume: -o " + output + " is not a regular file: a resumed run continues the rows of "
                                "an output file");
  if (!checkpoint.empty()) {
    if (const std::string problem = checkpoint_path_problem(checkpoint, output, cmd.resume); !problem.empty())
      return fail(exit_bad_input, problem);
  }
  const std::string& input = resuming ? cmd.resume : cmd.scene_file;
  if (!output.empty() && !lgi::app::is_streamed_path(output) && lgi::app::same_file(output, input))
    return fail(exit_bad_input, "-o " + output + " is the " + (resuming ? "checkpoint" : "scene file") +
                                    " itself: lgi does not replace its input");
  if (const std::string why = lgi::app::output_replaces_input(scene, output); !why.empty())
    return fail(exit_bad_input, why);
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

  std::unique_ptr<lgi::app::OutputFile> out;
  try {
    out = std::make_unique<lgi::app::OutputFile>(output.empty() ? std::string("-") : output);
  } catch (const lgi::app::OutputError& e) {
    return fail(exit_io_error, e.what());
  }
  catch_interrupts();
  lgi::app::RunOptions options;
  options.csv = out.get();
  options.progress = lgi::app::progress_mode(cmd.quiet, cmd.progress);
  options.stop = &g_signal;
  options.checkpoint_path = checkpoint;
  options.checkpoint_every_steps = every_steps;
  options.checkpoint_every_seconds = every_seconds;
  options.scene_document = document;
  options.version = LGI_VERSION;
  options.output = {output, out->temp_path()};
  std::string checkpoint_checksum;  // the last checkpoint this invocation wrote
  bool resume_refused = false;      // the resumed checkpoint could not be moved to the new rows: nothing changed
  if (resuming) {
    // The rows so far into the new temporary file, on disk, and a checkpoint that points at it before the old
    // temporary file goes: a SIGKILL at any moment leaves a checkpoint whose rows exist.
    if (!copy_prefix(rows, resume.output.bytes, *out) || !out->sync())
      return fail(exit_io_error, output + ": cannot copy the rows so far from " + rows + ": " +
                                     (out->failed() ? out->error_text() : std::string(std::strerror(errno))) +
                                     " (nothing changed: " + cmd.resume + " still resumes the run)");
    // Once the runner has checked the checkpoint against the scene and the stepper: the checkpoint moves to the new
    // rows, and only then the old temporary file goes. A checkpoint refused by those checks changes nothing.
    options.resume_accepted = [&](std::string& error) {
      lgi::app::Checkpoint moved = resume;
      moved.output.target = output;
      moved.output.partial = out->temp_path();
      moved.every_steps = every_steps;
      moved.every_seconds = every_seconds;
      if (!lgi::app::write_checkpoint(checkpoint, moved, LGI_VERSION, error, &checkpoint_checksum)) {
        resume_refused = true;
        return false;
      }
      out->keep_temporary();  // the moved checkpoint names it
      if (rows != output && is_temporary(rows)) std::remove(rows.c_str());
      return true;
    };
    options.resume = &resume;
    options.resume_path = cmd.resume;
  }
  lgi::app::RunReport report;
  try {
    report = lgi::app::run_scene(scene, options);
  } catch (const lgi::app::InputError& e) {  // a checkpoint that does not fit the stepper or the scene
    return fail(exit_bad_input, e.what());   // (nothing changed: it was refused before the resume moved anything)
  }
  if (resume_refused)
    return fail(exit_io_error, checkpoint + ": cannot write the checkpoint: " + report.checkpoint_error +
                                   " (nothing changed: " + cmd.resume + " still resumes the run)");
  out->flush();  // the last rows: a failure here is a failed write like any other
  if (!report.checkpoint_checksum.empty()) checkpoint_checksum = report.checkpoint_checksum;
  const std::string& name = input;
  const lgi::IntegrationSummary& s = report.summary;
  const std::string where = out->display_name();

  // A failed write: the rows that reached the file whole are kept under the output's name, and the last checkpoint
  // (which counts only rows that reached the file) continues the run once the cause is fixed.
  if (report.write_failed || out->failed()) {
    const std::string cause = out->failed() ? out->error_text() : report.checkpoint_error;
    const bool whole = out->truncate_to_last_record();
    const std::string last_t = last_row_time(*out);
    const bool kept = whole && out->commit();
    if (!kept) out->keep_temporary();  // the message names it
    std::string message = where + ": write error (" + cause + ") at t = " + format_number(s.t) + "; ";
    if (out->streamed()) message += "the rows before it were written";
    else if (kept) message += where + " holds " + (last_t.empty() ? "no rows" : "the rows to t = " + last_t) + " (whole rows only)";
    else message += "the rows so far are in " + out->temp_path() + (whole ? "" : " (its last row may be cut)");
    if (!checkpoint_checksum.empty())
      message += "; checkpoint " + checkpoint + " continues the run once the cause is fixed (lgi run --resume " +
                 checkpoint + ")";
    return fail(exit_io_error, message);
  }
  if (report.stop_reason == lgi::app::StopReason::write_failed) {  // the rows are whole, a checkpoint failed
    const bool kept = out->commit();
    if (!kept) out->keep_temporary();  // the message names it
    std::string message = checkpoint + ": cannot write the checkpoint (" + report.checkpoint_error +
                          "): the run stopped at t = " + format_number(s.t) + "; " +
                          (kept ? where + " holds the rows to there" : "the rows are in " + out->temp_path());
    if (!checkpoint_checksum.empty())
      message += "; the previous checkpoint in " + checkpoint + " continues the run (lgi run --resume " + checkpoint + ")";
    return fail(exit_io_error, message);
  }
  if (!out->commit()) {
    if (out->streamed()) return fail(exit_io_error, where + ": cannot write the output: " + out->error_text());
    out->keep_temporary();  // the message names it
    return fail(exit_io_error, where + ": cannot write the output: " + out->error_text() + "; the rows are in " +
                                   out->temp_path());
  }
  if (!cmd.quiet) std::fputs(lgi::app::brief_report(scene, report).c_str(), stderr);
  // The page of lgi view (view.hpp) of the rows kept, a complete run's or an incomplete one's.
  if (!cmd.html.empty() && report.has_rows) {
    lgi::app::ViewInput view;
    view.csv = output;
    view.body = lgi::app::view_body(scene);
    if (const int status = lgi::app::write_view(view, cmd.html, {input}, LGI_VERSION, cmd.quiet); status != 0)
      return status;
  }
  // The estimate: asked for, or by default for "auto" (whose tolerance it checks).
  const double tolerance = scene.auto_choice.tolerance;
  if (!cmd.quiet && (cmd.error_estimate || (tolerance > 0 && !cmd.no_error_estimate))) {
    const lgi::app::ErrorEstimate e = lgi::app::estimate_error(scene, report, &g_signal);
    std::fputs(lgi::app::error_estimate_line(e, report).c_str(), stderr);
    // auto aims at the tolerance and stays within 10× of it on regular motions (auto_method.hpp): beyond, a warning.
    if (tolerance > 0 && e.available && e.R + e.Omega > 10 * tolerance)
      std::fprintf(stderr, "lgi: warning: %s: the estimated error %.1e exceeds 10 x the tolerance %s (auto assumes an "
                           "error growing linearly in time, which chaotic motion does not obey); the rows are written\n",
                   name.c_str(), e.R + e.Omega, format_number(tolerance).c_str());
  }
  if (g_signal != 0 && s.status == lgi::RunStatus::completed)  // interrupted during the estimate: the rows are whole
    return fail(128 + g_signal, name + ": interrupted during the error estimate (the run completed and its output is written)");

  if (s.status == lgi::RunStatus::completed) {
    if (!checkpoint.empty()) {  // the run is complete: nothing to resume; remove only what this run wrote
      if (lgi::app::is_own_checkpoint(checkpoint, checkpoint_checksum)) std::remove(checkpoint.c_str());
      remove_stale_temporaries(checkpoint);
    }
    if (report.rows_not_finite > 0)
      return fail(exit_run_failed, name + ": " + std::to_string(report.rows_not_finite) +
                                       " rows were not written: a column was not finite (energy or an invariant "
                                       "overflowed), the first at t = " + format_number(report.first_not_finite_t));
    return 0;
  }

  // An incomplete run: where, why, what was kept, how to continue.
  auto [status, message] = lgi::app::incomplete_run(scene, report, g_signal);
  const std::string holds = out->streamed() ? where + " got" : where + " holds";
  if (report.has_rows)
    message += "; " + holds + " the rows to t = " + format_number(s.t) +
               (report.final_row ? ", the last one the last good state" : "") + " (incomplete)";
  else
    message += "; " + holds + " no rows (the header only)";
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
  else if (checkpoint.empty() && (report.stop_reason == lgi::app::StopReason::signal ||
                                  report.stop_reason == lgi::app::StopReason::max_steps ||
                                  report.stop_reason == lgi::app::StopReason::max_wall_seconds))
    message += "; to be able to continue a stopped run, give it --checkpoint CK (with -o FILE): lgi run --resume CK "
               "then goes on";
  return fail(status, name + ": " + message);
}

int list_command(bool markdown) {
  using lgi::app::method_registry;
  using lgi::app::problem_registry;
  const auto yes = [](bool b) { return b ? "yes" : "no"; };
  // "2", or "2 (free body 8)" where the method is of higher order on torque-free problems
  const auto order = [](const lgi::MethodTraits& t) {
    if (t.exact_solution) return std::string("exact");
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
    std::string methods;
    if (p.methods.size() == method_registry().size())
      methods = "all";
    else
      for (const auto& m : p.methods) methods += (methods.empty() ? "" : ", ") + std::string(m);
    std::printf("  %-*s %s\n  %-*s keys: %s\n  %-*s methods: %s\n", pw, std::string(p.name).c_str(),
                std::string(p.summary).c_str(), pw, "", keys.c_str(), pw, "", methods.c_str());
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

// `lgi fit ARGS...`: execs lgi-fit ARGS... from the directory of this executable (the build directory, or the
// installation's bin/); returns only when that fails.
int forward_fit(int argc, char** argv) {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  const std::filesystem::path program = self.parent_path() / "lgi-fit";
  if (ec || ::access(program.c_str(), X_OK) != 0)
    return fail(exit_bad_input, "lgi fit: this lgi has no fitting: " + program.string() +
                                    " is not there (it is built with Ceres: cmake --build BUILD --target lgi_fit_exe)");
  int i = 1;
  while (i < argc && std::strcmp(argv[i], "fit") != 0) ++i;
  std::vector<char*> args{const_cast<char*>(program.c_str())};
  for (int j = i + 1; j < argc; ++j) args.push_back(argv[j]);
  args.push_back(nullptr);
  std::fflush(nullptr);
  ::execv(program.c_str(), args.data());
  return fail(exit_io_error, "lgi fit: cannot run " + program.string() + ": " + std::strerror(errno));
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
  run->add_flag("--error-estimate", run_options.error_estimate,
                "Estimate the error at t_end by a second run (fixed steps: 2 dt, Richardson; adaptive: tolerances / 1000); "
                "the default with method auto");
  run->add_flag("--no-error-estimate", run_options.no_error_estimate, "No error estimate (method auto makes one otherwise)");
  CLI::Option* tol_option = run->add_option("--tol", run_options.tol,
                  "Run with \"method\": \"auto\" at this tolerance (R's angle + |dOmega|/|Omega| at every output), in "
                  "place of the scene's integrator");
  run->add_flag("--progress", run_options.progress,
                "Progress on stderr also when it is not a terminal (a line every 2 s; on a terminal it always shows)");
  run->add_option("--checkpoint", run_options.checkpoint,
                  "Write checkpoints to CK (needs -o): periodically, and where a signal or a budget stops the run");
  run->add_option("--checkpoint-every", run_options.checkpoint_every,
                  "Checkpoint interval: N steps, or Ns seconds of wall time (default 60s)");
  run->add_option("--html", run_options.html,
                  "Also write the page of lgi view of the run to PAGE.html (needs -o FILE; docs/viewer.md)");
  run->add_option("--resume", run_options.resume,
                  "Continue the run checkpoint CK stopped, bit for bit (no SCENE; -o defaults to the run's FILE)");

  auto* fit = app.add_subcommand("fit", "Fit initial conditions and parameters to observations: result JSON to stdout (or -o FILE)");
  lgi::app::FitCommandOptions fit_options;  // parsed here for help and errors; lgi-fit runs it (forward_fit)
  lgi::app::add_fit_options(*fit, fit_options);

  auto* sweep = app.add_subcommand("sweep", "Run a sweep file's members (grid or seeded random): one CSV row each");
  lgi::app::SweepCommandOptions sweep_options;
  sweep->add_option("SWEEPFILE", sweep_options.sweep_file, "Sweep file: a scene plus a \"sweep\" section (docs/sweep.md)")
      ->required();
  sweep->add_option("-o,--output", sweep_options.output, "Write the CSV to FILE (atomically: no file on bad input)")
      ->required();
  sweep->add_option("--threads", sweep_options.threads, "Worker threads (0: all cores; default 1); same bytes for any N");
  sweep->add_option("--shard", sweep_options.shard, "Run the members m with m mod N = i and write a part for lgi merge");
  sweep->add_flag("-q,--quiet", sweep_options.quiet, "Nothing on stderr but errors");
  sweep->add_flag("--progress", sweep_options.progress,
                  "Progress on stderr also when it is not a terminal (a line every 2 s; on a terminal it always shows)");
  bool no_batch = false;
  sweep->add_flag("--no-batch", no_batch,
                  "Run members one by one even when the sweep qualifies for the batched LGVI kernel (same bytes)");

  auto* merge = app.add_subcommand("merge", "Merge the part files of lgi sweep --shard into the serial run's CSV");
  lgi::app::MergeCommandOptions merge_options;
  merge->add_option("PART", merge_options.parts, "The N part files of one sweep (any order)")->required();
  merge->add_option("-o,--output", merge_options.output, "Write the CSV to FILE (atomically)")->required();
  merge->add_flag("-q,--quiet", merge_options.quiet, "Nothing on stderr but errors");

  auto* view = app.add_subcommand("view", "Write one self-contained HTML page that animates a run in 3D (docs/viewer.md)");
  ViewCommandOptions view_options;
  view->add_option("RUN", view_options.csv, "The CSV of lgi run (t and R11..R33 or q_w..q_z)")->required();
  view->add_option("-o,--output", view_options.output,
                   "The page (default: RUN with .html; an existing file there is replaced only if lgi view wrote it)");
  view->add_option("--scene", view_options.scene, "The run's scene: the body drawn with its inertia, gravity shown");
  view->add_option("--axis", view_options.axis, "The body axis whose trace on the unit sphere is drawn (1, 2, 3; default 3)");
  view->add_option("--max-frames", view_options.max_frames,
                   "At most this many frames in the page (default 20000; longer runs are decimated, the page says how)");
  view->add_flag("-q,--quiet", view_options.quiet, "Nothing on stderr but errors");

  auto* list = app.add_subcommand("list", "List the problems and methods lgi knows, with their properties");
  bool markdown = false;
  list->add_flag("--markdown", markdown, "Print the method table as markdown (the README's table)");

  // Problem types from plugins (apps/plugin.hpp, docs/new_problem.md), for the commands that read scenes.
  std::vector<std::string> plugins;
  for (auto* sub : {run, fit, sweep, view, list})
    lgi::app::add_plugin_option(*sub, plugins);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // One line, as every other error: what is wrong, and where help is.
    const std::string commands = "run, fit, sweep, merge, view, list";
    if (argc < 2) return fail(exit_bad_input, "give a command: " + commands + " (lgi --help)");
    const std::string first = argv[1];
    bool known = false;
    for (const auto* sub : app.get_subcommands({})) known = known || sub->get_name() == first;
    if (!known && !first.empty() && first[0] != '-')
      return fail(exit_bad_input, "unknown command " + lgi::app::quoted_input(first) +
                                      lgi::app::did_you_mean(first, {"run", "fit", "sweep", "merge", "view", "list"}) + " (commands: " +
                                      commands + "; lgi --help)");
    std::string where = "lgi";
    for (const auto* sub : app.get_subcommands()) where += " " + sub->get_name();
    return fail(exit_bad_input, where + ": " + e.what() + " (" + where + " --help)");
  }
  if (fit->parsed()) return forward_fit(argc, argv);  // lgi-fit loads the plugins
  try {
    for (const std::string& plugin : plugins) lgi::app::load_plugin(plugin);
  } catch (const lgi::app::InputError& e) {
    return fail(exit_bad_input, e.what());
  }
  return lgi::app::guarded([&] {
    if (run->parsed()) {
      run_options.tol_given = tol_option->count() > 0;
      return run_command(run_options);
    }
    if (sweep->parsed()) {
      catch_interrupts();  // stop between members (and inside one) and remove the temporary output
      sweep_options.stop = &g_signal;
      sweep_options.batch = !no_batch;
      return lgi::app::sweep_command(sweep_options);
    }
    if (merge->parsed()) return lgi::app::merge_command(merge_options);
    if (view->parsed()) return view_command(view_options);
    if (list->parsed()) return list_command(markdown);
    return 0;
  });
}
