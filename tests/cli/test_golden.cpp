// The bytes `lgi` writes, pinned: every scene of scenes/ and scenes/bench/, every method on four problems (fixed
// steps; with projection and adaptive steps where the method takes them), sweeps (batched, member by member, with
// in-run records, the Euler-angle top), shards merged, and a stopped run resumed — each output's FNV-1a hash and exit
// status against tests/cli/golden_outputs.txt, recorded from the binary before the engine was restructured (commit
// 0364ffb's code), so that no change of structure changes a bit of a result.
//
// Regenerate (only when a change of results is intended, and say so in the commit):
//   LGI_GOLDEN_WRITE=1 build/tests/test_golden      (writes tests/cli/golden_outputs.txt)
#include "../apps/hashing.hpp"
#include "lgi_process.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using lgi::test::slurp;

namespace {

class Golden : public lgi::test::CommandTest {
 protected:
  Golden() : CommandTest("golden") {}

  // name → "status hash bytes"
  std::map<std::string, std::string> got_;

  void record(const std::string& name, int status, const std::string& bytes) {
    got_[name] = std::to_string(status) + " " + lgi::app::hex64(lgi::app::fnv1a(bytes)) + " " +
                 std::to_string(bytes.size());
  }
  // lgi ARGS with -o OUT; records the status and OUT's bytes (empty when not written).
  int run_and_record(const std::string& name, const std::string& args, const fs::path& out) {
    fs::remove(out);
    const lgi::test::CommandResult r = lgi(args + " -q -o " + out.string());
    record(name, r.status, fs::exists(out) ? slurp(out) : std::string());
    return r.status;
  }

  std::vector<std::string> methods() {
    const lgi::test::CommandResult r = lgi("list --markdown");
    std::vector<std::string> names;
    const std::regex row("^\\| `([a-z0-9_]+)` \\|");
    std::istringstream in(r.out);
    for (std::string line; std::getline(in, line);)
      if (std::smatch m; std::regex_search(line, m, row)) names.push_back(m[1]);
    return names;
  }

  void compare() {
    const std::string file = LGI_GOLDEN_FILE;
    if (std::getenv("LGI_GOLDEN_WRITE")) {
      std::ofstream out(file, std::ios::trunc);
      out << "# name status fnv1a64 bytes — tests/cli/test_golden.cpp (LGI_GOLDEN_WRITE=1 build/tests/test_golden)\n";
      for (const auto& [name, value] : got_) out << name << " " << value << "\n";
      std::printf("[ written  ] %zu outputs to %s\n", got_.size(), file.c_str());
      return;
    }
    std::map<std::string, std::string> expected;
    std::ifstream in(file);
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || line[0] == '#') continue;
      const auto space = line.find(' ');
      expected[line.substr(0, space)] = line.substr(space + 1);
    }
    ASSERT_FALSE(expected.empty()) << file << " is missing or empty";
    int differ = 0;
    for (const auto& [name, value] : expected) {
      const auto it = got_.find(name);
      if (it == got_.end()) {
        ADD_FAILURE() << name << ": not produced (expected " << value << ")";
        ++differ;
      } else if (it->second != value) {
        ADD_FAILURE() << name << ": got " << it->second << ", expected " << value;
        ++differ;
      }
    }
    for (const auto& [name, value] : got_)
      if (!expected.count(name)) ADD_FAILURE() << name << ": not in the fixture (" << value << ")";
    std::printf("[ measured ] %zu outputs compared, %d differ\n", expected.size(), differ);
  }
};

// The problems every method is run on: (name, problem and initial sections, dt, t_end, every).
struct Case {
  std::string name, body;
  double dt, t_end;
  int every;
};
const std::vector<Case> cases = {
    {"heavy_top_skew",
     R"("problem": {"type": "heavy_top", "inertia": [[0.8, 0.1, -0.05], [0.1, 0.7, 0.05], [-0.05, 0.05, 0.9]],
        "b": 1.0, "k": [0.0, 0.0, 1.0], "z0": [0.48, 0.6, 0.64]}, "initial": {"omega": [2.0, 1.0, -1.0]})",
     0.01, 2.0, 25},
    {"free_body", R"("problem": {"type": "free_body", "inertia": [1, 2, 3]}, "initial": {"omega": [1.0, 0.1, 0.2]})",
     0.01, 2.0, 25},
    {"lagrange_top",
     R"("problem": {"type": "lagrange_top", "inertia": [2, 2, 1], "b": 1, "k": [0, 0.6, 0.8]},
        "initial": {"omega": [0.1, 0.2, 5.0]})",
     0.01, 2.0, 25},
    {"kovalevskaya_top",
     R"("problem": {"type": "kovalevskaya_top", "inertia": [2, 2, 1], "b": 1, "k": [0, 0.6, 0.8], "z0": [0.6, 0.8, 0]},
        "initial": {"omega": [0.5, -0.3, 2.0]})",
     0.01, 2.0, 25},
    {"euler_angles",
     R"("problem": {"type": "lagrange_top_euler_angles", "I2": 2.0, "I3": 1.0, "b": 1.0, "k2": 0.0, "k3": 1.0},
        "initial": {"euler_angles": [0.0, 0.5, 0.0], "euler_rates": [0.3, 0.0, 4.0]})",
     0.01, 2.0, 25},
};

TEST_F(Golden, OutputsAreThoseOfTheRecordedBinary) {
  // Every scene.
  for (const std::string dir : {"scenes", "scenes/bench"})
    for (const auto& e : fs::directory_iterator(fs::path(LGI_SOURCE_DIR) / dir))
      if (e.path().extension() == ".json")
        run_and_record("scene:" + dir + "/" + e.path().filename().string(), "run " + e.path().string(), dir_ / "out.csv");

  // Every method on each problem: fixed steps, projected, adaptive (where the method takes them: else exit 1).
  const std::vector<std::string> names = methods();
  ASSERT_GE(names.size(), 40u);
  for (const Case& c : cases)
    for (const std::string& m : names)
      for (const std::string variant : {"fixed", "projected", "adaptive"}) {
        std::string integrator = R"("method": ")" + m + R"(", "dt": )" + std::to_string(c.dt);
        if (variant == std::string("projected")) integrator += R"(, "projection": true)";
        if (variant == std::string("adaptive")) integrator += R"(, "rtol": 1e-8, "atol": 1e-8)";
        write("s.json", "{" + c.body + R"(, "integrator": {)" + integrator + R"(}, "t_end": )" +
                            std::to_string(c.t_end) + R"(, "output": {"every": )" + std::to_string(c.every) + "}}");
        run_and_record("method:" + c.name + ":" + m + ":" + variant, "run " + (dir_ / "s.json").string(), dir_ / "out.csv");
      }

  // Sweeps: batched LGVI (and --no-batch), member by member with in-run records, the Euler-angle top; shards merged.
  const std::string top = R"("problem": {"type": "heavy_top", "inertia": [2, 2, 1], "b": 1, "k": [0, 0.6, 0.8]},
    "initial": {"omega": [0.1, 0.2, 5.0]}, "t_end": 2)";
  write("batched.json", "{" + top + R"(, "integrator": {"method": "lgvi", "dt": 0.01},
    "sweep": {"grid": {"/initial/omega/0": {"from": -1, "to": 1, "count": 5}, "/problem/b": [0.5, 1, 2]}}})");
  write("records.json", "{" + top + R"(, "integrator": {"method": "rkmk4", "dt": 0.01},
    "sweep": {"random": {"seed": 11, "count": 7, "ranges": {"/initial/omega/2": [3, 6]}},
              "extrema": ["tilt", "omega3"], "section": {"function": "omega1", "value": 0, "direction": "both"},
              "lyapunov": {}}})");
  fs::copy_file(fs::path(LGI_SOURCE_DIR) / "examples/sweep/sleeping_top.json", dir_ / "euler.json");
  for (const std::string s : {"batched", "records", "euler"}) {
    const std::string file = (dir_ / (s + ".json")).string();
    run_and_record("sweep:" + s, "sweep " + file, dir_ / "sweep.csv");
    if (s == "records") record("sweep:records:crossings", 0, slurp(dir_ / "sweep.crossings.csv"));
    if (s == "batched") run_and_record("sweep:batched:no-batch", "sweep --no-batch " + file, dir_ / "sweep.csv");
    for (int i = 0; i < 3; ++i)
      ASSERT_EQ(lgi("sweep " + file + " -q --shard " + std::to_string(i) + "/3 -o " +
                    (dir_ / ("p" + std::to_string(i) + ".csv")).string())
                    .status,
                0);
    run_and_record("merge:" + s, "merge " + (dir_ / "p2.csv").string() + " " + (dir_ / "p0.csv").string() + " " +
                                     (dir_ / "p1.csv").string(),
                   dir_ / "merged.csv");
    EXPECT_EQ(got_["merge:" + s], got_["sweep:" + s]) << "the merged shards are the serial sweep";
  }

  // A run stopped by its budget twice and resumed: the uninterrupted run's bytes.
  write("long.json", "{" + top.substr(0, top.rfind(',')) + R"(, "integrator": {"method": "lgvi", "dt": 0.001},
    "t_end": 10, "output": {"every": 250}, "limits": {"max_steps": 3000}})");
  const std::string ck = (dir_ / "ck.json").string(), out = (dir_ / "resumed.csv").string();
  EXPECT_EQ(lgi("run " + (dir_ / "long.json").string() + " -q -o " + out + " --checkpoint " + ck).status, 6);
  EXPECT_EQ(lgi("run --resume " + ck + " -q").status, 6);
  EXPECT_EQ(lgi("run --resume " + ck + " -q").status, 6);
  EXPECT_EQ(lgi("run --resume " + ck + " -q").status, 0);
  record("resume:lgvi", 0, slurp(out));

  compare();
}

}  // namespace
