// lgi/apps/sweep_file.cpp — reading sweep files and their members (sweep_file.hpp).
#include "sweep_file.hpp"

#include "hashing.hpp"
#include "runner.hpp"
#include "sweep_command.hpp"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace lgi::app {

namespace {

// splitmix64's output function applied to z + the golden-ratio increment (Vigna, splitmix64.c).
std::uint64_t splitmix64(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// A key of the grid or the ranges: a JSON pointer to a number of the scene.
SweepKey read_key(const Node& owner, const std::string& pointer, const json& scene) {
  const Node node = owner.at(pointer);
  SweepKey key;
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
  const std::string type(scene0.problem->type_name());
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

}  // namespace

std::vector<double> member_values(const Sweep& s, std::int64_t m) {
  std::vector<double> v(s.keys.size());
  if (s.random) {
    for (std::size_t k = 0; k < s.keys.size(); ++k) {
      const SweepKey& key = s.keys[k];
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

Scene member_scene(const Sweep& s, const std::vector<double>& v, const std::string& label) {
  json document = s.scene;
  for (std::size_t k = 0; k < v.size(); ++k) document[s.keys[k].ptr] = v[k];
  // The label names the member in messages; file names in the scene (a torque table) are the sweep file's.
  const std::string directory = std::filesystem::path(s.file).parent_path().string();
  return parse_scene(document, s.file + " (" + label + ")", directory.empty() ? std::string(".") : directory);
}

std::string member_label(const Sweep& s, std::int64_t m, const std::vector<double>& v) {
  return "member " + std::to_string(m) + ": " + values_text(s, v);
}

Sweep parse_sweep(const json& document, const std::string& file) {
  Sweep s;
  s.file = file;
  const Node root(document, "", file);
  if (!root.is_object()) root.fail("expected an object (a scene with a \"sweep\" section), got " + describe(document));
  const Node sweep = root.at("sweep");
  sweep.allow_only({"grid", "random", "record", "extrema", "section", "lyapunov"});
  s.scene = document;
  s.scene.erase("sweep");
  s.hash = fnv1a(document.dump());
  if (sweep.find("grid") && sweep.find("random")) sweep.at("random").fail("give either \"grid\" or \"random\", not both");
  if (const auto grid = sweep.find("grid")) {
    if (!grid->is_object() || grid->value().empty())
      grid->fail("expected an object mapping JSON pointers to values, e.g. {\"/initial/omega/2\": [1, 2, 3]}, got " +
                 describe(grid->value()));
    s.members = 1;
    for (const auto& [pointer, value] : grid->value().items()) {
      SweepKey key = read_key(*grid, pointer, s.scene);
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
      SweepKey key = read_key(ranges, pointer, s.scene);
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
               did_you_mean(name, std::vector<std::string_view>(std::begin(record_names), std::end(record_names))) +
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
  // The files the scene reads (a torque table; the same for every member: a sweep varies numbers) are part of the
  // sweep: shards computed with different tables are parts of different sweeps, and lgi merge refuses to join them.
  for (const auto& input : scene0.problem->input_files()) s.hash = fnv1a(&input.second, sizeof input.second, s.hash);
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
  for (const SweepKey& key : s.keys) s.header += "," + key.pointer;
  const std::string final_header = csv_header(scene0);
  for (const Record r : s.record) {
    if (r == Record::status) s.header += ",status,steps";
    if (r == Record::final) s.header += "," + final_header;
    if (r == Record::invariants) {  // the integrals of the motion only (not the Euler angles)
      s.header += ",energy_rel_change";
      for (const std::string& name : integral_names(scene0)) s.header += "," + name + "_rel_change";
    }
    if (r == Record::extrema)
      for (const StateFunction& f : s.observe.extrema) s.header += "," + f.name + "_min," + f.name + "_max";
    if (r == Record::lyapunov) s.header += ",lyapunov,lyapunov_t";
    if (r == Record::crossings) s.header += ",crossings";
  }
  return s;
}

Sweep read_sweep(const std::string& file) { return parse_sweep(read_json_file(file), file); }

double sweep_uniform(std::uint64_t seed, std::uint64_t member, const std::string& pointer) {
  const std::uint64_t x = splitmix64(seed ^ splitmix64(fnv1a(pointer) ^ splitmix64(member)));
  return static_cast<double>(x >> 11) * 0x1p-53;
}

std::string crossings_path(const std::string& output) {
  const std::string suffix = ".csv";
  if (output.size() > suffix.size() && output.compare(output.size() - suffix.size(), suffix.size(), suffix) == 0)
    return output.substr(0, output.size() - suffix.size()) + ".crossings.csv";
  return output + ".crossings.csv";
}

}  // namespace lgi::app
