// lgi/apps/sweep_command.cpp — `lgi sweep` and `lgi merge` (sweep_command.hpp has the contract,
// docs/sweep.md the user's guide).
#include "sweep_command.hpp"

#include "command.hpp"
#include "json_reader.hpp"
#include "runner.hpp"
#include "scene.hpp"
#include "sweep_observe.hpp"

#include <lgi/core/inertia.hpp>
#include <lgi/core/invariants.hpp>
#include <lgi/core/so3.hpp>
#include <lgi/integrators/batch_lgvi.hpp>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <csignal>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <span>
#include <sstream>
#include <thread>
#include <variant>
#include <vector>

namespace lgi::app {

namespace {

inline constexpr std::int64_t max_members = 10'000'000;

std::uint64_t fnv1a64(const std::string& s) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (const char c : s) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

// splitmix64's output function applied to z + the golden-ratio increment (Vigna, splitmix64.c).
std::uint64_t splitmix64(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

std::string hex64(std::uint64_t h) {
  char buf[20];
  std::snprintf(buf, sizeof buf, "%016" PRIx64, h);
  return buf;
}

enum class Record { status, final, invariants, extrema, lyapunov, crossings };
constexpr const char* record_names[] = {"status", "final", "invariants", "extrema", "lyapunov", "crossings"};

struct Key {
  std::string pointer;
  json::json_pointer ptr;
  std::vector<double> values;  // grid: the axis's values
  double lo = 0, hi = 0;       // random: the range
};

struct Sweep {
  std::string file;
  json scene;  // the sweep file without its "sweep" section
  bool random = false;
  std::vector<Key> keys;
  std::uint64_t seed = 0;
  std::int64_t members = 0;
  std::vector<Record> record;
  ObserveSpec observe;  // what the members' runs record as they go (extrema, crossings, Lyapunov)
  Scene scene0;         // member 0, loaded
  std::string header;  // without the newline
  std::uint64_t hash = 0;
  bool records(Record r) const { return std::find(record.begin(), record.end(), r) != record.end(); }
};

// The crossings file's header (docs/sweep.md).
constexpr const char* crossings_header =
    "member,crossing,t,R11,R12,R13,R21,R22,R23,R31,R32,R33,omega1,omega2,omega3";

// Member m's values, one per key.
std::vector<double> member_values(const Sweep& s, std::int64_t m) {
  std::vector<double> v(s.keys.size());
  if (s.random) {
    for (std::size_t k = 0; k < s.keys.size(); ++k) {
      const Key& key = s.keys[k];
      v[k] = key.lo + (key.hi - key.lo) * sweep_uniform(s.seed, static_cast<std::uint64_t>(m), key.pointer);
    }
    return v;
  }
  for (std::size_t k = s.keys.size(); k-- > 0;) {  // the last key varies fastest
    const auto n = static_cast<std::int64_t>(s.keys[k].values.size());
    v[k] = s.keys[k].values[static_cast<std::size_t>(m % n)];
    m /= n;
  }
  return v;
}

std::string values_text(const Sweep& s, const std::vector<double>& v) {
  std::string t;
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (k > 0) t += ", ";
    t += s.keys[k].pointer + " = " + format_number(v[k]);
  }
  return t;
}

// The member's scene, loaded: a bad value is an InputError naming `label` (the member and its values).
Scene member_scene(const Sweep& s, const std::vector<double>& v, const std::string& label) {
  json document = s.scene;
  for (std::size_t k = 0; k < v.size(); ++k) document[s.keys[k].ptr] = v[k];
  return parse_scene(document, s.file + " (" + label + ")");
}

std::string member_label(const Sweep& s, std::int64_t m, const std::vector<double>& v) {
  return "member " + std::to_string(m) + ": " + values_text(s, v);
}

// A key of the grid or the ranges: a JSON pointer to a number of the scene.
Key read_key(const Node& owner, const std::string& pointer, const json& scene) {
  const Node node = owner.at(pointer);
  Key key;
  key.pointer = pointer;
  if (pointer.empty() || pointer[0] != '/')
    node.fail("the key " + quoted_input(pointer) + " is not a JSON pointer into the scene (e.g. \"/initial/omega/2\")");
  try {
    key.ptr = json::json_pointer(pointer);
  } catch (const json::exception&) {
    node.fail("the key " + quoted_input(pointer) + " is not a valid JSON pointer (RFC 6901: '~' only as ~0 or ~1)");
  }
  if (pointer.find_first_of(",\"\r\n") != std::string::npos)
    node.fail("the key " + quoted_input(pointer) + " names a CSV column: it may not hold ',', '\"' or a line break");
  if (pointer == "/sweep" || pointer.rfind("/sweep/", 0) == 0) node.fail("a sweep cannot sweep its own \"sweep\" section");
  const json* target = nullptr;
  try {
    if (scene.contains(key.ptr)) target = &scene.at(key.ptr);
  } catch (const json::exception&) {
  }
  if (!target) node.fail(quoted_input(pointer) + " is not in the scene (the pointer must name an existing number)");
  if (!target->is_number())
    node.fail(quoted_input(pointer) + " points at " + describe(*target) + " in the scene, not at a number");
  return key;
}

std::vector<double> read_axis(const Node& node) {
  std::vector<double> values;
  if (node.is_array()) {
    if (node.size() == 0) node.fail("expected a non-empty array of numbers");
    for (std::size_t i = 0; i < node.size(); ++i) values.push_back(node.at(i).number());
    return values;
  }
  if (!node.is_object())
    node.fail("expected an array of numbers or {\"from\", \"to\", \"count\"}, got " + describe(node.value()));
  node.allow_only({"from", "to", "count", "log"});
  const double from = node.at("from").number(), to = node.at("to").number();
  const std::int64_t count = node.at("count").integer(1, max_members);
  bool log = false;
  if (const auto l = node.find("log")) {
    if (!l->value().is_boolean()) l->fail("expected true or false, got " + describe(l->value()));
    log = l->value().get<bool>();
  }
  if (log && !(from > 0)) node.at("from").fail("a log axis needs from > 0, got " + format_number(from));
  if (log && !(to > 0)) node.at("to").fail("a log axis needs to > 0, got " + format_number(to));
  const double a = log ? std::log(from) : from, b = log ? std::log(to) : to;
  for (std::int64_t k = 0; k < count; ++k) {
    double v = from;
    if (k == count - 1) v = count == 1 ? from : to;
    else if (k > 0) {
      const double x = a + ((b - a) * static_cast<double>(k)) / static_cast<double>(count - 1);
      v = log ? std::exp(x) : x;
    }
    values.push_back(v);
  }
  return values;
}

// The in-run sections of the sweep: /sweep/extrema, /sweep/section, /sweep/lyapunov (sweep_observe.hpp).
void read_observe(const Node& sweep, const Scene& scene0, ObserveSpec& spec) {
  const BodyData body = body_data(scene0);
  const std::string type = std::visit([](const auto& p) { return std::string(p.name); }, scene0.problem);
  const bool adaptive = scene0.options.rtol > 0;
  if (const auto extrema = sweep.find("extrema")) {
    if (!extrema->is_array() || extrema->size() == 0)
      extrema->fail("expected a non-empty array of state functions (e.g. [\"tilt\", \"omega3\"]), got " +
                    describe(extrema->value()));
    for (std::size_t i = 0; i < extrema->size(); ++i) {
      StateFunction f = read_state_function(extrema->at(i), body, type);
      for (const StateFunction& g : spec.extrema)
        if (g.name == f.name) extrema->at(i).fail(quoted_input(f.name) + " twice");
      spec.extrema.push_back(std::move(f));
    }
  }
  if (const auto section = sweep.find("section")) {
    if (!section->is_object()) section->fail("expected {\"function\", \"value\", \"direction\"}, got " + describe(section->value()));
    section->allow_only({"function", "value", "direction", "max_crossings"});
    if (adaptive)
      section->fail("crossings are located by side-steps of a fixed-step run: the scene's integrator has rtol and atol "
                    "(adaptive steps)");
    SectionSpec s;
    s.f = read_state_function(section->at("function"), body, type);
    s.value = section->at("value").number();
    if (const auto d = section->find("direction")) {
      const std::string dir = d->string();
      if (dir == "increasing") s.direction = 1;
      else if (dir == "decreasing") s.direction = -1;
      else if (dir == "both") s.direction = 0;
      else d->fail("expected \"increasing\", \"decreasing\" or \"both\", got " + quoted_input(dir));
    }
    if (const auto n = section->find("max_crossings")) s.max_crossings = n->integer(1, std::int64_t{1} << 53);
    spec.section = s;
  }
  if (const auto lyapunov = sweep.find("lyapunov")) {
    if (!lyapunov->is_object()) lyapunov->fail("expected an object ({} for the defaults), got " + describe(lyapunov->value()));
    lyapunov->allow_only({"d0", "interval", "omega_scale"});
    if (adaptive)
      lyapunov->fail("the Lyapunov estimate steps a shadow trajectory with the run's fixed steps: the scene's "
                     "integrator has rtol and atol (adaptive steps)");
    LyapunovSpec l;
    if (const auto d0 = lyapunov->find("d0")) {
      l.d0 = d0->positive();
      if (!(l.d0 <= 1e-3)) d0->fail("must be <= 1e-3 (a small displacement), got " + format_number(l.d0));
    }
    if (const auto interval = lyapunov->find("interval")) l.interval = interval->positive();
    if (const auto scale = lyapunov->find("omega_scale")) l.omega_scale = scale->positive();
    spec.lyapunov = l;
  } else if (const auto record = sweep.find("record")) {
    for (std::size_t i = 0; i < record->size(); ++i)
      if (record->at(i).string() == "lyapunov") {
        if (adaptive)
          record->at(i).fail("the Lyapunov estimate steps a shadow trajectory with the run's fixed steps: the scene's "
                             "integrator has rtol and atol (adaptive steps)");
        spec.lyapunov = LyapunovSpec{};
      }
  }
}

Sweep read_sweep(const std::string& file) {
  Sweep s;
  s.file = file;
  const json document = read_json_file(file);
  const Node root(document, "", file);
  if (!root.is_object()) root.fail("expected an object (a scene with a \"sweep\" section), got " + describe(document));
  const Node sweep = root.at("sweep");
  sweep.allow_only({"grid", "random", "record", "extrema", "section", "lyapunov"});
  s.scene = document;
  s.scene.erase("sweep");
  s.hash = fnv1a64(document.dump());
  if (sweep.find("grid") && sweep.find("random")) sweep.at("random").fail("give either \"grid\" or \"random\", not both");
  if (const auto grid = sweep.find("grid")) {
    if (!grid->is_object() || grid->value().empty())
      grid->fail("expected an object mapping JSON pointers to values, e.g. {\"/initial/omega/2\": [1, 2, 3]}, got " +
                 describe(grid->value()));
    s.members = 1;
    for (const auto& [pointer, value] : grid->value().items()) {
      Key key = read_key(*grid, pointer, s.scene);
      key.values = read_axis(grid->at(pointer));
      s.members *= static_cast<std::int64_t>(key.values.size());
      if (s.members > max_members)
        grid->fail("the grid has more than " + std::to_string(max_members) + " members (the product of the axes' sizes)");
      s.keys.push_back(std::move(key));
    }
  } else if (const auto random = sweep.find("random")) {
    s.random = true;
    random->allow_only({"seed", "count", "ranges"});
    s.seed = static_cast<std::uint64_t>(random->at("seed").integer(0, std::int64_t{1} << 53));
    s.members = random->at("count").integer(1, max_members);
    const Node ranges = random->at("ranges");
    if (!ranges.is_object() || ranges.value().empty())
      ranges.fail("expected an object mapping JSON pointers to [lo, hi], got " + describe(ranges.value()));
    for (const auto& [pointer, value] : ranges.value().items()) {
      Key key = read_key(ranges, pointer, s.scene);
      const Node range = ranges.at(pointer);
      if (!range.is_array() || range.size() != 2) range.fail("expected [lo, hi], got " + describe(range.value()));
      key.lo = range.at(0).number();
      key.hi = range.at(1).number();
      if (!(key.lo <= key.hi))
        range.fail("expected lo <= hi, got [" + format_number(key.lo) + ", " + format_number(key.hi) + "]");
      s.keys.push_back(std::move(key));
    }
  } else {
    sweep.fail("give \"grid\" (values per JSON pointer) or \"random\" (seed, count, ranges)");
  }

  // record: by default the three basic groups and each in-run group whose section the sweep gives.
  s.record = {Record::status, Record::final, Record::invariants};
  if (sweep.find("extrema")) s.record.push_back(Record::extrema);
  if (sweep.find("lyapunov")) s.record.push_back(Record::lyapunov);
  if (sweep.find("section")) s.record.push_back(Record::crossings);
  if (const auto record = sweep.find("record")) {
    if (!record->is_array() || record->size() == 0)
      record->fail("expected a non-empty array of column groups (status, final, invariants, extrema, lyapunov, "
                   "crossings), got " + describe(record->value()));
    s.record.clear();
    for (std::size_t i = 0; i < record->size(); ++i) {
      const Node r = record->at(i);
      const std::string name = r.string();
      const auto known = std::find_if(std::begin(record_names), std::end(record_names),
                                      [&](const char* n) { return name == n; });
      if (known == std::end(record_names))
        r.fail("unknown column group " + quoted_input(name) +
               " (known: status, final, invariants, extrema, lyapunov, crossings)");
      const auto what = static_cast<Record>(known - std::begin(record_names));
      if (s.records(what)) r.fail(quoted_input(name) + " twice");
      if (what == Record::extrema && !sweep.find("extrema"))
        r.fail("\"extrema\" needs /sweep/extrema, the state functions (e.g. [\"tilt\", \"omega3\"])");
      if (what == Record::crossings && !sweep.find("section"))
        r.fail("\"crossings\" needs /sweep/section (e.g. {\"function\": \"gamma1\", \"value\": 0, \"direction\": \"increasing\"})");
      s.record.push_back(what);
    }
    const auto recorded = [&](const char* key, Record what) {
      if (const auto n = sweep.find(key); n && !s.records(what))
        n->fail(std::string("given but not recorded: add \"") + record_names[static_cast<int>(what)] + "\" to /sweep/record");
    };
    recorded("extrema", Record::extrema);
    recorded("lyapunov", Record::lyapunov);
    recorded("section", Record::crossings);
  }
  if (const auto limits = root.find("limits"); limits && limits->is_object())
    if (const auto wall = limits->find("max_wall_seconds"))
      wall->fail("a sweep's rows may not depend on the machine's speed: use /limits/max_steps");

  // Every member is loaded again before it runs; here, before any output: member 0, and each value of each
  // grid axis (the others at member 0's) or each end of each random range — most bad values are caught now.
  const std::vector<double> v0 = member_values(s, 0);
  s.scene0 = member_scene(s, v0, member_label(s, 0, v0));
  const Scene& scene0 = s.scene0;
  read_observe(sweep, scene0, s.observe);
  std::int64_t stride = 1;
  for (std::size_t k = s.keys.size(); k-- > 0;) {
    if (s.random) {
      for (const double end : {s.keys[k].lo, s.keys[k].hi}) {
        std::vector<double> v = v0;
        v[k] = end;
        member_scene(s, v, "/sweep/random/ranges/" + pointer_token(s.keys[k].pointer) + ": " + values_text(s, v));
      }
      continue;
    }
    const auto n = static_cast<std::int64_t>(s.keys[k].values.size());
    for (std::int64_t i = 1; i < n; ++i) {
      std::vector<double> v = v0;
      v[k] = s.keys[k].values[static_cast<std::size_t>(i)];
      member_scene(s, v, member_label(s, i * stride, v));
    }
    stride *= n;
  }

  s.header = "member";
  for (const Key& key : s.keys) s.header += "," + key.pointer;
  const std::string final_header = csv_header(scene0);
  for (const Record r : s.record) {
    if (r == Record::status) s.header += ",status,steps";
    if (r == Record::final) s.header += "," + final_header;
    if (r == Record::invariants) {
      s.header += ",energy_rel_change";
      const std::string invariants = final_header.substr(final_header.find("orthogonality_error") + 19);
      std::size_t at = 0;
      while (at < invariants.size()) {  // ",name,name": each name + "_rel_change"
        const std::size_t next = invariants.find(',', at + 1);
        s.header += invariants.substr(at, next - at) + "_rel_change";
        at = next == std::string::npos ? invariants.size() : next;
      }
    }
    if (r == Record::extrema)
      for (const StateFunction& f : s.observe.extrema) s.header += "," + f.name + "_min," + f.name + "_max";
    if (r == Record::lyapunov) s.header += ",lyapunov,lyapunov_t";
    if (r == Record::crossings) s.header += ",crossings";
  }
  return s;
}

double relative_change(double initial, double final) {
  const double scale = std::abs(initial) > 0 ? std::abs(initial) : 1.0;
  return std::abs(final - initial) / scale;
}

// The status column's word for a failed step (StepStatus's names; to_string gives a sentence).
std::string status_token(StepStatus s) {
  switch (s) {
    case StepStatus::ok: return "ok";
    case StepStatus::not_converged: return "not_converged";
    case StepStatus::non_finite: return "non_finite";
    case StepStatus::step_size_underflow: return "step_size_underflow";
  }
  return "step_failed";
}

// The atomic output file, or nullptr after saying on stderr why it cannot be created (exit_io_error).
std::unique_ptr<AtomicOutput> open_output(const std::string& path) {
  try {
    return std::make_unique<AtomicOutput>(path);
  } catch (const std::exception& e) {
    fail(exit_io_error, e.what());
    return nullptr;
  }
}

// Commits the crossings file (if any), then the main file; when the main file cannot be committed, the crossings
// file just renamed into place is removed again. false: failed, with the message on stderr.
bool commit_outputs(AtomicOutput& out, const std::string& path, AtomicOutput* crossings) {
  const std::string cpath = crossings_path(path);
  if (crossings && !crossings->commit()) {
    fail(exit_io_error, cpath + ": cannot write the crossings file: " + std::strerror(errno));
    return false;
  }
  if (!out.commit()) {
    fail(exit_io_error, path + ": cannot write the output file: " + std::strerror(errno));
    if (crossings) std::remove(cpath.c_str());
    return false;
  }
  return true;
}

enum class Outcome { completed, failed, stopped };

struct MemberResult {
  std::string row;
  std::string crossings;  // the member's rows of the crossings file
  Outcome outcome = Outcome::completed;
};

// Member m's row (and crossing rows) from its run's report: the same for a member run by the runner and one run
// in a batch (run_batch below).
MemberResult member_result(const Sweep& s, std::int64_t m, const std::vector<double>& v, const RunReport& r,
                           MemberObserver* observer) {
  MemberResult result;
  std::string& row = result.row;
  row = std::to_string(m);
  for (const double x : v) append_csv_number(row, x);
  const IntegrationSummary& summary = r.summary;
  if (summary.status == RunStatus::stopped) result.outcome = Outcome::stopped;
  else if (summary.status != RunStatus::completed) result.outcome = Outcome::failed;
  for (const Record what : s.record) {
    if (what == Record::status) {
      std::string status = "completed";
      if (r.stop_reason == StopReason::left_domain) status = "left_domain";
      else if (r.stop_reason == StopReason::max_steps) status = "max_steps";
      else if (summary.status == RunStatus::step_failed) status = status_token(summary.step_status);
      else if (summary.status == RunStatus::stopped) status = "stopped";
      row += "," + status + "," + std::to_string(summary.steps);
    }
    if (what == Record::final) {
      const State<double>& x = r.final_state;
      append_csv_number(row, summary.t);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) append_csv_number(row, x.R(i, j));
      for (int i = 0; i < 3; ++i) append_csv_number(row, x.Omega(i));
      append_csv_number(row, r.energy_final);
      append_csv_number(row, so3::orthogonality_error(x.R));
      for (const InvariantChange& inv : r.invariants) append_csv_number(row, inv.final);
    }
    if (what == Record::invariants) {
      append_csv_number(row, relative_change(r.energy_initial, r.energy_final));
      for (const InvariantChange& inv : r.invariants) append_csv_number(row, relative_change(inv.initial, inv.final));
    }
    if (what == Record::extrema) observer->append_extrema(row);
    if (what == Record::lyapunov) observer->append_lyapunov(row);
    if (what == Record::crossings) observer->append_crossing_count(row);
  }
  row += '\n';
  if (observer) result.crossings = std::move(observer->crossing_rows());
  return result;
}

MemberResult run_member(const Sweep& s, std::int64_t m, const volatile std::sig_atomic_t* stop) {
  const std::vector<double> v = member_values(s, m);
  Scene scene = member_scene(s, v, member_label(s, m, v));
  // No rows are written: no side-steps to the scene's output times (the trajectory does not depend on them).
  scene.output_times.clear();
  scene.output_every = 0;
  RunOptions options;  // no rows, no progress, no checkpoints
  options.stop = stop;
  std::optional<MemberObserver> observer;
  if (s.observe.any()) {
    observer.emplace(s.observe, body_data(scene), std::to_string(m) + ",");
    options.observer = &*observer;
  }
  return member_result(s, m, v, run_scene(scene, options), observer ? &*observer : nullptr);
}

// ---- the batched path --------------------------------------------------------------------------------------
// A sweep qualifies when every member is an LGVI run of the same heavy top or free body with diagonal J (the
// kernel's condition; integrators/batch_lgvi.hpp) over the same whole number of steps, the members differing only
// in their initial state and b: its keys are all under /initial/ or /problem/b, t_end is on the grid, no
// limits.max_steps, nothing recorded during the run. Its members then run in blocks through
// integrate_batch_lgvi, whose results equal the single-body Lgvi's bit for bit (tests/test_batch.cpp); the rows
// are built from them exactly as from the runner's report (tests/test_cli_sweep.cpp compares the bytes with
// --no-batch). Members longer than batch_max_steps run one by one, so that a signal still stops them within
// 1024 steps; a block (≤ batch_block_work body-steps) runs to its end before a signal is seen.
inline constexpr std::int64_t batch_max_steps = std::int64_t{1} << 20;
inline constexpr std::int64_t batch_block_work = std::int64_t{1} << 22;

// The number of steps of each member when the sweep qualifies for the batched path (0 otherwise; `why` says why).
std::int64_t batch_steps(const Sweep& s, const Scene& scene0, std::string& why) {
  const bool heavy = std::holds_alternative<HeavyTop<double>>(scene0.problem);
  const bool free_body = std::holds_alternative<FreeBody<double>>(scene0.problem);
  const auto no = [&](const std::string& reason) {
    why = reason;
    return std::int64_t{0};
  };
  if (scene0.method->traits.name != "lgvi") return no("the method is not lgvi");
  if (!heavy && !free_body) return no("the problem is not heavy_top or free_body");
  const Mat3<double>& J = heavy ? std::get<HeavyTop<double>>(scene0.problem).inertia
                                : std::get<FreeBody<double>>(scene0.problem).inertia;
  if (!Inertia<double>(J).diagonal) return no("the inertia tensor is not diagonal");
  for (const Key& key : s.keys)
    if (key.pointer.rfind("/initial/", 0) != 0 && !(heavy && key.pointer == "/problem/b"))
      return no("the members differ in " + key.pointer + " (batched: /initial/... and /problem/b only)");
  if (s.observe.any()) return no("the sweep records extrema, crossings or Lyapunov estimates during the run");
  if (scene0.max_steps > 0) return no("the scene has limits.max_steps");
  const lgi::detail::GridPoint end = lgi::detail::locate(0.0, scene0.dt, scene0.t_end);
  if (!(scene0.t_end > 0) || !end.on_grid) return no("t_end is not a whole number of steps");
  if (end.m > batch_max_steps) return no("the members take more than 2^20 steps each (one by one, signals stop them sooner)");
  return end.m;
}

// Members k_begin … k_end − 1 of this shard (m = shard + k·shards) through the batched LGVI; results in k order.
const char* kernel_name(int kernel) {
  switch (static_cast<BatchKernel>(kernel)) {
    case BatchKernel::baseline: return "baseline";
    case BatchKernel::avx2: return "avx2";
    case BatchKernel::avx512: return "avx512";
    case BatchKernel::per_body: return "per-body";
    case BatchKernel::automatic: break;
  }
  return "none";
}

// `member` follows the member being loaded (a bad one throws), then names the block's first for the kernel.
std::vector<MemberResult> run_batch(const Sweep& s, std::int64_t k_begin, std::int64_t k_end, std::int64_t shard,
                                    std::int64_t shards, std::int64_t n_steps, BatchKernel& kernel, std::int64_t& member) {
  const auto count = static_cast<std::size_t>(k_end - k_begin);
  std::vector<std::vector<double>> values(count);
  std::vector<Scene> scenes;
  scenes.reserve(count);
  BodyBatch batch(count);
  std::vector<double> b;
  for (std::size_t i = 0; i < count; ++i) {
    const std::int64_t m = shard + (k_begin + static_cast<std::int64_t>(i)) * shards;
    member = m;
    values[i] = member_values(s, m);
    scenes.push_back(member_scene(s, values[i], member_label(s, m, values[i])));
    batch.set_state(i, scenes[i].initial);
    if (const auto* top = std::get_if<HeavyTop<double>>(&scenes[i].problem)) b.push_back(top->b);
  }
  const Scene& scene0 = scenes.front();
  const double dt = scene0.dt;
  member = shard + k_begin * shards;
  std::visit(
      [&](const auto& problem) {
        using P = std::decay_t<decltype(problem)>;
        if constexpr (LgviBatchProblem<P>)
          kernel = integrate_batch_lgvi(problem, batch, 0.0, dt, n_steps, scene0.options, BatchOptions{1},
                                        std::span<const double>(b));
        else
          throw std::logic_error("lgi sweep: a batch of problem " + std::string(P::name));
      },
      scene0.problem);

  std::vector<MemberResult> results;
  results.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Scene& scene = scenes[i];
    RunReport r;  // what run_scene reports for the same member (runner_impl.hpp, run_stepper and drive_grid)
    r.summary.steps = batch.steps[i];
    if (batch.status[i] == StepStatus::ok) {
      r.summary.t = scene.t_end;
    } else {
      r.summary.status = RunStatus::step_failed;
      r.summary.step_status = batch.status[i];
      r.summary.t = static_cast<double>(batch.steps[i]) * dt;
    }
    r.final_state = batch.steps[i] > 0 ? batch.state(i) : scene.initial;  // not moved: the state as given
    std::visit(
        [&](const auto& problem) {
          using P = std::decay_t<decltype(problem)>;
          if constexpr (LgviBatchProblem<P>) {
            r.energy_initial = energy_at(problem, 0.0, scene.initial);
            r.energy_final = energy_at(problem, r.summary.t, r.final_state);
            const auto inv0 = invariants_at(problem, 0.0, scene.initial);
            const auto inv1 = invariants_at(problem, r.summary.t, r.final_state);
            for (std::size_t j = 0; j < inv0.size(); ++j)
              r.invariants.push_back({std::string(P::invariant_names[j]), inv0[j], inv1[j]});
          }
        },
        scene.problem);
    results.push_back(member_result(s, shard + (k_begin + static_cast<std::int64_t>(i)) * shards, values[i], r, nullptr));
  }
  return results;
}

// The first line of a part file; `what`: "" for the rows, " crossings" for the crossings.
std::string shard_line(std::int64_t i, std::int64_t n, std::int64_t members, std::uint64_t hash, const char* what = "") {
  return std::string("# lgi sweep") + what + " shard " + std::to_string(i) + "/" + std::to_string(n) + ": " + std::to_string(members) +
         " members, sweep " + hex64(hash) + ", lgi " + LGI_VERSION;
}

// "i/N" with 0 <= i < N, both decimal integers.
bool parse_shard(const std::string& text, std::int64_t& i, std::int64_t& n) {
  const std::size_t slash = text.find('/');
  if (slash == std::string::npos) return false;
  const auto number = [](const std::string& t, std::int64_t& x) {
    if (t.empty() || t.size() > 9 || t.find_first_not_of("0123456789") != std::string::npos) return false;
    x = std::stoll(t);
    return true;
  };
  return number(text.substr(0, slash), i) && number(text.substr(slash + 1), n) && n >= 1 && i < n;
}

}  // namespace

std::string crossings_path(const std::string& output) {
  const std::string suffix = ".csv";
  if (output.size() > suffix.size() && output.compare(output.size() - suffix.size(), suffix.size(), suffix) == 0)
    return output.substr(0, output.size() - suffix.size()) + ".crossings.csv";
  return output + ".crossings.csv";
}

double sweep_uniform(std::uint64_t seed, std::uint64_t member, const std::string& pointer) {
  const std::uint64_t x = splitmix64(seed ^ splitmix64(fnv1a64(pointer) ^ splitmix64(member)));
  return static_cast<double>(x >> 11) * 0x1p-53;
}

int sweep_command(const SweepCommandOptions& options) {
  std::int64_t shard = 0, shards = 1;
  const bool sharded = !options.shard.empty();
  if (sharded && !parse_shard(options.shard, shard, shards))
    return fail(exit_bad_input, "--shard: expected i/N with 0 <= i < N (e.g. 0/4), got " + quoted_input(options.shard));
  if (options.threads < 0) return fail(exit_bad_input, "--threads: expected 0 (all cores) or a positive number");
  if (options.output.empty()) return fail(exit_bad_input, "sweep: -o FILE is required");
  Sweep s;
  try {
    s = read_sweep(options.sweep_file);
  } catch (const InputError& e) {
    return fail(exit_bad_input, e.what());
  }
  // This shard's members: m = shard + k * shards, k = 0 ... count - 1.
  const std::int64_t count = s.members > shard ? (s.members - shard + shards - 1) / shards : 0;
  unsigned threads = options.threads > 0 ? static_cast<unsigned>(options.threads) : std::thread::hardware_concurrency();
  threads = static_cast<unsigned>(std::clamp<std::int64_t>(std::min<std::int64_t>(threads, count), 1, 4096));

  const std::unique_ptr<AtomicOutput> out = open_output(options.output);
  if (!out) return exit_io_error;
  std::FILE* f = out->file();
  std::string head;
  if (sharded) head = shard_line(shard, shards, s.members, s.hash) + "\n";
  head += s.header + "\n";
  bool write_failed = std::fwrite(head.data(), 1, head.size(), f) != head.size();
  // The crossings file beside it (when recorded), written and committed alongside.
  std::unique_ptr<AtomicOutput> crossings_out;
  std::FILE* cf = nullptr;
  if (s.records(Record::crossings)) {
    crossings_out = open_output(crossings_path(options.output));
    if (!crossings_out) return exit_io_error;
    cf = crossings_out->file();
    std::string chead;
    if (sharded) chead = shard_line(shard, shards, s.members, s.hash, " crossings") + "\n";
    chead += std::string(crossings_header) + "\n";
    write_failed = write_failed || std::fwrite(chead.data(), 1, chead.size(), cf) != chead.size();
  }

  const auto start = std::chrono::steady_clock::now();
  std::atomic<std::int64_t> next{0};
  std::atomic<bool> abort{false};
  std::mutex mutex;  // guards everything below
  std::map<std::int64_t, MemberResult> pending;  // finished rows waiting for the ones before them
  std::int64_t written = 0;
  std::int64_t outcomes[3] = {0, 0, 0};
  std::optional<std::pair<std::int64_t, std::string>> error;  // the lowest failing member seen, and its message
  int error_status = exit_bad_input;
  // The batched path (run_batch) when the sweep qualifies and --no-batch is not given: blocks of members.
  std::string why_not = "--no-batch";
  const std::int64_t n_steps = options.batch ? batch_steps(s, s.scene0, why_not) : 0;
  // Blocks of at most batch_block_work body-steps, at least 4 per thread when there are enough members.
  const std::int64_t per_thread = (count + 4 * std::int64_t{threads} - 1) / (4 * std::int64_t{threads});
  const std::int64_t block =
      n_steps > 0 ? std::clamp<std::int64_t>(std::min(batch_block_work / n_steps, per_thread), 4, 1024) : 1;
  std::atomic<int> kernel_used{-1};
  const auto work = [&] {
    for (;;) {
      const std::int64_t k0 = next.fetch_add(block);
      if (k0 >= count || abort.load() || (options.stop && *options.stop)) return;
      const std::int64_t k1 = std::min(count, k0 + block);
      std::int64_t m = shard + k0 * shards;
      std::vector<MemberResult> results;
      try {
        if (n_steps > 0) {
          BatchKernel kernel = BatchKernel::automatic;
          results = run_batch(s, k0, k1, shard, shards, n_steps, kernel, m);
          kernel_used = static_cast<int>(kernel);
        } else {
          results.push_back(run_member(s, m, options.stop));
        }
      } catch (const std::exception& e) {
        const std::lock_guard lock(mutex);
        if (!error || m < error->first) {
          error.emplace(m, e.what());
          error_status = dynamic_cast<const InputError*>(&e) ? exit_bad_input : exit_internal_error;
        }
        abort = true;
        return;
      }
      const std::lock_guard lock(mutex);
      for (std::size_t i = 0; i < results.size(); ++i) {
        ++outcomes[static_cast<int>(results[i].outcome)];
        pending.emplace(k0 + static_cast<std::int64_t>(i), std::move(results[i]));
      }
      for (auto it = pending.begin(); it != pending.end() && it->first == written; it = pending.erase(it), ++written) {
        const std::string& row = it->second.row;
        write_failed = write_failed || std::fwrite(row.data(), 1, row.size(), f) != row.size();
        const std::string& c = it->second.crossings;
        if (cf && !c.empty()) write_failed = write_failed || std::fwrite(c.data(), 1, c.size(), cf) != c.size();
      }
    }
  };
  std::vector<std::thread> workers;
  for (unsigned t = 1; t < threads; ++t) workers.emplace_back(work);
  work();
  for (std::thread& t : workers) t.join();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  if (options.stop && *options.stop) {  // `out` removes its temporary file: nothing is written
    const int signal = *options.stop;
    return fail(128 + signal, std::string("sweep interrupted by ") + (signal == SIGINT ? "SIGINT" : "SIGTERM") + " after " +
                                  std::to_string(written) + " of " + std::to_string(count) +
                                  " members: nothing written (rerun, or run it in shards with --shard)");
  }
  if (error) {
    if (error_status == exit_internal_error) return fail(exit_internal_error, "internal error: " + error->second);
    return fail(exit_bad_input, error->second);
  }
  if (write_failed || written != count) return fail(exit_io_error, options.output + ": write error");
  if (!commit_outputs(*out, options.output, crossings_out.get())) return exit_io_error;
  if (!options.quiet) {
    char buf[1024];
    std::snprintf(buf, sizeof buf,
                  "%s: %lld members%s, %u thread%s, %s, %.3f s (%.1f members/s): %lld completed, %lld step failed, "
                  "%lld stopped; %s\n",
                  options.sweep_file.c_str(), static_cast<long long>(s.members),
                  sharded ? (" (shard " + options.shard + ": " + std::to_string(count) + ")").c_str() : "", threads,
                  threads == 1 ? "" : "s",
                  n_steps > 0 ? (std::string("batched LGVI (") + kernel_name(kernel_used.load()) + " kernel)").c_str()
                              : ("member by member (not batched: " + why_not + ")").c_str(),
                  seconds, seconds > 0 ? static_cast<double>(count) / seconds : 0.0,
                  static_cast<long long>(outcomes[0]), static_cast<long long>(outcomes[1]),
                  static_cast<long long>(outcomes[2]), options.output.c_str());
    std::fputs(buf, stderr);
  }
  return 0;
}

int merge_command(const MergeCommandOptions& options) {
  if (options.output.empty()) return fail(exit_bad_input, "merge: -o FILE is required");
  if (options.parts.empty()) return fail(exit_bad_input, "merge: give the part files of a sweep (lgi sweep --shard)");
  struct Part {
    std::string file;
    std::int64_t i = 0, n = 0, members = 0;
    std::string line, header;
    std::unique_ptr<std::ifstream> in;
    std::int64_t line_number = 2;
    // the part's crossings file (when the sweep records crossings)
    std::string cfile;
    std::unique_ptr<std::ifstream> cin;
    std::int64_t cline_number = 2;
  };
  std::vector<Part> parts;
  for (const std::string& file : options.parts) {
    Part p;
    p.file = file;
    p.in = std::make_unique<std::ifstream>(file, std::ios::binary);
    if (!*p.in) return fail(exit_bad_input, file + ": cannot read the part file: " + std::strerror(errno));
    std::getline(*p.in, p.line);
    char hash[32] = {};
    long long i = 0, n = 0, members = 0;
    if (std::sscanf(p.line.c_str(), "# lgi sweep shard %lld/%lld: %lld members, sweep %16s", &i, &n, &members, hash) != 4 ||
        n < 1 || i < 0 || i >= n || members < 1)
      return fail(exit_bad_input, file + ":1: not a part file of lgi sweep --shard (expected \"# lgi sweep shard i/N: ...\")");
    p.i = i;
    p.n = n;
    p.members = members;
    if (!std::getline(*p.in, p.header)) return fail(exit_bad_input, file + ":2: the CSV header is missing");
    const Part* first = parts.empty() ? nullptr : &parts.front();
    if (first) {
      // Everything but the shard index must be the first part's: the same sweep, split the same way.
      const std::string mine = p.line.substr(p.line.find(':')), theirs = first->line.substr(first->line.find(':'));
      if (mine != theirs || p.n != first->n)
        return fail(exit_bad_input, file + ":1: a shard of another sweep, split or lgi version (\"" + p.line + "\"; " +
                                        first->file + " has \"" + first->line + "\")");
      if (p.header != first->header)
        return fail(exit_bad_input, file + ":2: the CSV header differs from " + first->file + "'s");
      for (const Part& q : parts)
        if (q.i == p.i)
          return fail(exit_bad_input, file + ": shard " + std::to_string(p.i) + "/" + std::to_string(p.n) +
                                          " again (also " + q.file + ")");
    }
    parts.push_back(std::move(p));
  }
  const std::int64_t n = parts.front().n, members = parts.front().members;
  if (static_cast<std::int64_t>(parts.size()) != n) {
    std::string missing;
    for (std::int64_t i = 0; i < n; ++i)
      if (std::none_of(parts.begin(), parts.end(), [&](const Part& p) { return p.i == i; }))
        missing += (missing.empty() ? "" : ", ") + std::to_string(i) + "/" + std::to_string(n);
    return fail(exit_bad_input, "merge: shard " + missing + " of the sweep in " + parts.front().file + " is missing");
  }
  std::sort(parts.begin(), parts.end(), [](const Part& a, const Part& b) { return a.i < b.i; });

  // A sweep that records crossings has a "crossings" column (the member's count) and, beside each part, its
  // crossings part: "# lgi sweep crossings shard ..." (the rest as the part's first line), the crossings header,
  // then each member's crossing rows in member order.
  const std::vector<std::string> columns = [&] {
    std::vector<std::string> c;
    std::string cell;
    std::istringstream in(parts.front().header);
    while (std::getline(in, cell, ',')) c.push_back(cell);
    return c;
  }();
  const auto count_column = std::find(columns.begin(), columns.end(), "crossings");
  const bool crossings = count_column != columns.end();
  const std::size_t count_index = static_cast<std::size_t>(count_column - columns.begin());
  if (crossings)
    for (Part& p : parts) {
      p.cfile = crossings_path(p.file);
      p.cin = std::make_unique<std::ifstream>(p.cfile, std::ios::binary);
      if (!*p.cin)
        return fail(exit_bad_input, p.cfile + ": cannot read the crossings part of " + p.file + ": " + std::strerror(errno));
      std::string line, header;
      std::getline(*p.cin, line);
      const std::string expected = "# lgi sweep crossings" + p.line.substr(std::string("# lgi sweep").size());
      if (line != expected)
        return fail(exit_bad_input, p.cfile + ":1: not the crossings part of " + p.file + " (expected \"" + expected + "\")");
      if (!std::getline(*p.cin, header) || header != crossings_header)
        return fail(exit_bad_input, p.cfile + ":2: expected the crossings header \"" + std::string(crossings_header) + "\"");
    }

  const std::unique_ptr<AtomicOutput> out = open_output(options.output);
  if (!out) return exit_io_error;
  std::FILE* f = out->file();
  bool write_failed = std::fputs((parts.front().header + "\n").c_str(), f) < 0;
  std::unique_ptr<AtomicOutput> crossings_out;
  std::FILE* cf = nullptr;
  if (crossings) {
    crossings_out = open_output(crossings_path(options.output));
    if (!crossings_out) return exit_io_error;
    cf = crossings_out->file();
    write_failed = write_failed || std::fputs((std::string(crossings_header) + "\n").c_str(), cf) < 0;
  }
  std::string row, crossing;
  for (std::int64_t m = 0; m < members; ++m) {
    Part& p = parts[static_cast<std::size_t>(m % n)];
    ++p.line_number;
    const std::string expected = std::to_string(m) + ",";
    if (!std::getline(*p.in, row) || row.compare(0, expected.size(), expected) != 0)
      return fail(exit_bad_input, p.file + ":" + std::to_string(p.line_number) + ": expected the row of member " +
                                      std::to_string(m) + (p.in->eof() ? ", the file ends (an unfinished shard?)" : ""));
    if (crossings) {
      // the member's crossing count, then as many rows of its crossings part
      std::size_t at = 0;
      for (std::size_t c = 0; c < count_index && at != std::string::npos; ++c) at = row.find(',', at) + 1;
      const long long count = at != std::string::npos && at > 0 ? std::atoll(row.c_str() + at) : -1;
      if (count < 0)
        return fail(exit_bad_input, p.file + ":" + std::to_string(p.line_number) + ": no crossings count in the row");
      for (long long k = 0; k < count; ++k) {
        ++p.cline_number;
        if (!std::getline(*p.cin, crossing) || crossing.compare(0, expected.size(), expected) != 0)
          return fail(exit_bad_input, p.cfile + ":" + std::to_string(p.cline_number) + ": expected crossing " +
                                          std::to_string(k) + " of member " + std::to_string(m) + " (" +
                                          std::to_string(count) + " in " + p.file + ")" +
                                          (p.cin->eof() ? ", the file ends (an unfinished shard?)" : ""));
        crossing += '\n';
        write_failed = write_failed || std::fwrite(crossing.data(), 1, crossing.size(), cf) != crossing.size();
      }
    }
    row += '\n';
    write_failed = write_failed || std::fwrite(row.data(), 1, row.size(), f) != row.size();
  }
  for (Part& p : parts) {
    if (std::getline(*p.in, row))
      return fail(exit_bad_input, p.file + ":" + std::to_string(p.line_number + 1) + ": a row after the shard's last member");
    if (crossings && std::getline(*p.cin, row))
      return fail(exit_bad_input, p.cfile + ":" + std::to_string(p.cline_number + 1) +
                                      ": a crossing beyond those the part's rows count");
  }
  if (write_failed) return fail(exit_io_error, options.output + ": write error");
  if (!commit_outputs(*out, options.output, crossings_out.get())) return exit_io_error;
  if (!options.quiet)
    std::fprintf(stderr, "merged %lld members from %lld shards into %s\n", static_cast<long long>(members),
                 static_cast<long long>(n), options.output.c_str());
  return 0;
}

}  // namespace lgi::app
