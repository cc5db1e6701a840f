// lgi/apps/runner.cpp — what every run shares and nothing instantiates per problem and method: the monitor, the
// checkpointer, the CSV header and columns, the brief report. run_scene (run_scene.cpp) dispatches to the runs of
// runner_impl.hpp, compiled in parts (runner_detail.hpp).
#include "runner_detail.hpp"

#include <lgi/core/invariants.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <type_traits>

namespace lgi::app {

namespace {

std::string relative(double initial, double final) {
  const double scale = std::abs(initial) > 0 ? std::abs(initial) : 1.0;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3e", std::abs(final - initial) / scale);
  return buf;
}

}  // namespace

Progress progress_mode(bool quiet, bool asked) {
  return quiet ? Progress::none : isatty(STDERR_FILENO) ? Progress::terminal : asked ? Progress::lines : Progress::none;
}

bool ProgressLine::due() const {
  if (mode_ == Progress::none) return false;
  const auto now = Clock::now();
  if (now - start_ < std::chrono::seconds(1)) return false;
  return !shown_ || now - last_ >= std::chrono::milliseconds(mode_ == Progress::terminal ? 250 : 2000);
}

void ProgressLine::show(const std::string& text) {
  if (mode_ == Progress::terminal)
    std::fprintf(stderr, "\r  %-100s", text.c_str());
  else
    std::fprintf(stderr, "lgi: progress: %s\n", text.c_str());
  std::fflush(stderr);
  last_ = Clock::now();
  shown_ = true;
}

void ProgressLine::clear() const {
  if (shown_ && mode_ == Progress::terminal) std::fprintf(stderr, "\r%104s\r", "");
}

// ---- the monitor ---------------------------------------------------------------------------------------------

namespace runner_detail {

SessionMonitor::SessionMonitor(const RunOptions& options, const Scene& scene, std::int64_t steps)
    : options_(options), max_wall_seconds_(scene.max_wall_seconds), t_end_(scene.t_end), checkpoint_steps_(steps) {}

namespace {
// A wall-clock duration for a progress line: "42 s", "3 min 07 s", "2 h 05 min".
std::string duration_text(double s) {
  char buf[48];
  if (!(s < 1e9)) return "?";
  const long n = std::lround(s);
  if (n < 60) std::snprintf(buf, sizeof buf, "%ld s", n);
  else if (n < 3600) std::snprintf(buf, sizeof buf, "%ld min %02ld s", n / 60, n % 60);
  else std::snprintf(buf, sizeof buf, "%ld h %02ld min", n / 3600, (n % 3600) / 60);
  return buf;
}
}  // namespace

void SessionMonitor::show_progress(std::int64_t steps, double t, double seconds) {
  const auto now = Clock::now();
  const double measured = std::chrono::duration<double>(now - first_).count();
  const double rate = measured > 0 ? static_cast<double>(steps - first_steps_) / measured : 0;
  const double done = t - first_t_, left = t_end_ - t;
  const std::string remaining = done > 0 ? ", about " + duration_text(measured * left / done) + " left" : "";
  char line[256];
  std::snprintf(line, sizeof line, "t = %.6g of %.6g (%.1f %%), %.3g steps/s, %s elapsed%s", t, t_end_, 100 * t / t_end_,
                rate, duration_text(seconds).c_str(), remaining.c_str());
  progress_.show(line);
}

SessionMonitor::Action SessionMonitor::check(std::int64_t steps, double t) {
  const auto now = Clock::now();
  if (first_steps_ < 0) {
    first_steps_ = steps;
    first_t_ = t;
    first_ = now;
  }
  const double since = std::chrono::duration<double>(now - last_check_).count();
  last_check_ = now;
  // The next call after about target_interval of work: at most twice as many steps, at least one.
  const double factor = since > 0 ? std::min(2.0, target_interval / since) : 2.0;
  stride_ = std::clamp<std::int64_t>(static_cast<std::int64_t>(static_cast<double>(stride_) * factor), 1, max_stride);
  if (options_.stop && *options_.stop != 0) {
    reason_ = StopReason::signal;
    return Action::stop;
  }
  if (options_.csv && options_.csv->failed()) {
    reason_ = StopReason::write_failed;
    return Action::stop;
  }
  const double seconds = std::chrono::duration<double>(now - start_).count();
  if (max_wall_seconds_ > 0 && seconds >= max_wall_seconds_) {
    reason_ = StopReason::max_wall_seconds;
    return Action::stop;
  }
  if (progress_.due()) show_progress(steps, t, seconds);
  if (options_.csv && options_.flush_seconds > 0 &&
      std::chrono::duration<double>(now - last_flush_).count() >= options_.flush_seconds) {
    options_.csv->flush();
    last_flush_ = now;
  }
  if (!options_.checkpoint_path.empty() &&
      ((options_.checkpoint_every_steps > 0 && steps - checkpoint_steps_ >= options_.checkpoint_every_steps) ||
       (options_.checkpoint_every_seconds > 0 &&
        std::chrono::duration<double>(now - last_checkpoint_).count() >= options_.checkpoint_every_seconds)))
    return Action::checkpoint;
  return Action::proceed;
}

void SessionMonitor::checkpointed(std::int64_t steps) {
  checkpoint_steps_ = steps;
  last_checkpoint_ = last_flush_ = Clock::now();
}

void SessionMonitor::finish() const { progress_.clear(); }

bool Checkpointer::write(const Cursor& c, std::span<const double> internal, double t, const State<double>& x,
                         const RowWriter& rows, std::span<const double> quaternion, RunReport& report) {
  Checkpoint ck;
  ck.scene_file = scene_.file;
  ck.scene = options_.scene_document;
  ck.inputs = scene_.problem->input_files();
  ck.method = std::string(scene_.method->traits.name);
  ck.cursor = c;
  ck.internal.assign(internal.begin(), internal.end());
  ck.output_quaternion.assign(quaternion.begin(), quaternion.end());
  ck.output = options_.output;
  ck.has_last_row = rows.has_row();
  ck.last_row_t = rows.last_t();
  ck.every_steps = options_.checkpoint_every_steps;
  ck.every_seconds = options_.checkpoint_every_seconds;
  ck.t = t;
  ck.R.assign(x.R.data(), x.R.data() + 9);
  ck.omega.assign(x.Omega.data(), x.Omega.data() + 3);
  std::string error;
  // The rows first, on disk before the checkpoint that counts them.
  OutputFile* out = options_.csv;
  if (!out || out->streamed() || !out->sync()) {
    error = options_.output.partial + ": cannot write the rows: " + (out ? out->error_text() : "no file");
  } else {
    ck.output.bytes = out->bytes_in_file();
    if (!output_hashes(out->fd(), ck.output.bytes, ck.output.head_hash, ck.output.tail_hash))
      error = options_.output.partial + ": cannot read the rows back: " + std::strerror(errno);
  }
  std::string checksum;
  if (error.empty() && write_checkpoint(options_.checkpoint_path, ck, options_.version, error, &checksum)) {
    out->keep_temporary();  // the checkpoint names it: whatever happens now, it stays
    ++report.checkpoints;
    report.checkpoint_checksum = checksum;
    return true;
  }
  report.checkpoint_error = error;
  return false;
}

}  // namespace runner_detail


std::string csv_header(const Scene& scene) {
  std::string h = "t,R11,R12,R13,R21,R22,R23,R31,R32,R33,omega1,omega2,omega3,energy,orthogonality_error";
  for (const std::string_view name : scene.problem->invariant_names()) {
    h += ',';
    h += name;
  }
  return h;
}

std::string output_header(const Scene& scene) {
  if (scene.columns.empty()) return csv_header(scene);
  const std::vector<std::string_view> names = scene.problem->invariant_names();
  return column_header(scene.columns, names);
}

std::vector<std::string> integral_names(const Scene& scene) {
  const std::vector<std::string_view> all = scene.problem->invariant_names();
  return {all.begin(), all.begin() + static_cast<std::ptrdiff_t>(scene.problem->integral_count())};
}

std::vector<double> state_columns(const Scene& scene, double t, const State<double>& x) {
  std::vector<double> c;
  scene.problem->state_columns(t, x, c);
  return c;
}

namespace {
// The order the method declares for this scene's problem: a method of higher order without torque (preprocessed DMV)
// has that order on a torque-free problem.
int declared_order(const Scene& scene) {
  const MethodTraits& m = scene.method->traits;
  return scene.problem->torque_free() && m.free_body_order > 0 ? m.free_body_order : m.order;
}
}  // namespace

std::string brief_report(const Scene& scene, const RunReport& r) {
  const MethodTraits& m = scene.method->traits;
  const std::string problem(scene.problem->type_name());
  const std::string coordinates = scene.problem->coordinates();  // a problem not on SO(3) × R³: its own path
  const int order = declared_order(scene);  // preprocessed DMV: its free-body order on a torque-free problem
  char buf[512];
  std::string s;
  // A forcing that reads Ω does work: the symplectic methods (the LGVI and its compositions) take it in the discrete
  // Lagrange–d'Alembert form, which is not symplectic.
  const char* geometry = !m.symplectic ? "" : scene.problem->reads_omega() ? ", forced Lagrange-d'Alembert" : ", symplectic";
  // The exact solution has no order: dt only spaces the states it evaluates.
  const std::string order_text = m.exact_solution ? "exact solution" : "order " + std::to_string(order);
  std::snprintf(buf, sizeof buf, "%s: %s, %s (%s%s%s), dt = %s\n", scene.file.c_str(), problem.c_str(),
                std::string(m.name).c_str(), order_text.c_str(), geometry,
                !coordinates.empty() ? coordinates.c_str() : m.exact_on_group ? ", on SO(3)" : "",
                format_number(scene.dt).c_str());
  s += buf;
  // What the readers changed to make the input exact.
  for (const InputAdjustment& a : scene.adjustments) s += "  input            " + a.where + " " + a.what + "\n";
  // "auto": what was chosen, why, and what choosing cost.
  if (const AutoChoice& a = scene.auto_choice; a.tolerance > 0) {
    if (a.probe_steps > 0) std::snprintf(buf, sizeof buf, " (the probes took %.3g ms)\n", 1e3 * a.seconds);
    else std::snprintf(buf, sizeof buf, "\n");
    s += "  method auto      tolerance " + format_number(a.tolerance) + " (R's angle + |dOmega|/|Omega|): " + a.reason + buf;
  }
  // How the run was made, where the scene asked for more than fixed steps.
  if (scene.options.rtol > 0)
    s += "  adaptive         rtol = " + format_number(scene.options.rtol) + ", atol = " +
         format_number(scene.options.atol) + " (dt is the initial step; steps below are the accepted ones)\n";
  if (scene.options.projection) s += "  projected        energy and m.k (free body: |J Omega|) restored after every step\n";
  std::snprintf(buf, sizeof buf, "  steps            %lld to t = %s", static_cast<long long>(r.summary.steps),
                format_number(r.summary.t).c_str());
  s += buf;
  if (r.newton_iterations >= 0 && r.session_steps > 0)
    std::snprintf(buf, sizeof buf, " (%.2f Newton iterations per step)\n",
                  static_cast<double>(r.newton_iterations) / static_cast<double>(r.session_steps));
  else if (r.rejected >= 0)
    std::snprintf(buf, sizeof buf, " (%lld trial steps rejected)\n", static_cast<long long>(r.rejected));
  else
    std::snprintf(buf, sizeof buf, "\n");
  s += buf;
  // A torque that reads Ω does work: the energy's change is the motion, not an error.
  s += (scene.problem->reads_omega() ? "  energy change    " : "  energy error     ") +
       relative(r.energy_initial, r.energy_final) + " (relative)\n";
  for (const auto& inv : r.invariants)
    s += "  " + inv.name + std::string(inv.name.size() < 16 ? 16 - inv.name.size() : 1, ' ') + " " +
         relative(inv.initial, inv.final) + " (relative change)\n";
  std::snprintf(buf, sizeof buf, "  orthogonality    %.3e (|R^T R - I|)\n  wall time        %.3f s (%.1f ns/step)\n",
                so3::orthogonality_error(r.final_state.R), r.wall_seconds,
                r.session_steps > 0 ? 1e9 * r.wall_seconds / static_cast<double>(r.session_steps) : 0.0);
  s += buf;
  return s;
}

ErrorEstimate estimate_error(const Scene& scene, const RunReport& report, const volatile std::sig_atomic_t* stop) {
  ErrorEstimate e;
  e.t = report.summary.t;
  const MethodTraits& m = scene.method->traits;
  if (m.exact_solution) {
    e.how = "none needed: the exact solution (round-off only)";
    return e;
  }
  if (report.summary.status != RunStatus::completed) {
    e.how = "not available: the run did not complete";
    return e;
  }
  Scene second = scene;
  second.output_times.clear();
  second.output_every = 0;
  second.columns.clear();
  double factor = 0;  // err(x) ≈ factor · |x − x_second|
  char buf[160];
  const int p = declared_order(scene);
  const double q = std::ldexp(1.0, p);  // 2^p
  // Richardson against dt/2: err(x_h) ≈ |x_h − x_{h/2}| · 2^p / (2^p − 1).
  const auto half_step = [&](const char* why) {
    second.dt = scene.dt / 2;
    factor = q / (q - 1);
    std::snprintf(buf, sizeof buf, "Richardson with dt = %s (order %d%s)", format_number(second.dt).c_str(), p, why);
  };
  if (scene.options.rtol > 0) {
    second.options.rtol = std::max(scene.options.rtol / 1000, min_rtol);
    second.options.atol = scene.options.atol / 1000;
    if (!(second.options.rtol < scene.options.rtol / 10)) {
      e.how = "not available: rtol is within 10x of its floor 10 eps";
      return e;
    }
    factor = 1;
    std::snprintf(buf, sizeof buf, "against rtol = %s, atol = %s", format_number(second.options.rtol).c_str(),
                  format_number(second.options.atol).c_str());
  } else if (p < 1) {
    e.how = "not available: the method declares no order";
    return e;
  } else if (2 * scene.dt <= scene.t_end) {
    second.dt = 2 * scene.dt;
    factor = 1 / (q - 1);
    std::snprintf(buf, sizeof buf, "Richardson with dt = %s (order %d)", format_number(second.dt).c_str(), p);
  } else {
    half_step("");
  }
  second.max_steps = 0;  // the comparison runs to t_end (its budget is the run's own wall-time limit)
  RunOptions options;
  options.stop = stop;
  RunReport r = run_scene(second, options);
  e.seconds = r.wall_seconds;
  if (r.summary.status == RunStatus::step_failed && scene.options.rtol == 0 && second.dt > scene.dt) {
    half_step("; 2 dt failed");  // 2·dt beyond the method's step limit (an implicit step that does not converge)
    r = run_scene(second, options);
    e.seconds += r.wall_seconds;
  }
  if (r.summary.status != RunStatus::completed || r.summary.t != report.summary.t) {
    e.how = std::string("not available: the comparison run (") + buf + ") did not complete";
    return e;
  }
  // |Ω| at t or at the start, whichever is larger (a motion brought to rest: relative to its initial speed).
  const StateDifference d = state_difference(report.final_state, r.final_state, scene.initial.Omega.norm());
  e.R = factor * d.angle;
  e.Omega = factor * d.omega;
  e.available = std::isfinite(e.R) && std::isfinite(e.Omega);
  e.how = buf;
  return e;
}

StateDifference state_difference(const State<double>& a, const State<double>& b, double omega_scale) {
  const double w = std::max(a.Omega.norm(), omega_scale);
  return {so3::log(Mat3<double>(b.R.transpose() * a.R)).norm(), (a.Omega - b.Omega).norm() / (w > 0 ? w : 1.0)};
}

std::string error_estimate_line(const ErrorEstimate& e, const RunReport& report) {
  if (!e.available) return "  estimated error  " + e.how + "\n";
  char buf[320];
  std::snprintf(buf, sizeof buf, "  estimated error  R %.1e rad, Omega %.1e (relative) at t = %s: %s, +%.3f s (%.2fx the run)\n",
                e.R, e.Omega, format_number(e.t).c_str(), e.how.c_str(), e.seconds,
                report.wall_seconds > 0 ? e.seconds / report.wall_seconds : 0.0);
  return buf;
}

}  // namespace lgi::app
