// The `lgi` command, run as a separate process: every malformed scene gets one message on stderr that
// names the file and JSON path, exit status 1, and no output file; valid scenes write the CSV of the
// contract (shared/DESIGN.md §3); a failing integration exits 2 and keeps the rows to its last good state
// (more on failures, budgets, signals and checkpoints in test_checkpoint.cpp).
#include "lgi_process.hpp"

#include <lgi/core/attitude.hpp>
#include <lgi/core/so3.hpp>

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using Result = lgi::test::CommandResult;
using lgi::test::slurp;

class Cli : public lgi::test::CommandTest {
 protected:
  Cli() : CommandTest("cli") {}
};

// A valid heavy-top scene; designated initialisers replace one piece at a time.
struct SceneText {
  std::string problem =
      R"("problem": {"type": "heavy_top", "inertia": [[2, 0, 0], [0, 2, 0], [0, 0, 1]], "b": 1.0, "k": [0, 0, 1], "z0": [0, 0, 1]})";
  std::string initial = R"("initial": {"R": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "omega": [0.1, 0.2, 5.0]})";
  std::string integrator = R"("integrator": {"method": "lgvi", "dt": 0.001})";
  std::string rest = R"("t_end": 1.0, "output": {"times": [0.5, 1]})";
  operator std::string() const {
    return "{\n  " + problem + ",\n  " + initial + ",\n  " + integrator + ",\n  " + rest + "\n}\n";
  }
};

std::string heavy(const std::string& fields) { return R"("problem": {"type": "heavy_top", )" + fields + "}"; }
const std::string kI = R"("inertia": [2, 2, 1])";

struct BadScene {
  const char* name;
  std::string text;
  std::string path;     // the JSON pointer the message must name
  std::string message;  // and a phrase it must contain
};

std::vector<BadScene> bad_scenes() {
  return {
      {"invalid_json", "{\n  \"problem\": {\"type\": \"heavy_top\",,\n}", ":2:", "invalid JSON"},
      {"truncated_json", "{\"problem\": [1, 2", ":1:", "invalid JSON"},
      {"empty_file", "", "", "empty"},
      {"duplicate_key", std::string(SceneText{.problem = heavy(kI + R"(, "b": 1, "b": 2)")}), "/problem",
       "duplicate key \"b\""},
      {"top_not_object", "[1, 2, 3]", "/", "expected an object"},
      {"missing_integrator",
       "{" + std::string(SceneText{}).substr(1, std::string(SceneText{}).find("\"integrator\"") - 1) + R"("t_end": 1})",
       "/", "missing key \"integrator\""},
      {"missing_dt", std::string(SceneText{.integrator = R"("integrator": {"method": "lgvi"})"}), "/integrator",
       "missing key \"dt\""},
      {"missing_omega", std::string(SceneText{.initial = R"("initial": {})"}), "/initial", "missing the angular velocity"},
      {"missing_inertia", std::string(SceneText{.problem = heavy(R"("b": 1)")}), "/problem", "missing key \"inertia\""},
      {"missing_b", std::string(SceneText{.problem = heavy(kI)}), "/problem", "missing key \"b\""},
      {"unknown_top_key", std::string(SceneText{.rest = R"("t_end": 1, "speed": 2)"}), "/speed", "unknown key"},
      {"unknown_problem_key", std::string(SceneText{.problem = heavy(kI + R"(, "b": 1, "mass": 2)")}), "/problem/mass",
       "unknown key for heavy_top"},
      {"free_body_has_no_b",
       std::string(SceneText{.problem = R"("problem": {"type": "free_body", "inertia": [1, 2, 2], "b": 1})"}),
       "/problem/b", "unknown key for free_body"},
      {"unknown_problem", std::string(SceneText{.problem = R"("problem": {"type": "spinning_plate"})"}),
       "/problem/type", "unknown problem type \"spinning_plate\" (known: free_body, heavy_top, "},
      {"dt_string", std::string(SceneText{.integrator = R"("integrator": {"method": "lgvi", "dt": "fast"})"}),
       "/integrator/dt", "expected a number, got a string (\"fast\")"},
      {"b_bool", std::string(SceneText{.problem = heavy(kI + R"(, "b": true)")}), "/problem/b",
       "expected a number, got true"},
      {"method_number", std::string(SceneText{.integrator = R"("integrator": {"method": 4, "dt": 0.1})"}),
       "/integrator/method", "expected a string"},
      {"b_overflow", std::string(SceneText{.problem = heavy(kI + R"(, "b": 1e400)")}), "/problem/b",
       "out of the range of a double"},
      {"omega_overflow", std::string(SceneText{.initial = R"("initial": {"omega": [0, -1e999, 0]})"}),
       "/initial/omega/1", "out of the range of a double"},
      {"omega_null", std::string(SceneText{.initial = R"("initial": {"omega": [0, null, 0]})"}), "/initial/omega/1",
       "expected a number, got null"},
      {"omega_length", std::string(SceneText{.initial = R"("initial": {"omega": [0, 1]})"}), "/initial/omega",
       "expected an array of 3 numbers"},
      {"inertia_not_symmetric",
       std::string(SceneText{.problem = heavy(R"("inertia": [[2, 0.1, 0], [0.2, 2, 0], [0, 0, 1]], "b": 1)")}),
       "/problem/inertia/0/1", "not symmetric"},
      {"inertia_not_positive_definite",
       std::string(SceneText{.problem = heavy(R"("inertia": [[1, 2, 0], [2, 1, 0], [0, 0, 1]], "b": 1)")}),
       "/problem/inertia", "not positive definite"},
      {"inertia_negative_diagonal", std::string(SceneText{.problem = heavy(R"("inertia": [1, -1, 1], "b": 1)")}),
       "/problem/inertia", "not positive definite"},
      {"inertia_triangle", std::string(SceneText{.problem = heavy(R"("inertia": [1, 1, 3], "b": 1)")}),
       "/problem/inertia", "triangle inequality"},
      {"inertia_shape", std::string(SceneText{.problem = heavy(R"("inertia": [[1, 0], [0, 1]], "b": 1)")}),
       "/problem/inertia", "expected a 3x3 array"},
      {"inertia_row", std::string(SceneText{.problem = heavy(R"("inertia": [[1, 0, 0], [0, 1], [0, 0, 1]], "b": 1)")}),
       "/problem/inertia/1", "expected a row of 3 numbers"},
      {"b_negative", std::string(SceneText{.problem = heavy(kI + R"(, "b": -1)")}), "/problem/b", "must be >= 0"},
      {"k_not_unit", std::string(SceneText{.problem = heavy(kI + R"(, "b": 1, "k": [0, 0, 2])")}), "/problem/k",
       "must be a unit vector"},
      {"z0_not_unit", std::string(SceneText{.problem = heavy(kI + R"(, "b": 1, "z0": [0.2, 0, 1])")}), "/problem/z0",
       "must be a unit vector"},
      {"z0_zero", std::string(SceneText{.problem = heavy(kI + R"(, "b": 1, "z0": [0, 0, 0])")}), "/problem/z0",
       "must be a unit vector"},
      {"R_not_rotation",
       std::string(
           SceneText{.initial = R"("initial": {"R": [[1, 0, 0], [0, 1, 0.1], [0, 0, 1]], "omega": [0, 0, 1]})"}),
       "/initial/R", "must be a rotation matrix"},
      {"R_reflection",
       std::string(SceneText{.initial = R"("initial": {"R": [[-1, 0, 0], [0, 1, 0], [0, 0, 1]], "omega": [0, 0, 1]})"}),
       "/initial/R", "det R = -1"},
      {"dt_zero", std::string(SceneText{.integrator = R"("integrator": {"method": "lgvi", "dt": 0})"}),
       "/integrator/dt", "must be > 0"},
      {"dt_negative", std::string(SceneText{.integrator = R"("integrator": {"method": "lgvi", "dt": -0.1})"}),
       "/integrator/dt", "must be > 0"},
      {"t_end_negative", std::string(SceneText{.rest = R"("t_end": -1)"}), "/t_end", "must be >= 0"},
      {"too_many_steps", std::string(SceneText{.integrator = R"("integrator": {"method": "lgvi", "dt": 1e-300})"}),
       "/integrator/dt", "steps, more than"},
      {"time_after_end", std::string(SceneText{.rest = R"("t_end": 1, "output": {"times": [0.5, 2]})"}),
       "/output/times/1", "outside [0, t_end = 1]"},
      {"time_negative", std::string(SceneText{.rest = R"("t_end": 1, "output": {"times": [-0.5]})"}), "/output/times/0",
       "outside"},
      {"times_not_increasing", std::string(SceneText{.rest = R"("t_end": 1, "output": {"times": [0.5, 0.7, 0.6]})"}),
       "/output/times/2", "must increase"},
      {"times_repeated", std::string(SceneText{.rest = R"("t_end": 1, "output": {"times": [0.5, 0.5]})"}),
       "/output/times/1", "must increase"},
      {"times_and_every", std::string(SceneText{.rest = R"("t_end": 1, "output": {"times": [0.5], "every": 10})"}),
       "/output", "give one of \"times\", \"every\" and \"interval\""},
      {"unknown_method", std::string(SceneText{.integrator = R"("integrator": {"method": "rk45", "dt": 0.1})"}),
       "/integrator/method", "unknown method \"rk45\" (known: lgvi, rkmk4, lie_euler, "},
      {"every_huge", std::string(SceneText{.rest = R"("t_end": 1, "output": {"every": 1e300})"}), "/output/every",
       "expected an integer"},
      {"every_fraction", std::string(SceneText{.rest = R"("t_end": 1, "output": {"every": 2.7})"}), "/output/every",
       "expected an integer"},
      {"every_negative", std::string(SceneText{.rest = R"("t_end": 1, "output": {"every": -1})"}), "/output/every",
       "expected an integer"},
      {"max_iterations_fraction",
       std::string(SceneText{.integrator = R"("integrator": {"method": "lgvi", "dt": 0.1, "max_iterations": 2.7})"}),
       "/integrator/max_iterations", "expected an integer"},
      {"tolerance_for_explicit",
       std::string(SceneText{.integrator = R"("integrator": {"method": "rkmk4", "dt": 0.1, "tolerance": 1e-12})"}),
       "/integrator/tolerance", "unknown key for method rkmk4"},
      {"deep_nesting",
       std::string(SceneText{.rest = R"("t_end": 1, "output": )" + std::string(100, '[') + std::string(100, ']')}),
       "/output/0/0/0", "nesting deeper than 64 levels"},
      {"inertia_tiny_scale", std::string(SceneText{.problem = heavy(R"("inertia": [1e-300, 1e-300, 1e-300], "b": 1)")}),
       "/problem/inertia", "outside [1e-150, 1e150]"},
      // adaptive steps and projection (integrators/adaptive.hpp, projection.hpp)
      {"rtol_without_embedded_pair",
       std::string(SceneText{.integrator = R"("integrator": {"method": "rkmk4", "dt": 0.1, "rtol": 1e-8, "atol": 1e-8})"}),
       "/integrator/rtol", "method rkmk4 has no embedded error estimate"},
      {"atol_without_embedded_pair",
       std::string(SceneText{.integrator = R"("integrator": {"method": "lgvi", "dt": 0.1, "atol": 1e-8})"}),
       "/integrator/atol", "need one of rkmk_dp5, rkmk_dp8"},
      {"projection_on_symplectic",
       std::string(SceneText{.integrator = R"("integrator": {"method": "lgvi", "dt": 0.1, "projection": true})"}),
       "/integrator/projection", "method lgvi is symplectic"},
      {"projection_not_bool",
       std::string(SceneText{.integrator = R"("integrator": {"method": "rkmk4", "dt": 0.1, "projection": 1})"}),
       "/integrator/projection", "expected true or false"},
      {"rtol_zero",
       std::string(SceneText{.integrator = R"("integrator": {"method": "rkmk_dp5", "dt": 0.1, "rtol": 0, "atol": 1e-8})"}),
       "/integrator/rtol", "must be > 0"},
      {"atol_negative",
       std::string(SceneText{.integrator = R"("integrator": {"method": "rkmk_dp8", "dt": 0.1, "rtol": 1e-8, "atol": -1e-8})"}),
       "/integrator/atol", "must be > 0"},
      {"atol_overflow",
       std::string(SceneText{.integrator = R"("integrator": {"method": "rkmk_dp5", "dt": 0.1, "rtol": 1e-8, "atol": 1e400})"}),
       "/integrator/atol", "out of the range of a double"},
      {"rtol_string",
       std::string(SceneText{.integrator = R"("integrator": {"method": "dop853_quat", "dt": 0.1, "rtol": "1e-8", "atol": 1e-8})"}),
       "/integrator/rtol", "expected a number"},
      {"rtol_below_roundoff",
       std::string(SceneText{.integrator = R"("integrator": {"method": "rkmk_dp5", "dt": 0.1, "rtol": 1e-20, "atol": 1e-8})"}),
       "/integrator/rtol", "10 machine epsilons"},
      {"rtol_without_atol",
       std::string(SceneText{.integrator = R"("integrator": {"method": "rkmk_dp5", "dt": 0.1, "rtol": 1e-8})"}),
       "/integrator", "needs both \"rtol\" and \"atol\""},
      {"projection_time_dependent_torque",
       std::string(SceneText{
           .problem = R"("problem": {"type": "satellite", "inertia": [1, 2, 3], "n": 1, "radial": [1, 0, 0], "normal": [0, 0, 1]})",
           .integrator = R"("integrator": {"method": "rkmk4", "dt": 0.1, "projection": true})"}),
       "/integrator/projection", "time-dependent torque"},
  };
}

TEST_F(Cli, EveryMalformedSceneGetsOneMessageNamingThePathAndNoOutput) {
  for (const BadScene& bad : bad_scenes()) {
    SCOPED_TRACE(bad.name);
    const fs::path file = write(std::string(bad.name) + ".json", bad.text);
    const fs::path out = dir_ / "out.csv";
    const Result r = lgi("run " + file.string() + " -o " + out.string());
    EXPECT_EQ(r.status, 1);
    EXPECT_EQ(r.out, "");
    EXPECT_FALSE(fs::exists(out));
    // One line: "lgi: error: <file>: <path>: <message>" (or <file>:<line>:<col>: for syntax errors).
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("lgi: error: " + file.string(), 0), 0u) << r.err;
    if (!bad.path.empty()) {
      const std::string located = file.string() + (bad.path[0] == ':' ? "" : ": ") + bad.path;
      EXPECT_NE(r.err.find(located), std::string::npos) << r.err;
    }
    EXPECT_NE(r.err.find(bad.message), std::string::npos) << r.err;
    // Nothing left beside the output either (no temporary files).
    for (const auto& entry : fs::directory_iterator(dir_))
      EXPECT_EQ(
          entry.path().extension() == ".csv" || entry.path().filename().string().find(".tmp-") != std::string::npos,
          false)
          << entry.path();
  }
}

TEST_F(Cli, UnreadableFile) {
  const Result r = lgi("run " + (dir_ / "missing.json").string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("missing.json: cannot read the file: No such file or directory"), std::string::npos) << r.err;
  const Result d = lgi("run " + dir_.string());  // a directory
  EXPECT_EQ(d.status, 1);
  EXPECT_NE(d.err.find("cannot read the file"), std::string::npos) << d.err;
}

TEST_F(Cli, InvalidJsonNamesLineAndColumn) {
  const fs::path file = write("syntax.json", "{\n  \"t_end\": 1,\n  \"problem\": [1 2]\n}\n");
  const Result r = lgi("run " + file.string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(file.string() + ":3:17: invalid JSON"), std::string::npos) << r.err;
}

// Parses the CSV on stdout into a header and rows of numbers.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::vector<std::vector<std::string>> text;
  std::size_t column(const std::string& name) const {
    return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
  }
};

Csv parse_csv(const std::string& s) {
  Csv csv;
  std::istringstream in(s);
  std::string line;
  bool first = true;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) cells.push_back(cell);
    if (first) {
      csv.header = cells;
      first = false;
      continue;
    }
    std::vector<double> row;
    for (const auto& c : cells) row.push_back(std::stod(c));
    csv.rows.push_back(row);
    csv.text.push_back(cells);
  }
  return csv;
}

TEST_F(Cli, CsvContract) {
  const fs::path file =
      write("ok.json", std::string(SceneText{.integrator = R"("integrator": {"method": "lgvi", "dt": 0.03})",
                                             .rest = R"("t_end": 1.0, "output": {"times": [0.1, 0.5, 0.7]})"}));
  const Result r = lgi("run " + file.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv csv = parse_csv(r.out);
  for (const char* name : {"t", "R11", "R12", "R13", "R21", "R22", "R23", "R31", "R32", "R33", "omega1", "omega2",
                           "omega3", "energy", "orthogonality_error", "momentum_k"})
    EXPECT_LT(csv.column(name), csv.header.size()) << name;
  ASSERT_EQ(csv.rows.size(), 5u);  // t = 0, the three times, t_end
  const std::vector<std::string> t = {"0", "0.10000000000000001", "0.5", "0.69999999999999996", "1"};
  for (std::size_t i = 0; i < t.size(); ++i) EXPECT_EQ(csv.text[i][csv.column("t")], t[i]);  // exactly the times asked
  EXPECT_EQ(csv.text[0][csv.column("omega1")], "0.10000000000000001");                       // 17 significant digits
  for (const auto& row : csv.rows) {
    EXPECT_LT(row[csv.column("orthogonality_error")], 1e-14);
    EXPECT_NEAR(row[csv.column("energy")], csv.rows[0][csv.column("energy")], 1e-3);
  }
  // The summary on stderr: method, steps, energy error, orthogonality, wall time.
  for (const char* word : {"lgvi", "steps", "energy error", "orthogonality", "wall time"})
    EXPECT_NE(r.err.find(word), std::string::npos) << word << " in " << r.err;

  // -o writes the same bytes to a file; -q silences stderr.
  const fs::path out = dir_ / "run.csv";
  const Result q = lgi("run -q " + file.string() + " -o " + out.string());
  ASSERT_EQ(q.status, 0);
  EXPECT_EQ(q.out, "");
  EXPECT_EQ(q.err, "");
  EXPECT_EQ(slurp(out), r.out);
}

TEST_F(Cli, OutputEvery) {
  const fs::path file =
      write("every.json", std::string(SceneText{.integrator = R"("integrator": {"method": "rkmk4", "dt": 0.01})",
                                                .rest = R"("t_end": 1.005, "output": {"every": 25})"}));
  const Result r = lgi("run -q " + file.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv csv = parse_csv(r.out);
  ASSERT_EQ(csv.rows.size(), 6u);  // steps 0, 25, 50, 75, 100, then t_end = 1.005
  EXPECT_DOUBLE_EQ(csv.rows[1][0], 0.25);
  EXPECT_EQ(csv.text.back()[0], "1.0049999999999999");
}

// The summary says how the run was made: adaptive (with its tolerances) and projected. Projection is taken by
// every non-symplectic method, whatever its internal state (CF4: (R, Ω); split_dmv4: quaternion and
// principal-axis momentum), and the energy column shows it.
TEST_F(Cli, SummarySaysAdaptiveAndProjected) {
  for (const char* method : {"cf4", "split_dmv4"}) {
    const fs::path file = write(std::string(method) + ".json",
                                std::string(SceneText{.integrator = std::string(R"("integrator": {"method": ")") + method +
                                                                    R"(", "dt": 0.01, "projection": true})",
                                                      .rest = R"("t_end": 20.0, "output": {"every": 100})"}));
    const Result r = lgi("run " + file.string());
    ASSERT_EQ(r.status, 0) << method << ": " << r.err;
    EXPECT_NE(r.err.find("projected"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("adaptive"), std::string::npos) << r.err;
    const Csv csv = parse_csv(r.out);
    const double E0 = csv.rows[0][csv.column("energy")];
    for (const auto& row : csv.rows) EXPECT_NEAR(row[csv.column("energy")], E0, 1e-13 * std::abs(E0)) << method;
  }
  const fs::path file = write(
      "dp5.json", std::string(SceneText{.integrator = R"("integrator": {"method": "rkmk_dp5", "dt": 0.01, "rtol": 1e-9, "atol": 1e-10})"}));
  const Result r = lgi("run " + file.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("adaptive         rtol = 1e-09, atol = 1e-10"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("projected"), std::string::npos) << r.err;
}

// --error-estimate adds one summary line (runner.hpp, estimate_error; measured against true errors in
// test_error_estimate.cpp): for fixed steps the Richardson comparison with 2 dt, and the rows are those of a run
// without it.
TEST_F(Cli, ErrorEstimateAddsOneLineAndChangesNoRow) {
  const fs::path file = write("estimate.json", std::string(SceneText{
      .integrator = R"("integrator": {"method": "rkmk4", "dt": 0.01})", .rest = R"("t_end": 5.0, "output": {"every": 100})"}));
  const Result plain = lgi("run " + file.string());
  const Result r = lgi("run --error-estimate " + file.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.out, plain.out);
  EXPECT_NE(r.err.find("  estimated error  R "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Richardson with dt = 0.02 (order 4)"), std::string::npos) << r.err;
  EXPECT_EQ(plain.err.find("estimated error"), std::string::npos) << plain.err;
  const Result q = lgi("run -q --error-estimate " + file.string());
  EXPECT_EQ(q.err, "");
}

// --tol: the scene's integrator replaced by "auto"; the summary names the choice and estimates the error; rows every
// N steps become rows every N dt; bad values and a resumed run are refused.
TEST_F(Cli, TolRunsMethodAutoWithItsEstimate) {
  const fs::path file = write("tol.json", std::string(SceneText{
      .integrator = R"("integrator": {"method": "rkmk4", "dt": 0.01})", .rest = R"("t_end": 5.0, "output": {"every": 100})"}));
  const Result r = lgi("run --tol 1e-8 " + file.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("heavy_top, rkmk_vern9_cayley (order 9"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("  method auto      tolerance 1e-08"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("  estimated error  R "), std::string::npos) << r.err;
  const Csv csv = parse_csv(r.out);
  ASSERT_EQ(csv.rows.size(), 6u);  // t = 0, 1, …, 5
  EXPECT_EQ(csv.rows[1][0], 1.0);
  const Result quiet = lgi("run --tol 1e-8 --no-error-estimate " + file.string());
  EXPECT_EQ(quiet.err.find("estimated error"), std::string::npos) << quiet.err;
  EXPECT_EQ(quiet.out, r.out);
  const Result bad = lgi("run --tol 0 " + file.string());
  EXPECT_EQ(bad.status, 1);
  EXPECT_EQ(bad.err, "lgi: error: --tol: must be in [1e-13, 0.1], got 0\n");
}

// Every attitude form — a quaternion of either sign, axis and angle (the axis of any length), z-x-z and z-y-x Euler
// angles in radians and degrees, with omega or with Euler-angle rates — gives the first row of the equivalent R and
// omega, to the rounding of the conversions (R = Rx(30°), Ω = (5, 0.2, 0.1): the rates below are chosen so).
TEST_F(Cli, EveryAttitudeFormGivesTheRowOfTheEquivalentR) {
  const double pi = 3.14159265358979323846, c = std::cos(pi / 6), s = std::sin(pi / 6);
  const auto first_row = [&](const std::string& initial) {
    const fs::path file = write("form.json", std::string(SceneText{.initial = R"("initial": )" + initial,
                                                                   .rest = R"("t_end": 0.01)"}));
    const Result r = lgi("run -q " + file.string());
    EXPECT_EQ(r.status, 0) << initial << "\n" << r.err;
    const Csv csv = parse_csv(r.out);
    return csv.rows.empty() ? std::vector<double>() : csv.rows.front();
  };
  char R[160];
  std::snprintf(R, sizeof R, "[[1, 0, 0], [0, %.17g, %.17g], [0, %.17g, %.17g]]", c, -s, s, c);
  const std::vector<double> expected = first_row(std::string(R"({"R": )") + R + R"(, "omega": [5, 0.2, 0.1]})");
  ASSERT_FALSE(expected.empty());
  char q[200], q_neg[200];
  std::snprintf(q, sizeof q, R"({"quaternion": [%.17g, %.17g, 0, 0], "omega": [5, 0.2, 0.1]})", std::cos(pi / 12),
                std::sin(pi / 12));
  std::snprintf(q_neg, sizeof q_neg, R"({"quaternion": [%.17g, %.17g, 0, 0], "omega": [5, 0.2, 0.1]})",
                -std::cos(pi / 12), -std::sin(pi / 12));
  // z-x-z (φ, θ, ψ) = (0, 30°, 0): Ω = φ'(0, sinθ, cosθ) + θ'(1, 0, 0) + ψ'(0, 0, 1) → θ' = 5, φ' = 0.4, ψ' = 0.1 − 0.4 cosθ.
  // z-y-x (ψ, θ, φ) = (0, 0, 30°): Ω = (φ', θ' cosφ, −θ' sinφ) + ψ'(0, sinφ, cosφ) → φ' = 5, and θ', ψ' from
  // (0.2, 0.1) turned by −φ: θ' = 0.2 c − 0.1 s, ψ' = 0.2 s + 0.1 c.
  const double deg = 180 / pi;
  char axis_long[160];
  std::snprintf(axis_long, sizeof axis_long, R"({"axis_angle": {"axis": [2.5, 0, 0], "angle": %.17g}, "omega": [5, 0.2, 0.1]})",
                pi / 6);
  char zxz_rad[200], zxz_deg[200], zyx_rad[200], zyx_deg[200];
  std::snprintf(zxz_rad, sizeof zxz_rad, R"({"euler_angles": [0, %.17g, 0], "euler_rates": [0.4, 5, %.17g]})", pi / 6,
                0.1 - 0.4 * c);
  std::snprintf(zxz_deg, sizeof zxz_deg,
                R"({"euler_angles": {"convention": "zxz", "angles": [0, 30, 0], "unit": "deg"}, )"
                R"("euler_rates": [%.17g, %.17g, %.17g]})",
                0.4 * deg, 5 * deg, (0.1 - 0.4 * c) * deg);
  std::snprintf(zyx_rad, sizeof zyx_rad,
                R"({"euler_angles": {"convention": "zyx", "angles": [0, 0, %.17g]}, "euler_rates": [%.17g, %.17g, 5]})",
                pi / 6, 0.2 * s + 0.1 * c, 0.2 * c - 0.1 * s);
  std::snprintf(zyx_deg, sizeof zyx_deg,
                R"({"euler_angles": {"convention": "zyx", "angles": [0, 0, 30], "unit": "deg"}, "omega": [5, 0.2, 0.1]})");
  const std::vector<std::string> forms = {
      q, q_neg,
      R"({"axis_angle": {"axis": [1, 0, 0], "angle": 30, "unit": "deg"}, "omega": [5, 0.2, 0.1]})",
      axis_long,
      zxz_rad, zxz_deg, zyx_rad, zyx_deg,
  };
  for (const std::string& form : forms) {
    const std::vector<double> row = first_row(form);
    ASSERT_EQ(row.size(), expected.size()) << form;
    double worst = 0;
    for (std::size_t i = 0; i < row.size(); ++i) worst = std::max(worst, std::abs(row[i] - expected[i]));
    std::printf("%-110s first row within %.1e of R's\n", form.substr(0, 110).c_str(), worst);
    EXPECT_LE(worst, 4e-15) << form;  // a few ulps of the O(1)..O(10) entries (the energy is ≈ 13)
  }
}

// Attitudes typed or stored to a few decimals are made exact and said so; beyond the bound they are refused.
TEST_F(Cli, RoundedAttitudesAreProjectedAndReported) {
  const auto run = [&](const std::string& initial, const std::string& output = "rounded.csv") {
    const fs::path file = write("rounded.json", std::string(SceneText{.initial = R"("initial": )" + initial,
                                                                      .rest = R"("t_end": 0.01)"}));
    return lgi("run -o " + (dir_ / output).string() + " " + file.string());
  };
  // 30° about x to 4 decimals: |RᵀR − I| = 6.2e-5.
  const Result four = run(R"({"R": [[1, 0, 0], [0, 0.866, -0.5], [0, 0.5, 0.866]], "omega": [5, 0.2, 0.1]})");
  ASSERT_EQ(four.status, 0) << four.err;
  EXPECT_NE(four.err.find("lgi: warning: "), std::string::npos) << four.err;
  EXPECT_NE(four.err.find("/initial/R: projected onto SO(3), the nearest rotation (|R^T R - I| was 6.2e-05)"),
            std::string::npos) << four.err;
  EXPECT_NE(four.err.find("  input            /initial/R projected onto SO(3)"), std::string::npos) << four.err;
  // A float32 quaternion: normalised, below the warning's threshold, in the summary only.
  const Result f32 = run(R"({"quaternion": [0.9659258, 0.25881904, 0, 0], "omega": [5, 0.2, 0.1]})");
  ASSERT_EQ(f32.status, 0) << f32.err;
  EXPECT_EQ(f32.err.find("lgi: warning: "), std::string::npos) << f32.err;
  EXPECT_NE(f32.err.find("  input            /initial/quaternion normalised (its length was 1 "), std::string::npos)
      << f32.err;
  // Exact input: nothing to say.
  const Result exact = run(R"({"R": [[1, 0, 0], [0, 0.6, -0.8], [0, 0.8, 0.6]], "omega": [5, 0.2, 0.1]})");
  ASSERT_EQ(exact.status, 0) << exact.err;
  EXPECT_EQ(exact.err.find("input "), std::string::npos) << exact.err;
  // To one decimal: |RᵀR − I| = 0.085, refused with its value, nothing written.
  const Result one = run(R"({"R": [[1, 0, 0], [0, 0.9, -0.5], [0, 0.5, 0.9]], "omega": [5, 0.2, 0.1]})", "refused.csv");
  EXPECT_EQ(one.status, 1);
  EXPECT_NE(one.err.find("/initial/R: must be a rotation matrix (to 0.01): |R^T R - I| = 0.0848"), std::string::npos)
      << one.err;
  EXPECT_FALSE(fs::exists(dir_ / "refused.csv"));
}

// "output": {"interval": Δ} on an adaptive run: rows exactly at k·Δ from the dense output, the accepted steps and the
// final state those of the run without outputs (bytes of the last row); too fine a grid is refused.
TEST_F(Cli, OutputIntervalIsAUniformGridThatLeavesTheStepsAlone) {
  const std::string integrator = R"("integrator": {"method": "rkmk_dp8", "dt": 0.01, "rtol": 1e-10, "atol": 1e-10})";
  const auto run = [&](const std::string& rest) {
    const fs::path file = write("grid.json", std::string(SceneText{.integrator = integrator, .rest = rest}));
    return lgi("run " + file.string());
  };
  const Result plain = run(R"("t_end": 7.3)");
  const Result grid = run(R"("t_end": 7.3, "output": {"interval": 0.1})");
  ASSERT_EQ(plain.status, 0) << plain.err;
  ASSERT_EQ(grid.status, 0) << grid.err;
  const auto steps = [](const std::string& err) { return err.substr(err.find("  steps "), err.find('(', err.find("  steps ")) - err.find("  steps ")); };
  EXPECT_EQ(steps(grid.err), steps(plain.err));
  const Csv p = parse_csv(plain.out), g = parse_csv(grid.out);
  ASSERT_EQ(p.rows.size(), 2u);  // t = 0 and t_end
  ASSERT_EQ(g.rows.size(), 74u);  // 0, 0.1, …, 7.2 and 7.3
  EXPECT_EQ(g.text.back(), p.text.back());
  for (std::size_t k = 1; k + 1 < g.rows.size(); ++k) EXPECT_EQ(g.rows[k][0], static_cast<double>(k) * 0.1) << k;
  EXPECT_EQ(g.rows.back()[0], 7.3);
  const Result fine = run(R"("t_end": 7.3, "output": {"interval": 1e-7})");
  EXPECT_EQ(fine.status, 1);
  EXPECT_NE(fine.err.find("/output/interval: t_end/interval = 7.3e+07 rows, more than the 1e+07 an output grid may "
                          "have (use \"every\")"),
            std::string::npos)
      << fine.err;
  const Result both = run(R"("t_end": 7.3, "output": {"interval": 0.1, "every": 3})");
  EXPECT_EQ(both.status, 1);
  EXPECT_NE(both.err.find("/output: give one of \"times\", \"every\" and \"interval\""), std::string::npos) << both.err;
}

// "output": {"columns": [...]}: the header names the chosen groups in their order; the quaternion and both kinds of
// Euler angles give back the R of the same row (core/attitude.hpp's maps, applied here) to rounding; the quaternion
// is continuous (its sign follows the previous row's) while w changes sign; the default columns stay those of
// csv_header.
TEST_F(Cli, OutputColumnsAreTheChosenGroupsAndAgreeWithR) {
  const fs::path file = write(
      "columns.json",
      std::string(SceneText{.initial = R"("initial": {"omega": [0.3, 0.2, 5.0]})",
                            .integrator = R"("integrator": {"method": "lgvi", "dt": 0.01})",
                            .rest = R"("t_end": 5, "output": {"every": 1, "columns": ["t", "quaternion", "R",
                                        "euler_zxz", "euler_zyx_deg", "omega", "energy", "invariants"]})"}));
  const Result r = lgi("run -q " + file.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv csv = parse_csv(r.out);
  EXPECT_EQ(r.out.substr(0, r.out.find('\n')),
            "t,q_w,q_x,q_y,q_z,R11,R12,R13,R21,R22,R23,R31,R32,R33,zxz_phi,zxz_theta,zxz_psi,yaw_deg,pitch_deg,roll_deg,"
            "omega1,omega2,omega3,energy,momentum_k");
  ASSERT_EQ(csv.rows.size(), 501u);
  double worst_q = 0, worst_zxz = 0, worst_zyx = 0, largest_step = 0, w_min = 1;
  const double deg = 3.14159265358979323846 / 180;
  for (std::size_t i = 0; i < csv.rows.size(); ++i) {
    const auto& row = csv.rows[i];
    lgi::Mat3<double> R;
    for (int e = 0; e < 9; ++e) R(e / 3, e % 3) = row[5 + static_cast<std::size_t>(e)];
    worst_q = std::max(worst_q, (lgi::rotation_from_quaternion(row[1], row[2], row[3], row[4]) - R).cwiseAbs().maxCoeff());
    // z-x-z angles lose ε/sin θ near θ = 0, where this run starts (R = I): held where sin θ ≥ 0.1.
    if (std::sin(row[15]) >= 0.1)
      worst_zxz = std::max(worst_zxz, (lgi::rotation_from_euler(lgi::EulerConvention::zxz,
                                                                lgi::Vec3<double>(row[14], row[15], row[16])) - R)
                                          .cwiseAbs()
                                          .maxCoeff());
    worst_zyx = std::max(worst_zyx, (lgi::rotation_from_euler(lgi::EulerConvention::zyx,
                                                              lgi::Vec3<double>(lgi::Vec3<double>(row[17], row[18], row[19]) * deg)) - R)
                                        .cwiseAbs()
                                        .maxCoeff());
    w_min = std::min(w_min, row[1]);
    if (i > 0) {
      double d = 0;
      for (std::size_t k = 1; k <= 4; ++k) d += (row[k] - csv.rows[i - 1][k]) * (row[k] - csv.rows[i - 1][k]);
      largest_step = std::max(largest_step, std::sqrt(d));
    }
  }
  std::printf("output columns: R from q %.1e, from z-x-z angles %.1e, from z-y-x degrees %.1e; largest |q step| %.3f "
              "while w reaches %.2f\n", worst_q, worst_zxz, worst_zyx, largest_step, w_min);
  EXPECT_LT(worst_q, 2.5e-15);
  EXPECT_LT(worst_zxz, 1e-14);  // ε/sin θ ≤ 10 ε where held
  EXPECT_LT(worst_zyx, 4e-15);
  EXPECT_LT(w_min, -0.9);          // the attitude turns through more than π: q's sign had to be chosen
  EXPECT_LT(largest_step, 0.03);   // |Ω| h / 2 = 0.025 a step: no jump to −q
  // Bad groups: one message naming the entry.
  const auto bad = [&](const std::string& columns) {
    const fs::path f = write("bad_columns.json", std::string(SceneText{.rest = R"("t_end": 1, "output": {"columns": )" +
                                                                                columns + "}"}));
    return lgi("run -q " + f.string()).err;
  };
  EXPECT_NE(bad(R"(["t", "quaternions"])").find("/output/columns/1: unknown column group \"quaternions\"; did you mean "
                                                "\"quaternion\"?"),
            std::string::npos);
  EXPECT_NE(bad(R"(["t", "R", "t"])").find("/output/columns/2: \"t\" twice"), std::string::npos);
  EXPECT_NE(bad(R"([])").find("/output/columns: expected a non-empty array of column groups"), std::string::npos);
}

TEST_F(Cli, FailedIntegrationExitsTwoAndKeepsTheLastGoodState) {
  // h|Ω| = 1.5 about the symmetry axis: the LGVI's implicit equation has no solution.
  const fs::path file =
      write("fail.json", std::string(SceneText{.initial = R"("initial": {"omega": [0, 0, 150]})",
                                               .integrator = R"("integrator": {"method": "lgvi", "dt": 0.01})"}));
  const fs::path out = dir_ / "fail.csv";
  const Result r = lgi("run " + file.string() + " -o " + out.string());
  EXPECT_EQ(r.status, 2);
  const Csv csv = parse_csv(slurp(out));  // the rows to the last good state: here t = 0 only
  ASSERT_EQ(csv.rows.size(), 1u);
  EXPECT_EQ(csv.text[0][csv.column("omega3")], "150");
  EXPECT_NE(r.err.find("the step from t = 0 failed: Newton iteration did not converge"), std::string::npos) << r.err;
  // The cause and what helps, not a knob that cannot (no iteration limit finds a solution that does not exist).
  EXPECT_NE(r.err.find("h|omega| = 1.5 at the last good state, where the implicit equation of lgvi may have no "
                       "solution (none beyond h|omega| = 1 about a principal axis): take /integrator/dt below "
                       "0.0033333333333333335, or split_dmv"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(r.err.find("max_iterations"), std::string::npos) << r.err;
}

TEST_F(Cli, ZeroDurationWritesTheInitialStateOnce) {
  const fs::path file = write("zero.json", std::string(SceneText{.rest = R"("t_end": 0, "output": {"times": [0]})"}));
  const Result r = lgi("run -q " + file.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv csv = parse_csv(r.out);
  ASSERT_EQ(csv.rows.size(), 1u);
  EXPECT_EQ(csv.text[0][csv.column("omega1")], "0.10000000000000001");  // the input, untouched
}

TEST_F(Cli, OutputFileProblemsAreReportedBeforeTheRun) {
  const fs::path file = write("ok.json", std::string(SceneText{}));
  const Result missing = lgi("run -q " + file.string() + " -o " + (dir_ / "no" / "such" / "dir.csv").string());
  EXPECT_EQ(missing.status, 3);
  EXPECT_NE(missing.err.find("cannot create the output file: No such file or directory"), std::string::npos)
      << missing.err;
  const Result directory = lgi("run -q " + file.string() + " -o " + dir_.string());
  EXPECT_EQ(directory.status, 3);
  EXPECT_NE(directory.err.find("it is a directory"), std::string::npos) << directory.err;
}

TEST_F(Cli, OutputFileHasTheUsualPermissions) {
  const fs::path file = write("ok.json", std::string(SceneText{}));
  const fs::path out = dir_ / "perm.csv";
  const Result r = lgi("run -q " + file.string() + " -o " + out.string() + " ; true");
  ASSERT_TRUE(fs::exists(out)) << r.err;
  const mode_t mask = ::umask(0);
  ::umask(mask);
  EXPECT_EQ(static_cast<unsigned>(fs::status(out).permissions() & fs::perms::all), 0666u & ~mask);
}

TEST_F(Cli, InterruptedRunKeepsItsRows) {
  // 1e8 steps take seconds; SIGTERM after 0.3 s stops the run at its next check (every 1024 steps).
  const fs::path file =
      write("long.json", std::string(SceneText{.integrator = R"("integrator": {"method": "rkmk4", "dt": 1e-6})",
                                               .rest = R"("t_end": 100)"}));
  const fs::path out = dir_ / "long.csv";
  const fs::path err = dir_ / "stderr.txt";
  const std::string cmd = std::string(LGI_EXE) + " run -q " + file.string() + " -o " + out.string() + " 2> " +
                          err.string() + " & pid=$!; sleep 0.3; kill -TERM $pid; wait $pid";
  const int raw = std::system(cmd.c_str());
  const Result r{WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, "", slurp(err)};
  EXPECT_EQ(r.status, 128 + 15);
  EXPECT_NE(r.err.find("interrupted by SIGTERM at t = "), std::string::npos) << r.err;
  const Csv csv = parse_csv(slurp(out));  // t = 0 and the state where the run stopped
  ASSERT_EQ(csv.rows.size(), 2u);
  EXPECT_GT(csv.rows[1][0], 0.0);
  EXPECT_LT(csv.rows[1][0], 100.0);
  for (const auto& entry : fs::directory_iterator(dir_))
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
}

TEST_F(Cli, HelpListAndUsage) {
  EXPECT_EQ(lgi("--help").status, 0);
  const Result list = lgi("list");
  EXPECT_EQ(list.status, 0);
  for (const char* name : {"free_body", "heavy_top", "lgvi", "rkmk4", "lie_euler"})
    EXPECT_NE(list.out.find(name), std::string::npos) << name;
  EXPECT_EQ(lgi("frobnicate").status, 1);
  EXPECT_EQ(lgi("run").status, 1);  // SCENE is required
}

// The example scenes shipped in scenes/ all run.
TEST_F(Cli, ExampleScenesRun) {
  for (const auto& entry : fs::directory_iterator(LGI_SCENES_DIR)) {
    if (entry.path().extension() != ".json") continue;
    SCOPED_TRACE(entry.path().string());
    const Result r = lgi("run " + entry.path().string() + " -o " + (dir_ / "example.csv").string());
    EXPECT_EQ(r.status, 0) << r.err;
    // Every column of every row is a finite number, and so is every figure of the summary.
    std::istringstream csv(slurp(dir_ / "example.csv"));
    std::string line;
    std::getline(csv, line);  // header
    int rows = 0;
    while (std::getline(csv, line)) {
      ++rows;
      std::istringstream fields(line);
      std::string field;
      while (std::getline(fields, field, ',')) {
        char* end = nullptr;
        const double v = std::strtod(field.c_str(), &end);
        ASSERT_TRUE(end != field.c_str() && *end == '\0' && std::isfinite(v)) << "row " << rows << ": " << field;
      }
    }
    EXPECT_GE(rows, 2);
    for (const char* bad : {"nan", "inf"}) EXPECT_EQ(r.err.find(bad), std::string::npos) << r.err;
  }
}

// rigid_body with damping (scenes/damped_top.json): the energy falls between every two output rows, the summary calls
// its change a change (not an error), and R stays on SO(3).
TEST_F(Cli, DampedTopLosesEnergyAtEveryRow) {
  const Result r = lgi("run " + std::string(LGI_SCENES_DIR) + "/damped_top.json");
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv csv = parse_csv(r.out);
  ASSERT_EQ(csv.rows.size(), 8u);
  const std::size_t E = csv.column("energy"), orth = csv.column("orthogonality_error");
  for (std::size_t i = 1; i < csv.rows.size(); ++i) {
    EXPECT_LT(csv.rows[i][E], csv.rows[i - 1][E]) << "row " << i;
    EXPECT_LT(csv.rows[i][orth], 1e-12) << "row " << i;
  }
  std::printf("damped_top: energy %.6f at t = 0, %.6f at t = 100\n", csv.rows.front()[E], csv.rows.back()[E]);
  EXPECT_NE(r.err.find("energy change"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("energy error"), std::string::npos) << r.err;
}

// rigid_body with the PD attitude law (scenes/attitude_slew.json): the attitude reaches the target and the rotation
// stops. Linearised about the target, each principal axis obeys I ë + k_Omega ė + k_R e = 0; with k_R = 4,
// k_Omega = 12 and moments between 7.9 and 12.1 every mode decays at a rate ≥ 0.49, so after 60 time units the
// error is below 1.6 e^-29 ≈ 4e-13 (rad); the bounds below leave room for the nonlinear transient.
TEST_F(Cli, AttitudeSlewReachesItsTarget) {
  const Result r = lgi("run " + std::string(LGI_SCENES_DIR) + "/attitude_slew.json");
  ASSERT_EQ(r.status, 0) << r.err;
  const Csv csv = parse_csv(r.out);
  ASSERT_FALSE(csv.rows.empty());
  const std::vector<double>& last = csv.rows.back();
  lgi::Mat3<double> R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      R(i, j) = last[csv.column("R" + std::to_string(i + 1) + std::to_string(j + 1))];
  const lgi::Mat3<double> target =
      lgi::rotation_from_axis_angle(lgi::Vec3<double>(1, 1, 0), std::numbers::pi / 2);
  const double angle = lgi::so3::log(lgi::Mat3<double>(target.transpose() * R)).norm();
  const double rate = std::hypot(last[csv.column("omega1")], last[csv.column("omega2")], last[csv.column("omega3")]);
  std::printf("attitude_slew: at t = %g the attitude is %.2e rad from the target, |Omega| = %.2e\n",
              last[csv.column("t")], angle, rate);
  EXPECT_LT(angle, 1e-7);
  EXPECT_LT(rate, 1e-7);
}

}  // namespace

// `lgi view` (apps/view.hpp): what is not the CSV of a run gets one line naming the file and what is missing, exit
// 1, and nothing is written.
TEST_F(Cli, ViewRefusesWhatIsNotARunWithOneLineAndWritesNothing) {
  const std::string R = "R11,R12,R13,R21,R22,R23,R31,R32,R33";
  const std::string I = "1,0,0,0,1,0,0,0,1";
  const struct {
    std::string name, bytes, message;
  } cases[] = {
      {"not_a_run.csv", "a,b\n1,2\n", "not_a_run.csv: no column t: lgi view needs the CSV of lgi run"},
      {"no_attitude.csv", "t,omega1,omega2,omega3\n0,1,2,3\n", "no_attitude.csv: no column R11 or q_w"},
      {"half_R.csv", "t,R11,R12\n0,1,0\n", "half_R.csv: no column R13 (R11 is there)"},
      {"half_q.csv", "t,q_w,q_x\n0,1,0\n", "half_q.csv: no column q_y (q_w is there)"},
      {"backwards.csv", "t," + R + "\n0," + I + "\n1," + I + "\n0.5," + I + "\n",
       "backwards.csv:4: t = 0.5 is before the previous row's t = 1: not the rows of one run"},
      {"text.csv", "Dear diary, today the top fell over.\n", "text.csv: no column t"},
      {"empty.csv", "", "empty.csv: empty CSV of a run (no header row)"},
      {"header_only.csv", "t," + R + "\n", "header_only.csv: no data rows after the header"},
      {"bad_number.csv", "t," + R + "\n0,1,abc,0,0,1,0,0,0,1\n", "bad_number.csv:2: column R12: not a finite number: \"abc\""},
      {"short_row.csv", "t," + R + "\n0,1,0\n", "short_row.csv:2: row has 3 values, the header 10"},
      {"nul.csv", std::string("t,q_w,q_x,q_y,q_z\n0,1,0,0,") + '\0' + "\n", "nul.csv:2: a NUL byte"},
      {"zero_q.csv", "t,q_w,q_x,q_y,q_z\n0,0,0,0,0\n", "zero_q.csv:2: the quaternion has length 0, not 1"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path csv = write(c.name, c.bytes);
    std::vector<fs::path> before;
    for (const auto& e : fs::directory_iterator(dir_)) before.push_back(e.path());
    const Result r = lgi("view " + csv.string());
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(r.out.empty());
    std::vector<fs::path> after;
    for (const auto& e : fs::directory_iterator(dir_)) after.push_back(e.path());
    std::sort(before.begin(), before.end());
    std::sort(after.begin(), after.end());
    EXPECT_EQ(after, before) << "lgi view wrote a file";
  }
  const Result missing = lgi("view " + (dir_ / "no_such.csv").string());
  EXPECT_EQ(missing.status, 1);
  EXPECT_NE(missing.err.find("no_such.csv: cannot read the run"), std::string::npos) << missing.err;
}

TEST_F(Cli, ViewWritesOnePageAndReplacesOnlyItsOwnOrWhatItIsToldTo) {
  SceneText s;
  s.rest = R"("t_end": 1.0, "output": {"every": 1})";
  const fs::path scene = write("top.json", std::string(s));
  const fs::path csv = dir_ / "run.csv", page = dir_ / "run.html";
  ASSERT_EQ(lgi("run -q " + scene.string() + " -o " + csv.string()).status, 0);
  const std::string rows = slurp(csv);

  // The default page: RUN with .html; the summary line; the marker; decimated to --max-frames with t_end kept.
  const Result first = lgi("view " + csv.string() + " --scene " + scene.string() + " --max-frames 10");
  if (first.err.find("built without three.js") != std::string::npos) GTEST_SKIP() << first.err;
  ASSERT_EQ(first.status, 0) << first.err;
  EXPECT_NE(first.err.find("run.html: 1001 rows shown as 10 frames, t = 0 ... 1,"), std::string::npos) << first.err;
  const std::string html = slurp(page);
  EXPECT_NE(html.find("<meta name=\"generator\" content=\"lgi view\">"), std::string::npos);
  EXPECT_NE(html.find("\"frames\":10,"), std::string::npos);
  EXPECT_NE(html.find("\"t_end\":1.0,"), std::string::npos);
  EXPECT_NE(html.find("\"problem\":\"heavy_top\""), std::string::npos);
  std::size_t opened = 0, closed = 0;
  for (std::size_t at = 0; (at = html.find("<script", at)) != std::string::npos; ++at) ++opened;
  for (std::size_t at = 0; (at = html.find("</script", at)) != std::string::npos; ++at) ++closed;
  EXPECT_EQ(opened, 5u);
  EXPECT_EQ(closed, 5u) << "an inlined script has an early </script";
  // Its own page is replaced by the next view.
  ASSERT_EQ(lgi("view -q " + csv.string()).status, 0);
  EXPECT_NE(slurp(page).find("\"known\":false"), std::string::npos);

  // A file lgi did not write at the default name stays; -o replaces what it names, never the run or the scene.
  const fs::path other_csv = dir_ / "other.csv", other_page = dir_ / "other.html";
  fs::copy_file(csv, other_csv);
  std::ofstream(other_page) << "my notes\n";
  const Result refused = lgi("view " + other_csv.string());
  EXPECT_EQ(refused.status, 1);
  EXPECT_NE(refused.err.find("other.html exists and is not a page of lgi view: lgi does not replace it (give -o "),
            std::string::npos) << refused.err;
  EXPECT_EQ(slurp(other_page), "my notes\n");
  EXPECT_EQ(lgi("view -q " + other_csv.string() + " -o " + other_page.string()).status, 0);
  EXPECT_NE(slurp(other_page).find("lgi view"), std::string::npos);
  for (const fs::path& input : {csv, scene}) {
    const Result self = lgi("view " + csv.string() + " --scene " + scene.string() + " -o " + input.string());
    EXPECT_EQ(self.status, 1);
    EXPECT_NE(self.err.find("lgi does not replace its input"), std::string::npos) << self.err;
  }
  EXPECT_EQ(slurp(csv), rows);
  EXPECT_EQ(lgi("view " + csv.string() + " --axis 4").status, 1);
  EXPECT_EQ(lgi("view " + csv.string() + " --max-frames 1").status, 1);

  // lgi run --html: the page of the rows written to -o, which it needs.
  const fs::path run_page = dir_ / "direct.html";
  const Result direct = lgi("run -q " + scene.string() + " -o " + (dir_ / "direct.csv").string() + " --html " +
                            run_page.string());
  ASSERT_EQ(direct.status, 0) << direct.err;
  EXPECT_NE(slurp(run_page).find("\"frames\":1001,"), std::string::npos);
  const Result no_output = lgi("run -q " + scene.string() + " --html " + run_page.string());
  EXPECT_EQ(no_output.status, 1);
  EXPECT_NE(no_output.err.find("--html needs -o FILE"), std::string::npos) << no_output.err;
  EXPECT_TRUE(no_output.out.empty());
  const Result same = lgi("run -q " + scene.string() + " -o " + csv.string() + " --html " + csv.string());
  EXPECT_EQ(same.status, 1);
  EXPECT_EQ(slurp(csv), rows);
}
