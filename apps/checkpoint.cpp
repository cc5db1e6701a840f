// lgi/apps/checkpoint.cpp — checkpoint files of `lgi run` (runner_checkpoint.hpp has the format and its contract).
#include "runner_checkpoint.hpp"

#include "hashing.hpp"
#include "output_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace lgi::app {

namespace {

constexpr int format_version = 2;
// How every checkpoint file begins (json::dump(1) of an ordered document whose first key is lgi_checkpoint):
// what a temporary file cut short by a kill is recognised by.
constexpr std::string_view file_start = "{\n \"lgi_checkpoint\": 2,\n";

std::string hex(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%a", x);
  return buf;
}

// A number written by hex(): a string strtod reads completely (bit for bit).
double read_hex(const Node& n) {
  const std::string s = n.string();
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(x) || errno == ERANGE)
    n.fail("expected a finite number as a hexadecimal float (\"%a\"), got " + quoted_input(s));
  return x;
}
std::uint64_t read_hex64(const Node& n) {
  const std::string s = n.string();
  char* end = nullptr;
  const unsigned long long x = std::strtoull(s.c_str(), &end, 16);
  if (s.size() != 16 || end != s.c_str() + s.size() || s.find_first_not_of("0123456789abcdef") != std::string::npos)
    n.fail("expected 16 hexadecimal digits, got " + quoted_input(s));
  return x;
}

// The checksum line. A checkpoint file is the JSON text of its document without "checksum" (json::dump(1) of an
// ordered document) up to its closing brace, then this line and the brace:
//     ...last member,
//      "checksum": "fnv1a64:<16 hex digits>"
//     }
// the hash covering every byte before `"checksum"`. Any change of any byte — a value, a key, the layout, a cut —
// is refused; nothing but lgi's own writer produces a file that passes.
constexpr std::string_view checksum_marker = ",\n \"checksum\": \"fnv1a64:";
constexpr std::string_view checksum_end = "\"\n}\n";

// The checksum ("fnv1a64:" and 16 hex digits) a file's bytes carry and hash to, or "" if they do not.
std::string verified_checksum(const std::string& text) {
  const std::size_t at = text.rfind(checksum_marker);
  if (at == std::string::npos || text.size() != at + checksum_marker.size() + 16 + checksum_end.size() ||
      text.compare(text.size() - checksum_end.size(), checksum_end.size(), checksum_end) != 0)
    return {};
  const std::string digits = text.substr(at + checksum_marker.size(), 16);
  if (digits != hex64(fnv1a(text.data(), at + 2))) return {};  // the bytes before the key, ",\n" included
  return "fnv1a64:" + digits;
}

// The file's bytes (false with `error` set if it cannot be read).
bool read_bytes(const std::string& path, std::string& text, std::string& error) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) {
    error = std::strerror(errno);
    return false;
  }
  text.clear();
  char buffer[1 << 14];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0 && text.size() <= max_input_bytes) text.append(buffer, n);
  const bool ok = !std::ferror(f);
  std::fclose(f);
  if (!ok) error = "read error";
  return ok;
}

}  // namespace

std::string step_status_token(StepStatus s) {
  switch (s) {
    case StepStatus::ok: return "ok";
    case StepStatus::not_converged: return "not_converged";
    case StepStatus::non_finite: return "non_finite";
    case StepStatus::step_size_underflow: return "step_size_underflow";
  }
  return "step_failed";
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

bool write_checkpoint(const std::string& path, const Checkpoint& ck, const std::string& version, std::string& error,
                      std::string* checksum) {
  nlohmann::ordered_json j;
  j["lgi_checkpoint"] = format_version;
  j["lgi_version"] = version;
  j["scene_file"] = ck.scene_file;
  j["method"] = ck.method;
  j["t"] = ck.t;
  j["state"] = {{"R", ck.R}, {"omega", ck.omega}};
  const Cursor& c = ck.cursor;
  nlohmann::ordered_json cursor;
  cursor["driver"] = c.adaptive ? "adaptive" : "fixed";
  cursor["steps"] = c.steps;
  if (c.adaptive) {
    cursor["t"] = hex(c.t);
    cursor["h"] = hex(c.h);
    cursor["err_old"] = hex(c.err_old);
    cursor["rejected_last"] = c.rejected_last;
    cursor["cause"] = step_status_token(c.cause);
    cursor["attempts"] = c.attempts;
    cursor["rejected"] = c.rejected;
    cursor["next"] = c.next;
  } else {
    cursor["n"] = c.n;
    cursor["event"] = c.event;
  }
  j["cursor"] = cursor;
  nlohmann::ordered_json internal = nlohmann::ordered_json::array();
  for (const double v : ck.internal) internal.push_back(hex(v));
  j["internal"] = internal;
  j["output"] = {{"target", ck.output.target},
                 {"partial", ck.output.partial},
                 {"bytes", ck.output.bytes},
                 {"head_fnv1a64", hex64(ck.output.head_hash)},
                 {"tail_fnv1a64", hex64(ck.output.tail_hash)}};
  j["last_row_t"] = ck.has_last_row ? nlohmann::ordered_json(hex(ck.last_row_t)) : nlohmann::ordered_json(nullptr);
  if (!ck.output_quaternion.empty()) {
    nlohmann::ordered_json q = nlohmann::ordered_json::array();
    for (const double v : ck.output_quaternion) q.push_back(hex(v));
    j["last_row_quaternion"] = q;
  }
  nlohmann::ordered_json every = nlohmann::ordered_json::object();
  if (ck.every_steps > 0) every["steps"] = ck.every_steps;
  if (ck.every_seconds > 0) every["seconds"] = ck.every_seconds;
  j["checkpoint_every"] = every;
  j["scene"] = nlohmann::ordered_json::parse(ck.scene.dump());
  if (!ck.inputs.empty()) {
    nlohmann::ordered_json inputs = nlohmann::ordered_json::array();
    for (const auto& [file, digest] : ck.inputs) inputs.push_back({{"file", file}, {"fnv1a64", hex64(digest)}});
    j["inputs"] = inputs;
  }
  std::string text = j.dump(1);  // ends in "\n}"
  text.resize(text.size() - 2);
  text += checksum_marker;
  const std::string digits = hex64(fnv1a(text.data(), text.size() - checksum_marker.size() + 2));
  text += digits;
  text += checksum_end;
  const std::string sum = "fnv1a64:" + digits;

  // Atomically: a temporary file beside it, fsync, rename, fsync of the directory.
  std::string temp;
  const int fd = create_temporary_beside(path, temp);
  if (fd < 0) {
    error = std::string("cannot create a file beside it: ") + std::strerror(errno);
    return false;
  }
  std::size_t done = 0;
  bool ok = true;
  int saved = 0;
  while (ok && done < text.size()) {
    const ssize_t w = ::write(fd, text.data() + done, text.size() - done);
    if (w < 0 && errno == EINTR) continue;
    ok = w > 0;
    if (ok) done += static_cast<std::size_t>(w);
    else saved = w < 0 ? errno : EIO;
  }
  if (ok && fsync(fd) != 0) {
    ok = false;
    saved = errno;
  }
  if (close(fd) != 0 && ok) {
    ok = false;
    saved = errno;
  }
  if (ok && std::rename(temp.c_str(), path.c_str()) != 0) {
    ok = false;
    saved = errno;
  }
  if (!ok) {
    error = std::strerror(saved);
    unlink(temp.c_str());
    return false;
  }
  sync_directory_of(path);
  if (checksum) *checksum = sum;
  return true;
}

Checkpoint read_checkpoint(const std::string& path) {
  struct stat st {};
  if (stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    throw InputError(path + ": not a checkpoint: not a regular file");
  std::string text, error;
  if (!read_bytes(path, text, error)) throw InputError(path + ": cannot read the file: " + error);
  return parse_checkpoint(text, path);
}

Checkpoint parse_checkpoint(const std::string& text, const std::string& path) {
  if (text.size() > max_input_bytes) throw InputError(path + ": not a checkpoint: larger than " + std::to_string(max_input_bytes) + " bytes");
  // The whole content first: a checkpoint changed anywhere is refused before any of it is used.
  if (text.rfind(file_start, 0) != 0) {
    if (text.find("\"lgi_checkpoint\":") != std::string::npos)  // format 1 (keys sorted), or a later one
      throw InputError(path + ": /lgi_checkpoint: a checkpoint format this lgi does not read (it reads format " +
                       std::to_string(format_version) + "; written by another version of lgi)");
    throw InputError(path + ": not a checkpoint of lgi run (it does not begin as one)");
  }
  if (verified_checksum(text).empty())
    throw InputError(path + ": /checksum: does not match the file's bytes: the checkpoint was changed, damaged or cut "
                            "short (it cannot be resumed)");
  const json doc = parse_json(text, path);
  const Node root(doc, "", path);
  if (!root.is_object()) root.fail("not a checkpoint of lgi run");
  root.allow_only({"lgi_checkpoint", "lgi_version", "scene_file", "method", "t", "state", "cursor", "internal",
                   "output", "last_row_t", "last_row_quaternion", "checkpoint_every", "scene", "inputs", "checksum"});
  Checkpoint ck;
  ck.scene_file = root.at("scene_file").string();
  const Node scene = root.at("scene");
  if (!scene.is_object()) scene.fail("expected an object (the scene), got " + describe(scene.value()));
  ck.scene = scene.value();
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
    if (!(c.t >= 0)) cursor.at("t").fail("expected t >= 0, got " + format_number(c.t));
    c.h = read_hex(cursor.at("h"));
    if (!(c.h > 0)) cursor.at("h").fail("expected a step > 0, got " + format_number(c.h));
    c.err_old = read_hex(cursor.at("err_old"));
    if (!(c.err_old > 0)) cursor.at("err_old").fail("expected an error > 0, got " + format_number(c.err_old));
    const Node rejected_last = cursor.at("rejected_last");
    if (!rejected_last.value().is_boolean()) rejected_last.fail("expected true or false");
    c.rejected_last = rejected_last.value().get<bool>();
    const std::string cause = cursor.at("cause").string();
    bool known = false;
    for (const StepStatus s : {StepStatus::not_converged, StepStatus::non_finite, StepStatus::step_size_underflow})
      if (cause == step_status_token(s)) {
        c.cause = s;
        known = true;
      }
    if (!known) cursor.at("cause").fail("unknown step status " + quoted_input(cause));
    c.attempts = cursor.at("attempts").integer(0, big);
    c.rejected = cursor.at("rejected").integer(0, big);
    if (c.attempts != c.steps + c.rejected)
      cursor.at("attempts").fail("attempted steps " + std::to_string(c.attempts) + " are not the accepted " +
                                 std::to_string(c.steps) + " plus the rejected " + std::to_string(c.rejected));
    c.next = cursor.at("next").integer(0, big);
  } else {
    cursor.allow_only({"driver", "steps", "n", "event"});
    c.n = cursor.at("n").integer(0, big);
    c.event = cursor.at("event").integer(0, big);
    if (c.steps < c.n)
      cursor.at("steps").fail("fewer steps (" + std::to_string(c.steps) + ") than the grid index n = " +
                              std::to_string(c.n));
  }
  const Node internal = root.at("internal");
  for (std::size_t i = 0; i < internal.size(); ++i) ck.internal.push_back(read_hex(internal.at(i)));
  const Node output = root.at("output");
  output.allow_only({"target", "partial", "bytes", "head_fnv1a64", "tail_fnv1a64"});
  ck.output.target = output.at("target").string();
  if (ck.output.target.empty()) output.at("target").fail("an empty file name");
  ck.output.partial = output.at("partial").string();
  if (ck.output.partial.empty()) output.at("partial").fail("an empty file name");
  ck.output.bytes = static_cast<std::uint64_t>(output.at("bytes").integer(1, big));
  ck.output.head_hash = read_hex64(output.at("head_fnv1a64"));
  ck.output.tail_hash = read_hex64(output.at("tail_fnv1a64"));
  const Node last = root.at("last_row_t");
  ck.has_last_row = !last.value().is_null();
  if (ck.has_last_row) ck.last_row_t = read_hex(last);
  if (const auto q = root.find("last_row_quaternion")) {
    if (!q->is_array() || q->size() != 4) q->fail("expected 4 numbers (the last row's quaternion)");
    for (std::size_t i = 0; i < 4; ++i) ck.output_quaternion.push_back(read_hex(q->at(i)));
  }
  const Node every = root.at("checkpoint_every");
  every.allow_only({"steps", "seconds"});
  if (auto n = every.find("steps")) ck.every_steps = n->integer(1, big);
  if (auto n = every.find("seconds")) ck.every_seconds = n->positive();
  if (const auto inputs = root.find("inputs")) {
    if (!inputs->is_array()) inputs->fail("expected an array of {\"file\": ..., \"fnv1a64\": ...}");
    for (std::size_t i = 0; i < inputs->size(); ++i) {
      const Node in = inputs->at(i);
      in.allow_only({"file", "fnv1a64"});
      ck.inputs.emplace_back(in.at("file").string(), read_hex64(in.at("fnv1a64")));
    }
  }
  ck.t = root.at("t").number();
  return ck;
}

bool is_own_checkpoint(const std::string& path, const std::string& checksum) {
  struct stat st {};
  if (checksum.empty() || lstat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;
  std::string text, error;
  return read_bytes(path, text, error) && text.rfind(file_start, 0) == 0 && verified_checksum(text) == checksum;
}

bool is_checkpoint_temporary(const std::string& path) {
  struct stat st {};
  if (lstat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  char head[file_start.size()];
  const std::size_t n = std::fread(head, 1, sizeof head, f);
  std::fclose(f);
  return std::string_view(head, n) == file_start.substr(0, n);  // empty, cut short, or whole
}

}  // namespace lgi::app
