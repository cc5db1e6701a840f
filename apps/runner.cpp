// lgi/apps/runner.cpp — run_scene's dispatch on the problem, the CSV header and the brief report. The
// runs themselves are in runner_impl.hpp, compiled in parts (runner_detail.hpp).
#include "runner_detail.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <variant>

namespace lgi::app {

// LGI_RUNNER_PARTS: the number of runner parts apps/CMakeLists.txt configures.
static_assert(std::variant_size_v<AnyProblem> == LGI_RUNNER_PARTS,
              "a problem was added to the registry: raise LGI_RUNNER_PARTS in apps/CMakeLists.txt to the number "
              "of problems, so that its runner part is compiled");

namespace {

std::string relative(double initial, double final) {
  const double scale = std::abs(initial) > 0 ? std::abs(initial) : 1.0;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3e", std::abs(final - initial) / scale);
  return buf;
}

}  // namespace

// ---- the monitor ---------------------------------------------------------------------------------------------

namespace runner_detail {

SessionMonitor::SessionMonitor(const RunOptions& options, const Scene& scene, std::int64_t total, std::int64_t steps)
    : options_(options), max_wall_seconds_(scene.max_wall_seconds), total_(total), checkpoint_steps_(steps) {}

SessionMonitor::Action SessionMonitor::check(std::int64_t steps) {
  if (options_.stop && *options_.stop != 0) {
    reason_ = StopReason::signal;
    return Action::stop;
  }
  const auto now = Clock::now();
  const double seconds = std::chrono::duration<double>(now - start_).count();
  if (max_wall_seconds_ > 0 && seconds >= max_wall_seconds_) {
    reason_ = StopReason::max_wall_seconds;
    return Action::stop;
  }
  if (options_.progress && total_ > 0 && seconds >= 1 && now - last_progress_ >= std::chrono::milliseconds(250)) {
    last_progress_ = now;
    printed_ = true;
    std::fprintf(stderr, "\r  %5.1f %%  %lld of %lld steps", 100.0 * static_cast<double>(steps) / static_cast<double>(total_),
                 static_cast<long long>(steps), static_cast<long long>(total_));
    std::fflush(stderr);
  }
  if (options_.csv && options_.flush_seconds > 0 &&
      std::chrono::duration<double>(now - last_flush_).count() >= options_.flush_seconds) {
    std::fflush(options_.csv);
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

void SessionMonitor::finish() const {
  if (printed_) std::fprintf(stderr, "\r%60s\r", "");
}

bool Checkpointer::write(const Cursor& c, std::span<const double> internal, double t, const State<double>& x,
                         const RowWriter& rows, RunReport& report) {
  Checkpoint ck;
  ck.scene_file = scene_.file;
  ck.scene = options_.scene_document;
  ck.method = std::string(scene_.method->traits.name);
  ck.cursor = c;
  ck.internal.assign(internal.begin(), internal.end());
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
  const int fd = options_.csv ? fileno(options_.csv) : -1;
  const off_t end = fd >= 0 && std::fflush(options_.csv) == 0 && fsync(fd) == 0 ? lseek(fd, 0, SEEK_CUR) : -1;
  if (end < 0) {
    error = options_.output.partial + ": cannot flush the rows: " + std::strerror(errno);
  } else {
    ck.output.bytes = static_cast<std::uint64_t>(end);
    if (!output_hashes(fd, ck.output.bytes, ck.output.head_hash, ck.output.tail_hash))
      error = options_.output.partial + ": cannot read the rows back: " + std::strerror(errno);
  }
  if (error.empty() && write_checkpoint(options_.checkpoint_path, ck, options_.version, error)) {
    ++report.checkpoints;
    return true;
  }
  if (report.checkpoint_error.empty())
    std::fprintf(stderr, "lgi: warning: %s: cannot write the checkpoint (the run goes on): %s\n",
                 options_.checkpoint_path.c_str(), error.c_str());
  report.checkpoint_error = error;
  return false;
}

}  // namespace runner_detail

// ---- checkpoint files --------------------------------------------------------------------------------------

std::uint64_t fnv1a(const void* data, std::size_t size, std::uint64_t hash) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= p[i];
    hash *= 1099511628211ull;
  }
  return hash;
}

bool output_hashes(int fd, std::uint64_t bytes, std::uint64_t& head, std::uint64_t& tail) {
  constexpr std::uint64_t span = 4096;
  char buffer[span];
  const auto hash_at = [&](std::uint64_t offset, std::uint64_t n, std::uint64_t& h) {
    std::uint64_t done = 0;
    while (done < n) {
      const ssize_t r = pread(fd, buffer + done, n - done, static_cast<off_t>(offset + done));
      if (r <= 0) {
        if (r == 0) errno = EIO;  // the file is shorter than `bytes`
        return false;
      }
      done += static_cast<std::uint64_t>(r);
    }
    h = fnv1a(buffer, n);
    return true;
  };
  const std::uint64_t n = std::min(bytes, span);
  return hash_at(0, n, head) && hash_at(bytes - n, n, tail);
}

namespace {

std::string hex(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}
std::string hex64(std::uint64_t x) {
  char buf[20];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(x));
  return buf;
}

const char* cause_name(StepStatus s) {
  switch (s) {
    case StepStatus::ok: return "ok";
    case StepStatus::not_converged: return "not_converged";
    case StepStatus::non_finite: return "non_finite";
    case StepStatus::step_size_underflow: return "step_size_underflow";
  }
  return "?";
}

// A number written by hex(): a string strtod reads completely (bit for bit).
double read_hex(const Node& n) {
  const std::string s = n.string();
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(x) || errno == ERANGE)
    n.fail("expected a finite number as a hexadecimal float (\"%a\"), got \"" + s + "\"");
  return x;
}
std::uint64_t read_hex64(const Node& n) {
  const std::string s = n.string();
  char* end = nullptr;
  const unsigned long long x = std::strtoull(s.c_str(), &end, 16);
  if (s.size() != 16 || end != s.c_str() + s.size()) n.fail("expected 16 hexadecimal digits, got \"" + s + "\"");
  return x;
}

}  // namespace

bool write_checkpoint(const std::string& path, const Checkpoint& ck, const std::string& version, std::string& error) {
  json j;
  j["lgi_checkpoint"] = 1;
  j["lgi_version"] = version;
  j["scene_file"] = ck.scene_file;
  const std::string scene_text = ck.scene.dump();
  j["scene_fnv1a64"] = hex64(fnv1a(scene_text.data(), scene_text.size()));
  j["scene"] = ck.scene;
  j["method"] = ck.method;
  j["t"] = ck.t;
  json state;
  state["R"] = ck.R;
  state["omega"] = ck.omega;
  j["state"] = state;
  const Cursor& c = ck.cursor;
  json cursor;
  cursor["driver"] = c.adaptive ? "adaptive" : "fixed";
  cursor["steps"] = c.steps;
  if (c.adaptive) {
    cursor["t"] = hex(c.t);
    cursor["h"] = hex(c.h);
    cursor["err_old"] = hex(c.err_old);
    cursor["rejected_last"] = c.rejected_last;
    cursor["cause"] = cause_name(c.cause);
    cursor["attempts"] = c.attempts;
    cursor["rejected"] = c.rejected;
    cursor["next"] = c.next;
  } else {
    cursor["n"] = c.n;
    cursor["event"] = c.event;
  }
  j["cursor"] = cursor;
  json internal = json::array();
  for (const double v : ck.internal) internal.push_back(hex(v));
  j["internal"] = internal;
  json output;
  output["target"] = ck.output.target;
  output["partial"] = ck.output.partial;
  output["bytes"] = ck.output.bytes;
  output["head_fnv1a64"] = hex64(ck.output.head_hash);
  output["tail_fnv1a64"] = hex64(ck.output.tail_hash);
  j["output"] = output;
  j["last_row_t"] = ck.has_last_row ? json(hex(ck.last_row_t)) : json(nullptr);
  json every = json::object();
  if (ck.every_steps > 0) every["steps"] = ck.every_steps;
  if (ck.every_seconds > 0) every["seconds"] = ck.every_seconds;
  j["checkpoint_every"] = every;
  const std::string text = j.dump(1) + "\n";

  // Atomically: a temporary file beside it, fsync, rename, fsync of the directory.
  const std::filesystem::path p(path);
  const std::filesystem::path dir = p.has_parent_path() ? p.parent_path() : std::filesystem::path(".");
  std::string temp = (dir / ("." + p.filename().string() + ".tmp-XXXXXX")).string();
  const int fd = mkstemp(temp.data());
  if (fd < 0) {
    error = std::string("cannot create a file beside it: ") + std::strerror(errno);
    return false;
  }
  const mode_t mask = umask(0);  // mkstemp makes 0600; give the file the mode a plain create would
  umask(mask);
  fchmod(fd, 0666 & ~mask);
  std::size_t done = 0;
  bool ok = true;
  while (ok && done < text.size()) {
    const ssize_t w = ::write(fd, text.data() + done, text.size() - done);
    ok = w > 0;
    if (ok) done += static_cast<std::size_t>(w);
  }
  ok = ok && fsync(fd) == 0;
  const int saved = errno;
  ok = close(fd) == 0 && ok;
  if (!ok || std::rename(temp.c_str(), path.c_str()) != 0) {
    error = std::strerror(ok ? errno : saved);
    unlink(temp.c_str());
    return false;
  }
  const int dfd = open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (dfd >= 0) {
    fsync(dfd);
    close(dfd);
  }
  return true;
}

Checkpoint read_checkpoint(const std::string& path) {
  const json doc = read_json_file(path);
  const Node root(doc, "", path);
  root.allow_only({"lgi_checkpoint", "lgi_version", "scene_file", "scene_fnv1a64", "scene", "method", "t", "state",
                   "cursor", "internal", "output", "last_row_t", "checkpoint_every"});
  if (root.at("lgi_checkpoint").integer(1, 1) != 1) root.at("lgi_checkpoint").fail("unknown checkpoint format");
  Checkpoint ck;
  ck.scene_file = root.at("scene_file").string();
  const Node scene = root.at("scene");
  if (!scene.is_object()) scene.fail("expected an object (the scene), got " + describe(scene.value()));
  ck.scene = scene.value();
  const std::string scene_text = ck.scene.dump();
  if (read_hex64(root.at("scene_fnv1a64")) != fnv1a(scene_text.data(), scene_text.size()))
    root.at("scene_fnv1a64").fail("does not match the scene: the checkpoint was changed");
  ck.method = root.at("method").string();
  constexpr std::int64_t big = std::int64_t{1} << 53;
  const Node cursor = root.at("cursor");
  const std::string driver = cursor.at("driver").string();
  if (driver != "fixed" && driver != "adaptive") cursor.at("driver").fail("expected \"fixed\" or \"adaptive\"");
  Cursor& c = ck.cursor;
  c.adaptive = driver == "adaptive";
  c.steps = cursor.at("steps").integer(0, big);
  if (c.adaptive) {
    cursor.allow_only({"driver", "steps", "t", "h", "err_old", "rejected_last", "cause", "attempts", "rejected", "next"});
    c.t = read_hex(cursor.at("t"));
    c.h = read_hex(cursor.at("h"));
    c.err_old = read_hex(cursor.at("err_old"));
    const Node rejected_last = cursor.at("rejected_last");
    if (!rejected_last.value().is_boolean()) rejected_last.fail("expected true or false");
    c.rejected_last = rejected_last.value().get<bool>();
    const std::string cause = cursor.at("cause").string();
    bool known = false;
    for (const StepStatus s : {StepStatus::not_converged, StepStatus::non_finite, StepStatus::step_size_underflow})
      if (cause == cause_name(s)) {
        c.cause = s;
        known = true;
      }
    if (!known) cursor.at("cause").fail("unknown step status \"" + cause + "\"");
    c.attempts = cursor.at("attempts").integer(0, big);
    c.rejected = cursor.at("rejected").integer(0, big);
    c.next = cursor.at("next").integer(0, big);
  } else {
    cursor.allow_only({"driver", "steps", "n", "event"});
    c.n = cursor.at("n").integer(0, big);
    c.event = cursor.at("event").integer(0, big);
  }
  const Node internal = root.at("internal");
  for (std::size_t i = 0; i < internal.size(); ++i) ck.internal.push_back(read_hex(internal.at(i)));
  const Node output = root.at("output");
  ck.output.target = output.at("target").string();
  ck.output.partial = output.at("partial").string();
  ck.output.bytes = static_cast<std::uint64_t>(output.at("bytes").integer(0, big));
  ck.output.head_hash = read_hex64(output.at("head_fnv1a64"));
  ck.output.tail_hash = read_hex64(output.at("tail_fnv1a64"));
  const Node last = root.at("last_row_t");
  ck.has_last_row = !last.value().is_null();
  if (ck.has_last_row) ck.last_row_t = read_hex(last);
  const Node every = root.at("checkpoint_every");
  every.allow_only({"steps", "seconds"});
  if (auto n = every.find("steps")) ck.every_steps = n->integer(1, big);
  if (auto n = every.find("seconds")) ck.every_seconds = n->positive();
  ck.t = root.at("t").number();
  return ck;
}

RunReport run_scene(const Scene& scene, const RunOptions& options) {
  return std::visit([&](const auto& p) { return run_problem(p, scene, options); }, scene.problem);
}

std::string csv_header(const Scene& scene) {
  return std::visit([](const auto& p) { return runner_detail::header_for<std::decay_t<decltype(p)>>(); }, scene.problem);
}

std::string brief_report(const Scene& scene, const RunReport& r) {
  const MethodTraits& m = scene.method->traits;
  const std::string problem = std::visit([](const auto& p) { return std::string(p.name); }, scene.problem);
  const bool euler_angles = problem == EulerAngleTop<double>::name;  // its own path: RK on the angles
  // A method whose order is higher without torque (preprocessed DMV) shows that order on a torque-free problem.
  const bool torque_free = std::visit(
      [](const auto& p) {
        using P = std::decay_t<decltype(p)>;
        if constexpr (requires { P::has_torque; })
          return !P::has_torque;
        else
          return false;
      },
      scene.problem);
  const int order = torque_free && m.free_body_order > 0 ? m.free_body_order : m.order;
  char buf[512];
  std::string s;
  std::snprintf(buf, sizeof buf, "%s: %s, %s (order %d%s%s), dt = %s\n", scene.file.c_str(), problem.c_str(),
                std::string(m.name).c_str(), order, m.symplectic ? ", symplectic" : "",
                euler_angles ? ", Runge-Kutta on the Euler angles" : m.exact_on_group ? ", on SO(3)" : "",
                format_number(scene.dt).c_str());
  s += buf;
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
  s += "  energy error     " + relative(r.energy_initial, r.energy_final) + " (relative)\n";
  for (const auto& inv : r.invariants)
    s += "  " + inv.name + std::string(inv.name.size() < 16 ? 16 - inv.name.size() : 1, ' ') + " " +
         relative(inv.initial, inv.final) + " (relative change)\n";
  std::snprintf(buf, sizeof buf, "  orthogonality    %.3e (|R^T R - I|)\n  wall time        %.3f s (%.1f ns/step)\n",
                so3::orthogonality_error(r.final_state.R), r.wall_seconds,
                r.session_steps > 0 ? 1e9 * r.wall_seconds / static_cast<double>(r.session_steps) : 0.0);
  s += buf;
  return s;
}

}  // namespace lgi::app
