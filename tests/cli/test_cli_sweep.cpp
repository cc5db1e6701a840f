// `lgi sweep` and `lgi merge`, run as separate processes (apps/sweep_command.hpp, docs/sweep.md): the grid's
// member order and values, random members reproducible, in range and as the documented generator gives them; a
// member's row equal character for character to the last row `lgi run` writes for the scene with the member's
// values (a completed member and one whose step fails mid-run); --threads 1/2/3 and --shard i/3 + merge give the
// serial run's bytes; bad sweep files, shard specs and part sets end in exit 1, one line naming the problem, no
// output file.
#include "../apps/hashing.hpp"
#include "lgi_process.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using lgi::test::CommandResult;
using lgi::test::slurp;

using lgi::test::split;

std::vector<std::string> lines_of(const std::string& text) { return split(text, '\n'); }

// The heavy top of scenes/heavy_top.json over a short time (10 steps), with the sweep section appended.
std::string heavy_top_sweep(const std::string& sweep) {
  return R"({"problem": {"type": "heavy_top", "inertia": [2.0, 2.0, 1.0], "b": 1.0, "k": [0.0, 0.6, 0.8],
              "z0": [0.0, 0.0, 1.0]},
             "initial": {"omega": [0.1, 0.2, 5.0]},
             "integrator": {"method": "lgvi", "dt": 0.01}, "t_end": 0.1)" +
         (sweep.empty() ? std::string() : ", \"sweep\": " + sweep) + "}";
}

// In-run records for the heavy top of heavy_top_sweep over t_end = 0.1: its body axes turn at |Ω| ≈ 5 rad/s, so
// R11 = cos(5t) … crosses 0.9 once in 0.1 s; extrema of the tilt and of ω3, a Lyapunov estimate.
const char* const observed_records = R"("extrema": ["tilt", "omega3"], "lyapunov": {"interval": 0.02},
                                        "section": {"function": "R11", "value": 0.99, "direction": "both"})";

class CliSweep : public lgi::test::CommandTest {
 protected:
  CliSweep() : CommandTest("cli_sweep") {}

  // lgi sweep FILE -o OUT ARGS; returns the result (OUT's bytes via slurp).
  CommandResult sweep(const std::string& file, const std::string& out, const std::string& args = "") {
    return lgi("sweep " + (dir_ / file).string() + " -o " + (dir_ / out).string() + " " + args);
  }
  std::string read(const std::string& name) { return slurp(dir_ / name); }

  // Nothing in dir_ but the files named: no output, no temporary file.
  void expect_only(const std::vector<std::string>& names) {
    for (const auto& entry : fs::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      EXPECT_NE(std::find(names.begin(), names.end(), name), names.end()) << "unexpected file " << name;
    }
  }
};

// Two axes: keys in byte order ("/initial/omega/2" < "/problem/b"), the last varying fastest; a linear and a
// log {"from", "to", "count"} axis; the header; every member completes its 10 steps.
TEST_F(CliSweep, GridMembersComeInDocumentedOrderWithTheirValues) {
  write("grid.json", heavy_top_sweep(R"({"grid": {"/problem/b": {"from": 0.5, "to": 1.5, "count": 3},
                                                  "/initial/omega/2": [3, 5]}})"));
  const CommandResult r = sweep("grid.json", "out.csv");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.out.empty());
  EXPECT_NE(r.err.find("6 members"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("6 completed, 0 step failed, 0 stopped"), std::string::npos) << r.err;
  const auto lines = lines_of(read("out.csv"));
  ASSERT_EQ(lines.size(), 7u);
  EXPECT_EQ(lines[0],
            "member,/initial/omega/2,/problem/b,status,steps,t,R11,R12,R13,R21,R22,R23,R31,R32,R33,omega1,omega2,omega3,"
            "energy,orthogonality_error,momentum_k,energy_rel_change,momentum_k_rel_change");
  const double omega[] = {3, 5}, b[] = {0.5, 1.0, 1.5};
  for (int m = 0; m < 6; ++m) {
    const auto cells = split(lines[static_cast<std::size_t>(m) + 1], ',');
    ASSERT_EQ(cells.size(), 23u);
    EXPECT_EQ(cells[0], std::to_string(m));
    EXPECT_EQ(std::strtod(cells[1].c_str(), nullptr), omega[m / 3]) << m;
    EXPECT_EQ(std::strtod(cells[2].c_str(), nullptr), b[m % 3]) << m;
    EXPECT_EQ(cells[3], "completed");
    EXPECT_EQ(cells[4], "10");
    // The LGVI keeps m·k to round-off (momentum_k_rel_change) and the energy to O(h²) over 10 steps.
    EXPECT_LT(std::strtod(cells[22].c_str(), nullptr), 1e-13) << lines[static_cast<std::size_t>(m) + 1];
    EXPECT_LT(std::strtod(cells[21].c_str(), nullptr), 1e-3) << lines[static_cast<std::size_t>(m) + 1];
  }

  write("log.json", heavy_top_sweep(R"({"grid": {"/problem/b": {"from": 1, "to": 100, "count": 3, "log": true}},
                                          "record": ["status"]})"));
  ASSERT_EQ(sweep("log.json", "log.csv").status, 0);
  const auto log_lines = lines_of(read("log.csv"));
  ASSERT_EQ(log_lines.size(), 4u);
  EXPECT_EQ(log_lines[0], "member,/problem/b,status,steps");
  EXPECT_EQ(log_lines[1].substr(0, 4), "0,1,");
  EXPECT_NEAR(std::strtod(split(log_lines[2], ',')[1].c_str(), nullptr), 10.0, 1e-14);
  EXPECT_EQ(log_lines[3].substr(0, 6), "2,100,");  // the end exactly
}

// splitmix64 and FNV-1a as docs/sweep.md states them, written out here from their published constants.
std::uint64_t mix(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
double documented_uniform(std::uint64_t seed, std::uint64_t member, const std::string& key) {
  std::uint64_t h = 14695981039346656037ULL;
  for (const char c : key) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ULL;
  return static_cast<double>(mix(seed ^ mix(h ^ mix(member))) >> 11) / 9007199254740992.0;
}

// Random members: in [lo, hi], as the documented generator gives them, the same on every run, and a key's
// values unchanged when another key is added to the ranges.
TEST_F(CliSweep, RandomMembersAreReproducibleAndInRange) {
  const std::string ranges = R"("/initial/omega/0": [-1, 1], "/problem/b": [0.5, 2])";
  write("r.json", heavy_top_sweep(R"({"random": {"seed": 42, "count": 40, "ranges": {)" + ranges +
                                  R"(}}, "record": ["status"]})"));
  ASSERT_EQ(sweep("r.json", "a.csv").status, 0);
  ASSERT_EQ(sweep("r.json", "b.csv").status, 0);
  const std::string a = read("a.csv");
  EXPECT_EQ(a, read("b.csv"));
  const auto lines = lines_of(a);
  ASSERT_EQ(lines.size(), 41u);
  EXPECT_EQ(lines[0], "member,/initial/omega/0,/problem/b,status,steps");
  double min0 = 1e300, max0 = -1e300;
  for (std::uint64_t m = 0; m < 40; ++m) {
    const auto cells = split(lines[m + 1], ',');
    const double w = std::strtod(cells[1].c_str(), nullptr), b = std::strtod(cells[2].c_str(), nullptr);
    EXPECT_GE(w, -1.0);
    EXPECT_LE(w, 1.0);
    EXPECT_GE(b, 0.5);
    EXPECT_LE(b, 2.0);
    EXPECT_EQ(w, -1.0 + 2.0 * documented_uniform(42, m, "/initial/omega/0")) << m;
    EXPECT_EQ(b, 0.5 + 1.5 * documented_uniform(42, m, "/problem/b")) << m;
    min0 = std::min(min0, w);
    max0 = std::max(max0, w);
  }
  EXPECT_LT(min0, -0.5);  // 40 draws spread over the range
  EXPECT_GT(max0, 0.5);

  write("r3.json", heavy_top_sweep(R"({"random": {"seed": 42, "count": 40, "ranges": {)" + ranges +
                                   R"(, "/initial/omega/1": [0, 1]}}, "record": ["status"]})"));
  ASSERT_EQ(sweep("r3.json", "c.csv").status, 0);
  const auto lines3 = lines_of(read("c.csv"));
  ASSERT_EQ(lines3.size(), 41u);
  for (std::size_t m = 1; m <= 40; ++m) {
    const auto two = split(lines[m], ','), three = split(lines3[m], ',');
    EXPECT_EQ(three[1], two[1]);  // /initial/omega/0
    EXPECT_EQ(three[3], two[2]);  // /problem/b
  }

  write("r7.json", heavy_top_sweep(R"({"random": {"seed": 7, "count": 40, "ranges": {)" + ranges +
                                   R"(}}, "record": ["status"]})"));
  ASSERT_EQ(sweep("r7.json", "d.csv").status, 0);
  EXPECT_NE(lines_of(read("d.csv"))[1], lines[1]);  // another seed, other values
}

// A member's "final" columns are `lgi run`'s last row for the scene with the member's values, character for
// character: a completed member of the heavy top, and a free body whose RKMK4 steps overflow mid-run (the row
// holds status non_finite and the last good state; the sweep still exits 0).
TEST_F(CliSweep, MemberRowIsTheLastRowOfLgiRun) {
  write("top.json", heavy_top_sweep(R"({"grid": {"/initial/omega/0": [0.1, -0.7], "/integrator/dt": [0.01, 0.025]},
                                          "record": ["final"]})"));
  ASSERT_EQ(sweep("top.json", "top.csv").status, 0);
  const auto top = lines_of(read("top.csv"));
  ASSERT_EQ(top.size(), 5u);
  for (std::size_t m = 1; m <= 4; ++m) {
    const auto cells = split(top[m], ',');
    write("member.json", R"({"problem": {"type": "heavy_top", "inertia": [2.0, 2.0, 1.0], "b": 1.0,
                                         "k": [0.0, 0.6, 0.8], "z0": [0.0, 0.0, 1.0]},
                             "initial": {"omega": [)" + cells[1] + R"(, 0.2, 5.0]},
                             "integrator": {"method": "lgvi", "dt": )" + cells[2] + R"(}, "t_end": 0.1})");
    const CommandResult run = lgi("run " + (dir_ / "member.json").string() + " -q");
    ASSERT_EQ(run.status, 0) << run.err;
    const auto rows = lines_of(run.out);
    const std::string prefix = cells[0] + "," + cells[1] + "," + cells[2] + ",";
    EXPECT_EQ(top[m], prefix + rows.back()) << m;
  }

  const std::string body = R"({"problem": {"type": "free_body", "inertia": [1, 2, 3]}, "initial": {"omega": [1, W, 1]},
                               "integrator": {"method": "rkmk4", "dt": 0.1}, "t_end": 1000)";
  std::string sweep_file = body;
  sweep_file.replace(sweep_file.find('W'), 1, "1");
  write("body.json", sweep_file + R"(, "sweep": {"grid": {"/initial/omega/1": [1, 40]}, "record": ["status", "final"]}})");
  const CommandResult r = sweep("body.json", "body.csv");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("1 completed, 1 step failed, 0 stopped"), std::string::npos) << r.err;
  const auto rows = lines_of(read("body.csv"));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1].rfind("0,1,completed,10000,1000,", 0), 0u) << rows[1];
  const auto failed = split(rows[2], ',');
  EXPECT_EQ(failed[2], "non_finite");
  std::string scene = body;
  scene.replace(scene.find('W'), 1, "40");
  write("blowup.json", scene + "}");
  const CommandResult run = lgi("run " + (dir_ / "blowup.json").string() + " -q");
  ASSERT_EQ(run.status, 2) << run.err;
  const auto run_rows = lines_of(run.out);
  EXPECT_EQ(rows[2], "1,40,non_finite," + failed[3] + "," + run_rows.back());
  // the steps column: the last good state's time over dt
  EXPECT_NEAR(std::strtod(failed[4].c_str(), nullptr), 0.1 * std::strtod(failed[3].c_str(), nullptr), 1e-9);
}

// Every problem type `lgi list` names, through a sweep of its scene in scenes/ over two members (t_end of 20 and 40
// steps) recording status, final state and invariants: the header and every row have the same number of fields,
// and each row's final columns are `lgi run`'s last row for the member's scene, character for character.
TEST_F(CliSweep, EveryProblemTypesRowsHaveTheHeadersFieldsAndLgiRunsLastRow) {
  const CommandResult list = lgi("list");
  ASSERT_EQ(list.status, 0) << list.err;
  std::vector<std::string> problems;
  for (const std::string& line : lines_of(list.out)) {
    if (line.rfind("methods", 0) == 0) break;
    if (line.size() > 2 && line.rfind("  ", 0) == 0 && line[2] != ' ')
      problems.push_back(line.substr(2, line.find(' ', 2) - 2));
  }
  ASSERT_GE(problems.size(), 7u) << list.out;
  std::map<std::string, fs::path> scene_of;  // the first scene of each type, by file name
  std::vector<fs::path> files(fs::directory_iterator(LGI_SCENES_DIR), fs::directory_iterator{});
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files)
    if (f.extension() == ".json") scene_of.emplace(nlohmann::json::parse(slurp(f))["problem"]["type"], f);
  for (const std::string& problem : problems) {
    SCOPED_TRACE(problem);
    ASSERT_TRUE(scene_of.count(problem)) << "no scene in scenes/ has problem type " << problem;
    nlohmann::json scene = nlohmann::json::parse(slurp(scene_of[problem]));
    scene.erase("output");
    const double dt = scene["integrator"]["dt"];
    nlohmann::json sweep_file = scene;
    sweep_file["sweep"] = {{"grid", {{"/t_end", {20 * dt, 40 * dt}}}},
                           {"record", {"status", "final", "invariants"}}};
    write("sweep.json", sweep_file.dump());
    const CommandResult s = sweep("sweep.json", "sweep.csv");
    ASSERT_EQ(s.status, 0) << s.err;
    const auto rows = lines_of(read("sweep.csv"));
    ASSERT_EQ(rows.size(), 3u);
    const std::size_t fields = split(rows[0], ',').size();
    for (std::size_t m = 1; m < rows.size(); ++m) {
      const auto cells = split(rows[m], ',');
      EXPECT_EQ(cells.size(), fields) << "row " << m << " against the header " << rows[0];
      nlohmann::json member = scene;
      member["t_end"] = std::strtod(cells[1].c_str(), nullptr);
      write("member.json", member.dump());
      const CommandResult run = lgi("run " + (dir_ / "member.json").string() + " -q");
      ASSERT_EQ(run.status, 0) << run.err;
      const std::string expected = cells[0] + "," + cells[1] + "," + cells[2] + "," + cells[3] + "," +
                                   lines_of(run.out).back() + ",";
      EXPECT_EQ(rows[m].substr(0, expected.size()), expected) << "header " << rows[0];
    }
  }
}

// In-run records (extrema, a Lyapunov estimate, crossings) do not change a member's trajectory: its status and final
// columns are those of the same sweep without them, byte for byte. The header; the crossings file: one row per
// crossing with the member, its index and the state, each on the section (R11 = 0.99 to rounding), in time order,
// as many as the member's count; the extrema bracket the initial value; the Lyapunov estimate covers the run.
TEST_F(CliSweep, InRunRecordsLeaveTheTrajectoryAlone) {
  const std::string grid = R"({"grid": {"/initial/omega/0": [0.1, -0.7, 2], "/integrator/dt": [0.01, 0.0125]}, )";
  write("plain.json", heavy_top_sweep(grid + R"("record": ["status", "final"]})"));
  write("observed.json", heavy_top_sweep(grid + R"("record": ["status", "final", "extrema", "lyapunov", "crossings"], )" +
                                         observed_records + "}"));
  ASSERT_EQ(sweep("plain.json", "plain.csv").status, 0);
  const CommandResult r = sweep("observed.json", "observed.csv");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto plain = lines_of(read("plain.csv")), observed = lines_of(read("observed.csv"));
  ASSERT_EQ(plain.size(), 7u);
  ASSERT_EQ(observed.size(), 7u);
  EXPECT_EQ(observed[0], plain[0] + ",tilt_min,tilt_max,omega3_min,omega3_max,lyapunov,lyapunov_t,crossings");
  const auto crossings = lines_of(read("observed.crossings.csv"));
  ASSERT_GE(crossings.size(), 1u);
  EXPECT_EQ(crossings[0], "member,crossing,t,R11,R12,R13,R21,R22,R23,R31,R32,R33,omega1,omega2,omega3");
  std::size_t next = 1;
  for (std::size_t m = 1; m < plain.size(); ++m) {
    EXPECT_EQ(observed[m].substr(0, plain[m].size() + 1), plain[m] + ",") << m;
    const auto cells = split(observed[m], ',');
    ASSERT_EQ(cells.size(), split(plain[m], ',').size() + 7);
    const auto at = [&](std::size_t from_end) { return std::strtod(cells[cells.size() - from_end].c_str(), nullptr); };
    // tilt at t = 0: the angle between R z0 = e3 and k = (0, 0.6, 0.8)
    EXPECT_LE(at(7), std::acos(0.8) + 1e-15);
    EXPECT_GE(at(6), std::acos(0.8) - 1e-15);
    EXPECT_LE(at(5), 5.0);  // omega3
    EXPECT_GE(at(4), 5.0);
    EXPECT_NEAR(at(2), 0.1, 1e-12);  // lyapunov_t: the whole run
    EXPECT_TRUE(std::isfinite(at(3)));
    const long count = std::strtol(cells.back().c_str(), nullptr, 10);
    EXPECT_EQ(count, 1) << observed[m];  // R11 ≈ cos(5t) passes 0.99 once in 0.1 s
    double t_last = 0;
    for (long k = 0; k < count; ++k, ++next) {
      ASSERT_LT(next, crossings.size());
      const auto c = split(crossings[next], ',');
      ASSERT_EQ(c.size(), 15u) << crossings[next];
      EXPECT_EQ(c[0], std::to_string(m - 1));
      EXPECT_EQ(c[1], std::to_string(k));
      const double t = std::strtod(c[2].c_str(), nullptr);
      EXPECT_GT(t, t_last);
      EXPECT_LE(t, 0.1);
      t_last = t;
      EXPECT_NEAR(std::strtod(c[3].c_str(), nullptr), 0.99, 1e-15) << crossings[next];
    }
  }
  EXPECT_EQ(next, crossings.size());  // no rows beyond the members' counts

  // The same for an adaptive run (extrema at the accepted steps) and the seed paper's Euler-angle top (its own
  // runner path), with the scene's own output times, which a sweep ignores.
  const std::vector<std::pair<std::string, std::string>> others = {
      {R"({"problem": {"type": "heavy_top", "inertia": [0.6, 0.8, 1.0], "b": 1}, "initial": {"omega": [1, 0.5, 2]},
           "integrator": {"method": "rkmk_dp5", "dt": 0.1, "rtol": 1e-9, "atol": 1e-9}, "t_end": 3,
           "output": {"times": [0.5, 1.25]},)",
       R"({"grid": {"/initial/omega/1": [0.5, -1]}, "extrema": ["omega1", "tilt"]})"},
      {R"({"problem": {"type": "lagrange_top_euler_angles", "I2": 2, "I3": 1, "b": 1, "k2": 0.6, "k3": 0.8},
           "initial": {"euler_angles": [0.1, 0.5, 0.2], "euler_rates": [0.3, 0.1, 4]},
           "integrator": {"method": "rkmk4", "dt": 0.01}, "t_end": 2.005, "output": {"every": 7},)",
       R"({"grid": {"/initial/euler_rates/2": [4, 6]}, "extrema": ["tilt", "gamma2"]})"},
  };
  for (const auto& [scene, sweep_section] : others) {
    SCOPED_TRACE(scene);
    std::string plain_sweep = sweep_section;
    plain_sweep.replace(plain_sweep.find(", \"extrema\""), std::string::npos, ", \"record\": [\"status\", \"final\"]}");
    std::string observed_sweep = sweep_section;
    observed_sweep.insert(observed_sweep.size() - 1, R"(, "record": ["status", "final", "extrema"])");
    write("plain.json", scene + R"( "sweep": )" + plain_sweep + "}");
    write("observed.json", scene + R"( "sweep": )" + observed_sweep + "}");
    ASSERT_EQ(sweep("plain.json", "plain.csv").status, 0);
    const CommandResult o = sweep("observed.json", "observed.csv");
    ASSERT_EQ(o.status, 0) << o.err;
    const auto p = lines_of(read("plain.csv")), q = lines_of(read("observed.csv"));
    ASSERT_EQ(p.size(), 3u);
    ASSERT_EQ(q.size(), 3u);
    for (std::size_t m = 1; m < 3; ++m) {
      EXPECT_EQ(q[m].substr(0, p[m].size() + 1), p[m] + ",") << m;
      const auto cells = split(q[m], ',');
      const auto lo = std::strtod(cells[cells.size() - 4].c_str(), nullptr), hi = std::strtod(cells[cells.size() - 3].c_str(), nullptr);
      EXPECT_LT(lo, hi);  // the first function moved during the run
    }
  }
}

// On a terminal (script(1)) a sweep that takes seconds shows the members done, their rate and the time left; the
// line is cleared before the message.
TEST_F(CliSweep, ProgressOnATerminal) {
  write("slow.json", R"({"problem": {"type": "heavy_top", "inertia": [2.0, 2.0, 1.0], "b": 1.0},
                         "initial": {"omega": [0.1, 0.2, 5.0]}, "integrator": {"method": "rkmk4", "dt": 1e-5},
                         "t_end": 10, "sweep": {"grid": {"/problem/b": {"from": 0.5, "to": 1.5, "count": 40}}}})");
  EXPECT_EQ(lgi::test::lgi_on_a_terminal("sweep " + (dir_ / "slow.json").string() + " -o " + (dir_ / "slow.csv").string(),
                                         dir_ / "screen.txt", 2),
            128 + SIGINT);
  const std::string shown = slurp(dir_ / "screen.txt");
  EXPECT_NE(shown.find(" of 40 members ("), std::string::npos) << shown;
  EXPECT_NE(shown.find(" members/s, "), std::string::npos) << shown;
  EXPECT_NE(shown.find(" s elapsed, about "), std::string::npos) << shown;
  EXPECT_NE(shown.find("lgi: error: sweep interrupted by SIGINT after "), std::string::npos) << shown;
  EXPECT_FALSE(fs::exists(dir_ / "slow.csv"));
  // Not a terminal, with --progress: lines (12 members, ≈ 1.6 s).
  std::string twelve = slurp(dir_ / "slow.json");
  twelve.replace(twelve.find("\"count\": 40"), std::string("\"count\": 40").size(), "\"count\": 12");
  write("twelve.json", twelve);
  const CommandResult r = sweep("twelve.json", "twelve.csv", "--progress");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err.rfind("lgi: progress: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(" of 12 members ("), std::string::npos) << r.err;
}

// The same bytes whatever the number of threads (members of different cost: dt varies 5-fold).
TEST_F(CliSweep, ThreadCountDoesNotChangeTheBytes) {
  write("grid.json", heavy_top_sweep(R"({"grid": {"/integrator/dt": {"from": 0.002, "to": 0.01, "count": 5},
                                                  "/initial/omega/1": [-0.3, 0, 0.3], "/problem/b": [0.5, 1]}})"));
  ASSERT_EQ(sweep("grid.json", "t1.csv", "--threads 1").status, 0);
  const std::string serial = read("t1.csv");
  EXPECT_EQ(lines_of(serial).size(), 31u);
  for (const std::string t : {"2", "3", "0"}) {
    const CommandResult r = sweep("grid.json", "t" + t + ".csv", "--threads " + t);
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_EQ(read("t" + t + ".csv"), serial) << "--threads " << t;
  }
  // The same with in-run records: the rows and the crossings file.
  write("observed.json", heavy_top_sweep(std::string(R"({"grid": {"/integrator/dt": {"from": 0.002, "to": 0.01, "count": 5},
                                                  "/initial/omega/1": [-0.3, 0, 0.3], "/problem/b": [0.5, 1]}, )") +
                                         observed_records + "}"));
  ASSERT_EQ(sweep("observed.json", "o1.csv", "--threads 1").status, 0);
  const std::string rows = read("o1.csv"), crossings = read("o1.crossings.csv");
  EXPECT_EQ(lines_of(crossings).size(), 31u);  // the header and one crossing per member
  for (const std::string t : {"2", "3"}) {
    ASSERT_EQ(sweep("observed.json", "o" + t + ".csv", "--threads " + t).status, 0);
    EXPECT_EQ(read("o" + t + ".csv"), rows) << "--threads " << t;
    EXPECT_EQ(read("o" + t + ".crossings.csv"), crossings) << "--threads " << t;
  }
}

// SIGTERM during a sweep, the signal after 1 s: exit 128 + 15, one line on stderr, and nothing written — no output,
// no temporary file. Member by member (40 members of 1e7 LGVI steps, over a second each: 1e7 > 2^20 steps keeps
// them off the batched path) and batched (400 members of 1e6 steps in blocks of 4, ~0.1 s a block; ~90 s in all).
TEST_F(CliSweep, InterruptedSweepWritesNothing) {
  const std::string scene = R"({"problem": {"type": "heavy_top", "inertia": [2.0, 2.0, 1.0], "b": 1.0},
                               "initial": {"omega": [0.1, 0.2, 5.0]}, "integrator": {"method": "lgvi", "dt": 0.001},)";
  write("long.json", scene + R"("t_end": 10000.0, "sweep": {"grid": {"/problem/b": {"from": 0.5, "to": 1.5, "count": 40}}}})");
  write("batched.json", scene + R"("t_end": 1000.0, "sweep": {"grid": {"/problem/b": {"from": 0.5, "to": 1.5, "count": 400}}}})");
  for (const std::string file : {"long.json", "batched.json"}) {
    SCOPED_TRACE(file);
    const fs::path err = fs::temp_directory_path() / ("lgi_sweep_interrupted_" + std::to_string(::getpid()) + ".txt");
    const std::string cmd = std::string(LGI_EXE) + " sweep " + (dir_ / file).string() + " -o " +
                            (dir_ / "out.csv").string() + " --threads 2 2> " + err.string() +
                            " & pid=$!; sleep 1; kill -TERM $pid; wait $pid";
    const int raw = std::system(cmd.c_str());
    const std::string message = slurp(err);
    fs::remove(err);
    ASSERT_TRUE(WIFEXITED(raw));
    EXPECT_EQ(WEXITSTATUS(raw), 128 + 15) << message;
    EXPECT_NE(message.find("interrupted by SIGTERM"), std::string::npos) << message;
    EXPECT_NE(message.find("nothing written"), std::string::npos) << message;
    EXPECT_EQ(std::count(message.begin(), message.end(), '\n'), 1) << message;
    // stopped where it was: "after K of N members" with K < N (ignoring the signal until the end would give N of N)
    const auto after = message.find(" after ");
    ASSERT_NE(after, std::string::npos) << message;
    long done = -1, total = -1;
    ASSERT_EQ(std::sscanf(message.c_str() + after, " after %ld of %ld members", &done, &total), 2) << message;
    EXPECT_LT(done, total) << message;
    expect_only({"long.json", "batched.json"});
  }
}

// --shard i/3 parts merged (in any order) are the serial run's file byte for byte; so are 7 shards of 30
// members (uneven) with 2 threads each; a part carries the shard line.
TEST_F(CliSweep, ShardsMergeToTheSerialBytes) {
  write("grid.json", heavy_top_sweep(R"({"grid": {"/initial/omega/0": {"from": -1, "to": 1, "count": 10},
                                                  "/problem/b": [0.5, 1, 2]}})"));
  ASSERT_EQ(sweep("grid.json", "serial.csv").status, 0);
  const std::string serial = read("serial.csv");
  for (int i = 0; i < 3; ++i) {
    const std::string part = "p" + std::to_string(i) + ".csv";
    ASSERT_EQ(sweep("grid.json", part, "--shard " + std::to_string(i) + "/3").status, 0);
    const auto lines = lines_of(read(part));
    ASSERT_EQ(lines.size(), 13u);  // the shard line, the header, 10 rows, the check line
    EXPECT_EQ(lines[12].rfind("# lgi sweep part end: fnv1a64 ", 0), 0u) << lines[12];
    EXPECT_EQ(lines[0].rfind("# lgi sweep shard " + std::to_string(i) + "/3: 30 members, sweep ", 0), 0u) << lines[0];
  }
  const CommandResult m = lgi("merge " + (dir_ / "p2.csv").string() + " " + (dir_ / "p0.csv").string() + " " +
                              (dir_ / "p1.csv").string() + " -o " + (dir_ / "merged.csv").string());
  ASSERT_EQ(m.status, 0) << m.err;
  EXPECT_EQ(read("merged.csv"), serial);

  std::string parts;
  for (int i = 0; i < 7; ++i) {
    const std::string part = "q" + std::to_string(i) + ".csv";
    ASSERT_EQ(sweep("grid.json", part, "--threads 2 --shard " + std::to_string(i) + "/7").status, 0);
    parts += (dir_ / part).string() + " ";
  }
  ASSERT_EQ(lgi("merge " + parts + "-o " + (dir_ / "merged7.csv").string()).status, 0);
  EXPECT_EQ(read("merged7.csv"), serial);

  // In-run records: each part has its crossings part beside it; merged, both files are the serial run's.
  write("observed.json", heavy_top_sweep(std::string(R"({"grid": {"/initial/omega/0": {"from": -1, "to": 1, "count": 10},
                                                  "/problem/b": [0.5, 1, 2]}, )") + observed_records + "}"));
  ASSERT_EQ(sweep("observed.json", "oserial.csv").status, 0);
  ASSERT_EQ(lines_of(read("oserial.crossings.csv")).size(), 31u);  // the header and one crossing per member
  parts.clear();
  for (int i = 0; i < 4; ++i) {
    const std::string part = "o" + std::to_string(i) + ".csv";
    ASSERT_EQ(sweep("observed.json", part, "--threads 2 --shard " + std::to_string(i) + "/4").status, 0);
    EXPECT_EQ(lines_of(read("o" + std::to_string(i) + ".crossings.csv"))[0].rfind("# lgi sweep crossings shard " +
                                                                                  std::to_string(i) + "/4: 30 members", 0),
              0u);
    parts += (dir_ / part).string() + " ";
  }
  const CommandResult mo = lgi("merge " + parts + "-o " + (dir_ / "omerged.csv").string());
  ASSERT_EQ(mo.status, 0) << mo.err;
  EXPECT_EQ(read("omerged.csv"), read("oserial.csv"));
  EXPECT_EQ(read("omerged.crossings.csv"), read("oserial.crossings.csv"));
}

// One bad thing at a time: exit 1, one line on stderr naming it, no output file.
TEST_F(CliSweep, BadSweepFilesAreRefusedWithoutOutput) {
  struct Case {
    std::string sweep, args, message;
  };
  const std::vector<Case> cases = {
      {R"({"grid": {"/initial/omegaa/2": [1, 2]}})", "", "\"/initial/omegaa/2\" is not in the scene"},
      {R"({"grid": {"/initial/omega/3": [1, 2]}})", "", "\"/initial/omega/3\" is not in the scene"},
      {R"({"grid": {"/integrator/method": [1, 2]}})", "",
       "/sweep/grid/~1integrator~1method: \"/integrator/method\" points at a string (\"lgvi\") in the scene, not at a number"},
      {R"({"grid": {"/initial/omega": [1, 2]}})", "", "points at an array of 3 in the scene, not at a number"},
      {R"({"grid": {"initial/omega/0": [1, 2]}})", "", "is not a JSON pointer into the scene"},
      {R"({"grid": {"/problem/b": {"from": 1, "to": 2, "count": 0}}})", "",
       "/sweep/grid/~1problem~1b/count: expected an integer from 1 to 10000000, got 0"},
      {R"({"grid": {"/problem/b": []}})", "", "/sweep/grid/~1problem~1b: expected a non-empty array of numbers"},
      {R"({"grid": {"/problem/b": [1, "2"]}})", "", "/sweep/grid/~1problem~1b/1: expected a number"},
      {R"({"grid": {"/problem/b": {"from": 1, "to": 2, "count": 5000}, "/initial/omega/0": {"from": 1, "to": 2, "count": 5000}}})",
       "", "/sweep/grid: the grid has more than 10000000 members"},
      {R"({"random": {"seed": 1, "count": 0, "ranges": {"/problem/b": [1, 2]}}})", "",
       "/sweep/random/count: expected an integer from 1 to 10000000, got 0"},
      {R"({"random": {"seed": 1, "count": 5, "ranges": {"/problem/b": [2, 1]}}})", "", "expected lo <= hi"},
      {R"({"grid": {"/problem/b": [1]}, "random": {"seed": 1, "count": 5, "ranges": {}}})", "", "not both"},
      {R"({"grid": {"/problem/b": [1]}, "record": ["final", "lyapunovv"]})", "", "/sweep/record/1: unknown column group \"lyapunovv\"; did you mean \"lyapunov\"?"},
      // in-run records
      {R"({"grid": {"/problem/b": [1]}, "extrema": ["spin"]})", "", "/sweep/extrema/0: unknown state function \"spin\" ("},
      {R"({"grid": {"/problem/b": [1]}, "extrema": ["Omega3"]})", "",
       "/sweep/extrema/0: unknown state function \"Omega3\"; did you mean \"omega3\"?"},
      {R"({"grid": {"/problem/b": [1]}, "extrema": ["tilt", "tilt"]})", "", "/sweep/extrema/1: \"tilt\" twice"},
      {R"({"grid": {"/problem/b": [1]}, "extrema": []})", "", "/sweep/extrema: expected a non-empty array"},
      {R"({"grid": {"/problem/b": [1]}, "record": ["status", "extrema"]})", "",
       "/sweep/record/1: \"extrema\" needs /sweep/extrema"},
      {R"({"grid": {"/problem/b": [1]}, "record": ["crossings"]})", "", "/sweep/record/0: \"crossings\" needs /sweep/section"},
      {R"({"grid": {"/problem/b": [1]}, "record": ["status"], "extrema": ["tilt"]})", "",
       "/sweep/extrema: given but not recorded: add \"extrema\" to /sweep/record"},
      {R"({"grid": {"/problem/b": [1]}, "record": ["status"], "lyapunov": {}})", "",
       "/sweep/lyapunov: given but not recorded"},
      {R"({"grid": {"/problem/b": [1]}, "section": {"function": "gamma1", "value": 0, "direction": "up"}})", "",
       "/sweep/section/direction: expected \"increasing\", \"decreasing\" or \"both\", got \"up\""},
      {R"({"grid": {"/problem/b": [1]}, "section": {"function": "gamma1"}})", "", "/sweep/section: missing key \"value\""},
      {R"({"grid": {"/problem/b": [1]}, "section": {"function": "gamma1", "value": 0, "every": 2}})", "",
       "/sweep/section/every: unknown key (allowed: function, value, direction, max_crossings)"},
      {R"({"grid": {"/problem/b": [1]}, "lyapunov": {"d0": 0.1}})", "", "/sweep/lyapunov/d0: must be <= 1e-3"},
      {R"({"grid": {"/problem/b": [1]}, "lyapunov": {"interval": 0}})", "", "/sweep/lyapunov/interval: "},
      // a member the loader refuses: named with its values and the scene's pointer
      {R"({"grid": {"/problem/b": [1, -1], "/initial/omega/0": [0, 1]}})", "",
       "(member 1: /initial/omega/0 = 0, /problem/b = -1): /problem/b: must be >= 0, got -1"},
      {R"({"grid": {"/problem/b": [1]}})", "--shard 3/3", "--shard: expected i/N with 0 <= i < N"},
      {R"({"grid": {"/problem/b": [1]}})", "--shard 1", "--shard: expected i/N"},
      {R"({"grid": {"/problem/b": [1]}})", "--shard a/b", "--shard: expected i/N"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.sweep + " " + c.args);
    write("bad.json", heavy_top_sweep(c.sweep));
    const CommandResult r = sweep("bad.json", "out.csv", c.args);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
    EXPECT_EQ(r.err.rfind("lgi: error: ", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    expect_only({"bad.json"});
  }
  write("wall.json", R"({"problem": {"type": "free_body", "inertia": [1, 2, 3]}, "initial": {"omega": [1, 1, 1]},
                         "integrator": {"method": "lgvi", "dt": 0.1}, "t_end": 1, "limits": {"max_wall_seconds": 10},
                         "sweep": {"grid": {"/t_end": [1, 2]}}})");
  const CommandResult r = sweep("wall.json", "out.csv");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("/limits/max_wall_seconds: a sweep's rows may not depend on the machine's speed"),
            std::string::npos)
      << r.err;
  // gravity's functions on a free body; crossings and Lyapunov estimates on an adaptive run
  const std::string body = R"({"problem": {"type": "free_body", "inertia": [1, 2, 3]}, "initial": {"omega": [1, 1, 1]},
                               "integrator": {"method": "rkmk_dp5", "dt": 0.1, "rtol": 1e-8, "atol": 1e-8}, "t_end": 1,)";
  const std::vector<Case> body_cases = {
      {R"({"grid": {"/t_end": [1]}, "extrema": ["omega1", "gamma3"]})", "",
       "/sweep/extrema/1: gamma3 needs a top (a problem with gravity k and centre of mass z0"},
      {R"({"grid": {"/t_end": [1]}, "section": {"function": "omega1", "value": 0}})", "",
       "/sweep/section: crossings are located by side-steps of a fixed-step run"},
      {R"({"grid": {"/t_end": [1]}, "record": ["lyapunov"]})", "",
       "/sweep/record/0: the Lyapunov estimate steps a shadow trajectory with the run's fixed steps"},
  };
  for (const Case& c : body_cases) {
    SCOPED_TRACE(c.sweep);
    write("bad.json", body + R"( "sweep": )" + c.sweep + "}");
    const CommandResult refused = sweep("bad.json", "out.csv", c.args);
    EXPECT_EQ(refused.status, 1);
    EXPECT_NE(refused.err.find(c.message), std::string::npos) << refused.err;
    EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << refused.err;
    expect_only({"bad.json", "wall.json"});
  }
  write("nosweep.json", heavy_top_sweep(""));
  EXPECT_EQ(sweep("nosweep.json", "out.csv").status, 1);
  EXPECT_FALSE(fs::exists(dir_ / "out.csv"));
}

// Merge refuses a missing shard, a shard twice, shards of two sweeps, a cut part and a file that is no part.
// A part's text without its last n lines.
std::string without_last_lines(std::string text, int n) {
  for (int i = 0; i < n; ++i) text.resize(text.rfind('\n', text.size() - 2) + 1);
  return text;
}
// The part's check line (apps/sweep_part.hpp) for `body`, appended: a part edited on purpose, to reach the checks
// behind the hash.
std::string resign(const std::string& body) {
  return body + "# lgi sweep part end: fnv1a64 " + lgi::app::hex64(lgi::app::fnv1a(body)) + "\n";
}

// A sweep of a body under a replayed torque table: the table's path is the sweep file's (not the member's label), and
// the table's bytes are part of the sweep — shards run with different tables do not merge (one line, exit 1); the
// same table's shards merge to the serial run's bytes.
TEST_F(CliSweep, TorqueTablesBelongToTheSweep) {
  const std::string table = "t,M1,M2,M3\n0,0.1,0,0\n0.05,0.2,0.1,0\n0.1,0.1,0,0.3\n";
  write("torque.csv", table);
  write("table.json", R"({"problem": {"type": "rigid_body", "inertia": [1, 2, 3],
      "torques": [{"type": "table", "file": "torque.csv", "frame": "body", "interpolation": "cubic"}]},
    "initial": {"omega": [0.1, 0.2, 1]}, "integrator": {"method": "rkmk4", "dt": 0.01}, "t_end": 0.1,
    "sweep": {"grid": {"/initial/omega/2": [1, 2, 3, 4]}, "record": ["status", "final"]}})");
  const CommandResult serial = sweep("table.json", "serial.csv");
  ASSERT_EQ(serial.status, 0) << serial.err;
  ASSERT_EQ(sweep("table.json", "p0.csv", "--shard 0/2").status, 0);
  write("torque.csv", "t,M1,M2,M3\n0,0.1,0,0\n0.05,0.25,0.1,0\n0.1,0.1,0,0.3\n");
  ASSERT_EQ(sweep("table.json", "q1.csv", "--shard 1/2").status, 0);
  const auto p = [&](const std::string& name) { return (dir_ / name).string() + " "; };
  CommandResult r = lgi("merge " + p("p0.csv") + p("q1.csv") + "-o " + (dir_ / "merged.csv").string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("q1.csv:1: a shard of another sweep"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "merged.csv"));
  write("torque.csv", table);
  ASSERT_EQ(sweep("table.json", "p1.csv", "--shard 1/2").status, 0);
  r = lgi("merge " + p("p0.csv") + p("p1.csv") + "-o " + (dir_ / "merged.csv").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(read("merged.csv"), read("serial.csv"));
  // -o naming the table: refused, the table untouched.
  r = sweep("table.json", "torque.csv");
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("is the scene's torque table"), std::string::npos) << r.err;
  EXPECT_EQ(read("torque.csv"), table);
}

TEST_F(CliSweep, MergeRefusesIncompleteOrMixedParts) {
  write("a.json", heavy_top_sweep(R"({"grid": {"/problem/b": [0.5, 1, 1.5, 2, 2.5]}, "record": ["status"]})"));
  write("b.json", heavy_top_sweep(R"({"grid": {"/problem/b": [0.5, 1, 1.5, 2, 3]}, "record": ["status"]})"));
  for (const std::string s : {"a", "b"})
    for (int i = 0; i < 3; ++i)
      ASSERT_EQ(sweep(s + ".json", s + std::to_string(i) + ".csv", "--shard " + std::to_string(i) + "/3").status, 0);
  ASSERT_EQ(sweep("a.json", "serial.csv").status, 0);
  const std::string cut = read("a1.csv");
  write("cut1.csv", cut.substr(0, cut.rfind('\n', cut.size() - 2) + 1));  // its check line gone: unfinished
  write("short1.csv", resign(without_last_lines(cut, 2)));                  // its last row gone, check line redone
  const auto p = [&](const std::string& name) { return (dir_ / name).string() + " "; };
  struct Case {
    std::string parts, message;
  };
  std::vector<Case> cases = {
      {p("a0.csv") + p("a2.csv"), "merge: shard 1/3 of the sweep in " + p("a0.csv").substr(0, p("a0.csv").size() - 1) +
                                      " is missing"},
      {p("a0.csv") + p("a1.csv") + p("a1.csv"), p("a1.csv").substr(0, p("a1.csv").size() - 1) + ": shard 1/3 again"},
      {p("a0.csv") + p("b1.csv") + p("a2.csv"), "b1.csv:1: a shard of another sweep"},
      {p("a0.csv") + p("cut1.csv") + p("a2.csv"), "cut1.csv: the part does not end with its check line"},
      {p("a0.csv") + p("short1.csv") + p("a2.csv"), "short1.csv:4: expected the row of member 4"},
      {p("serial.csv"), "serial.csv:1: not a part file of lgi sweep --shard"},
      {p("a0.csv") + p("nothere.csv"), "nothere.csv: cannot read the part file"},
  };
  // A shard count beyond what --shard writes (found by the part fuzzer: the list of missing shards never ended), and
  // the largest it writes, with one part of a billion: refused at once, the missing ones listed up to ten.
  {
    std::string huge = read("a0.csv");
    huge.replace(huge.find("0/3:"), 4, "0/3333333333333333331:");
    write("huge.csv", resign(without_last_lines(huge, 1)));
    std::string many = read("a0.csv");
    many.replace(many.find("0/3:"), 4, "0/999999999:");
    write("many.csv", resign(without_last_lines(many, 1)));
  }
  cases.push_back({p("huge.csv"), "huge.csv:1: not a part file of lgi sweep --shard"});
  cases.push_back({p("many.csv"), "merge: shard 1/999999999, 2/999999999, 3/999999999, 4/999999999, 5/999999999, "
                                  "6/999999999, 7/999999999, 8/999999999, 9/999999999, 10/999999999, ... of the sweep in"});
  for (const Case& c : cases) {
    SCOPED_TRACE(c.parts);
    const CommandResult r = lgi("merge " + c.parts + "-o " + (dir_ / "merged.csv").string());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "merged.csv"));
  }
  ASSERT_EQ(lgi("merge " + p("a1.csv") + p("a0.csv") + p("a2.csv") + "-o " + (dir_ / "merged.csv").string()).status, 0);
  EXPECT_EQ(read("merged.csv"), read("serial.csv"));

  // With crossings: a part without its crossings part, or with one cut short or of another shard.
  write("c.json", heavy_top_sweep(std::string(R"({"grid": {"/problem/b": [0.5, 1, 1.5, 2, 2.5]}, )") + observed_records + "}"));
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(sweep("c.json", "c" + std::to_string(i) + ".csv", "--shard " + std::to_string(i) + "/2").status, 0);
  const std::string c1 = read("c1.crossings.csv");
  fs::remove(dir_ / "c1.crossings.csv");
  const auto refused = [&](const std::string& parts, const std::string& message) {
    SCOPED_TRACE(parts);
    const CommandResult r = lgi("merge " + parts + "-o " + (dir_ / "cmerged.csv").string());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir_ / "cmerged.csv"));
    EXPECT_FALSE(fs::exists(dir_ / "cmerged.crossings.csv"));
  };
  refused(p("c0.csv") + p("c1.csv"), "c1.crossings.csv: cannot read the crossings part of");
  write("c1.crossings.csv", without_last_lines(c1, 1));  // its check line gone: unfinished
  refused(p("c0.csv") + p("c1.csv"), "c1.crossings.csv: the part does not end with its check line");
  write("c1.crossings.csv", resign(without_last_lines(c1, 2)));  // its last crossing gone, the check line redone
  refused(p("c0.csv") + p("c1.csv"), "c1.crossings.csv:4: expected crossing 0 of member 3 (1 in ");
  const std::string body = without_last_lines(c1, 1);
  write("c1.crossings.csv", resign(body + body.substr(body.rfind('\n', body.size() - 2) + 1)));  // one too many
  refused(p("c0.csv") + p("c1.csv"), "c1.crossings.csv:5: a crossing beyond those the part's rows count");
  write("c1.crossings.csv", c1 + "x");  // changed after its check line
  refused(p("c0.csv") + p("c1.csv"), "c1.crossings.csv: the part does not end with its check line");
  write("c1.crossings.csv", read("c0.crossings.csv"));  // shard 0's
  refused(p("c0.csv") + p("c1.csv"), "c1.crossings.csv:1: not the crossings part of");
  write("c1.crossings.csv", c1);
  const CommandResult ok = lgi("merge " + p("c0.csv") + p("c1.csv") + "-o " + (dir_ / "cmerged.csv").string());
  ASSERT_EQ(ok.status, 0) << ok.err;
  ASSERT_EQ(sweep("c.json", "cserial.csv").status, 0);
  EXPECT_EQ(read("cmerged.csv"), read("cserial.csv"));
  EXPECT_EQ(read("cmerged.crossings.csv"), read("cserial.crossings.csv"));
}

// A sweep that qualifies for the batched LGVI kernel — a heavy top with diagonal J, members differing in Ω0 and b,
// t_end a whole number of steps — writes the bytes of the member-by-member run (--no-batch): members that complete,
// that fail at their first step (the row holds the initial state) and that fail mid-run (steps 1 … 4 of 50); with
// 1 and 3 threads and in 3 shards merged; the summary says which path ran. Sweeps that do not qualify say why.
TEST_F(CliSweep, BatchedKernelWritesTheMemberByMemberBytes) {
  const std::string top = R"({"problem": {"type": "heavy_top", "inertia": [2.0, 2.0, 1.0], "b": 1.0, "k": [0.0, 0.6, 0.8],
                                          "z0": [0.0, 0.0, 1.0]},
                              "initial": {"omega": [0.1, 0.2, 5.0]}, "integrator": {"method": "lgvi", "dt": DT},
                              "t_end": 5, "sweep": )";
  const auto with_dt = [&](const std::string& dt, const std::string& sweep_section) {
    std::string doc = top + sweep_section + "}";
    doc.replace(doc.find("DT"), 2, dt);
    return doc;
  };
  write("grid.json", with_dt("0.1", R"({"grid": {"/problem/b": [0.5, 30, 65, 120], "/initial/omega/2": [3, 8, 12],
                                                  "/initial/omega/0": {"from": -1, "to": 1, "count": 7}}})"));
  const CommandResult batched = sweep("grid.json", "batched.csv");
  ASSERT_EQ(batched.status, 0) << batched.err;
  EXPECT_NE(batched.err.find("batched LGVI ("), std::string::npos) << batched.err;
  const CommandResult single = sweep("grid.json", "single.csv", "--no-batch");
  ASSERT_EQ(single.status, 0) << single.err;
  EXPECT_NE(single.err.find("member by member (not batched: --no-batch)"), std::string::npos) << single.err;
  const std::string bytes = read("single.csv");
  EXPECT_EQ(read("batched.csv"), bytes);
  int completed = 0, at_once = 0, mid_run = 0;
  for (const auto& line : lines_of(bytes)) {
    const auto cells = split(line, ',');
    if (cells[4] == "completed") ++completed;
    else if (cells[4] == "not_converged" && cells[5] == "0") ++at_once;
    else if (cells[4] == "not_converged") ++mid_run;
  }
  EXPECT_GT(completed, 0);
  EXPECT_GT(at_once, 0);
  EXPECT_GT(mid_run, 0);
  ASSERT_EQ(sweep("grid.json", "t3.csv", "--threads 3").status, 0);
  EXPECT_EQ(read("t3.csv"), bytes);
  std::string parts;
  for (int i = 0; i < 3; ++i) {
    const std::string part = "p" + std::to_string(i) + ".csv";
    ASSERT_EQ(sweep("grid.json", part, "--threads 2 --shard " + std::to_string(i) + "/3").status, 0);
    parts += (dir_ / part).string() + " ";
  }
  ASSERT_EQ(lgi("merge " + parts + "-o " + (dir_ / "merged.csv").string()).status, 0);
  EXPECT_EQ(read("merged.csv"), bytes);

  struct Case {
    std::string file, message;
  };
  const std::vector<Case> not_batched = {
      {with_dt("0.3", R"({"grid": {"/problem/b": [1, 2]}})"), "t_end is not a whole number of steps"},
      {with_dt("0.1", R"({"grid": {"/integrator/dt": [0.1, 0.05]}})"), "the members differ in /integrator/dt"},
      {with_dt("0.1", R"({"grid": {"/problem/b": [1, 2]}, "extrema": ["tilt"]})"), "the sweep records extrema, crossings or Lyapunov"},
  };
  for (const Case& c : not_batched) {
    write("nb.json", c.file);
    const CommandResult r = sweep("nb.json", "nb.csv");
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.err.find("member by member (not batched: " + c.message), std::string::npos) << r.err;
  }
}

// Every example sweep (examples/sweep/*.json) loads, passes the checks before the run, and runs its member 0
// (--shard 0/N with N beyond its member count): the examples cannot rot unnoticed.
TEST_F(CliSweep, ExampleSweepsLoadAndRun) {
  int examples = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(LGI_EXAMPLES_DIR) / "sweep")) {
    if (entry.path().extension() != ".json") continue;
    ++examples;
    SCOPED_TRACE(entry.path().string());
    const CommandResult r = lgi("sweep " + entry.path().string() + " --shard 0/10000000 -q -o " + (dir_ / "part.csv").string());
    ASSERT_EQ(r.status, 0) << r.err;
    const auto lines = lines_of(read("part.csv"));
    ASSERT_EQ(lines.size(), 4u);  // the shard line, the header, member 0, the check line
    EXPECT_EQ(lines[2].rfind("0,", 0), 0u);
    if (lines[1].find(",status,") != std::string::npos) {
      EXPECT_NE(lines[2].find(",completed,"), std::string::npos) << lines[2];
    }
  }
  EXPECT_GE(examples, 4);
}

#ifdef LGI_SWEEP_MPI_EXE
// lgi_sweep_mpi under mpirun with 1, 2 and 3 ranks on this machine (--oversubscribe: more ranks than cores):
// the serial run's bytes; a bad sweep file: exit 1, one message, no output file.
TEST_F(CliSweep, MpiRanksWriteTheSerialBytes) {
  write("grid.json", heavy_top_sweep(R"({"grid": {"/initial/omega/0": {"from": -1, "to": 1, "count": 10},
                                                  "/problem/b": [0.5, 1, 2]}})"));
  ASSERT_EQ(sweep("grid.json", "serial.csv").status, 0);
  // Open MPI refuses to run as root without these (CI containers run as root).
  const std::string mpirun = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun --oversubscribe -np ";
  for (const std::string np : {"1", "2", "3"}) {
    const std::string out = (dir_ / ("mpi" + np + ".csv")).string();
    const std::string cmd = mpirun + np + " " + LGI_SWEEP_MPI_EXE + " " + (dir_ / "grid.json").string() + " -o " + out +
                            " -q > " + (dir_ / "mpi.out").string() + " 2>&1";
    const int raw = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) == 0) << np << " ranks: " << slurp(dir_ / "mpi.out");
    EXPECT_EQ(read("mpi" + np + ".csv"), read("serial.csv")) << np << " ranks";
  }
  // In-run records: the crossings file too.
  write("observed.json", heavy_top_sweep(std::string(R"({"grid": {"/initial/omega/0": {"from": -1, "to": 1, "count": 10},
                                                  "/problem/b": [0.5, 1, 2]}, )") + observed_records + "}"));
  ASSERT_EQ(sweep("observed.json", "oserial.csv").status, 0);
  ASSERT_EQ(lines_of(read("oserial.crossings.csv")).size(), 31u);  // the header and one crossing per member
  for (const std::string np : {"1", "3"}) {
    const std::string out = (dir_ / ("ompi" + np + ".csv")).string();
    const std::string cmd = mpirun + np + " " + LGI_SWEEP_MPI_EXE + " " + (dir_ / "observed.json").string() + " -o " +
                            out + " -q > " + (dir_ / "mpi.out").string() + " 2>&1";
    const int raw = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) == 0) << np << " ranks: " << slurp(dir_ / "mpi.out");
    EXPECT_EQ(read("ompi" + np + ".csv"), read("oserial.csv")) << np << " ranks";
    EXPECT_EQ(read("ompi" + np + ".crossings.csv"), read("oserial.crossings.csv")) << np << " ranks";
  }
  write("bad.json", heavy_top_sweep(R"({"grid": {"/initial/omegaa/0": [1, 2]}})"));
  const std::string cmd = mpirun + "2 " + LGI_SWEEP_MPI_EXE + " " + (dir_ / "bad.json").string() + " -o " +
                          (dir_ / "bad.csv").string() + " > " + (dir_ / "mpi.out").string() + " 2>&1";
  const int raw = std::system(cmd.c_str());
  EXPECT_TRUE(WIFEXITED(raw) && WEXITSTATUS(raw) == 1);
  const std::string said = slurp(dir_ / "mpi.out");
  const auto first = said.find("\"/initial/omegaa/0\" is not in the scene");
  EXPECT_NE(first, std::string::npos) << said;
  EXPECT_EQ(said.find("lgi: error:", said.find("lgi: error:") + 1), std::string::npos) << said;  // once, not per rank
  EXPECT_FALSE(fs::exists(dir_ / "bad.csv"));
}
#endif

}  // namespace
