// lgi/apps/sweep_file.hpp — sweep files (sweep_command.hpp has the format): read, checked, and their members.
#pragma once

#include "json_reader.hpp"
#include "scene.hpp"
#include "sweep_observe.hpp"

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace lgi::app {

inline constexpr std::int64_t max_members = 10'000'000;

enum class Record { status, final, invariants, extrema, lyapunov, crossings };
inline constexpr const char* record_names[] = {"status", "final", "invariants", "extrema", "lyapunov", "crossings"};

struct SweepKey {
  std::string pointer;
  json::json_pointer ptr;
  std::vector<double> values;  // grid: the axis's values
  double lo = 0, hi = 0;       // random: the range
};

struct Sweep {
  std::string file;
  json scene;  // the sweep file without its "sweep" section
  bool random = false;
  std::vector<SweepKey> keys;
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
inline constexpr const char* crossings_header =
    "member,crossing,t,R11,R12,R13,R21,R22,R23,R31,R32,R33,omega1,omega2,omega3";

// Reads and checks a sweep file: every key, axis and range, the records, and member 0 and each value of each axis
// (or each end of each range) loaded as a scene — most bad values are caught before anything runs. Throws
// InputError naming the file and the JSON path.
Sweep read_sweep(const std::string& file);
Sweep parse_sweep(const json& document, const std::string& file);

// Member m's values, one per key (the grid's order, or the random sweep's sweep_uniform).
std::vector<double> member_values(const Sweep& s, std::int64_t m);
// "/initial/omega/0 = 2, /problem/b = 1" for messages.
std::string values_text(const Sweep& s, const std::vector<double>& v);
// The member's scene, loaded: a bad value is an InputError naming `label` (the member and its values).
Scene member_scene(const Sweep& s, const std::vector<double>& v, const std::string& label);
// "member 12: /initial/omega/0 = 2"
std::string member_label(const Sweep& s, std::int64_t m, const std::vector<double>& v);

}  // namespace lgi::app
