// Scene loading in process: what a valid scene means, and that the runner adds nothing to the library's
// own integration (same bits as calling the driver directly).
#include "run_rows.hpp"
#include "test_problems.hpp"

#include <json_reader.hpp>
#include <runner.hpp>
#include <scene.hpp>

#include <lgi/core/driver.hpp>
#include <lgi/integrators/lgvi.hpp>

#include <gtest/gtest.h>

#include <cstdio>
#include <span>
#include <string>
#include <vector>

namespace lgi::app {
namespace {

Scene parse(const std::string& text) { return parse_scene(parse_json(text, "test.json"), "test.json"); }

const char* kScene = R"({
  "problem": {"type": "heavy_top", "inertia": [0.6, 0.8, 1.0], "b": 1},
  "initial": {"omega": [3, 0.5, -0.9]},
  "integrator": {"method": "lgvi", "dt": 0.01},
  "t_end": 2.5,
  "output": {"times": [1, 2.345]}
})";

TEST(Scene, DiagonalShorthandAndDefaults) {
  const Scene s = parse(kScene);
  const auto& top = *problem_as<HeavyTop<double>>(*s.problem);
  EXPECT_EQ(top.inertia, Mat3<double>(Vec3<double>(0.6, 0.8, 1.0).asDiagonal()));
  EXPECT_EQ(top.k, Vec3<double>::UnitZ());
  EXPECT_EQ(top.z0, Vec3<double>::UnitZ());
  EXPECT_EQ(s.initial.R, Mat3<double>::Identity());
  EXPECT_EQ(s.method->traits.name, "lgvi");
  EXPECT_EQ(s.options.max_iterations, StepperOptions{}.max_iterations);
  EXPECT_EQ(s.output_times, (std::vector<double>{1, 2.345}));
}

TEST(Scene, NearlyOrthogonalInitialRIsProjectedOntoSO3) {
  // An attitude printed with 10 digits: within 1e-9 of a rotation, accepted and made exact.
  const Mat3<double> R = so3::exp(Vec3<double>(0.3, -0.2, 1.1));
  char text[1024];
  std::snprintf(text, sizeof text, R"({
    "problem": {"type": "free_body", "inertia": [[1, 0.1, 0], [0.1, 2, 0], [0, 0, 2.5]]},
    "initial": {"R": [[%.10f, %.10f, %.10f], [%.10f, %.10f, %.10f], [%.10f, %.10f, %.10f]], "omega": [1, 2, 3]},
    "integrator": {"method": "rkmk4", "dt": 0.1}, "t_end": 1})",
                R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2));
  const Scene s = parse(text);
  EXPECT_GT(so3::orthogonality_error(Mat3<double>(R.unaryExpr([](double x) { return std::round(x * 1e10) / 1e10; }))),
            1e-12);
  EXPECT_LT(so3::orthogonality_error(s.initial.R), 1e-15);
  EXPECT_LT((s.initial.R - R).norm(), 1e-9);
}

TEST(Scene, UnitVectorsAreNormalised) {
  const Scene s = parse(R"({"problem": {"type": "heavy_top", "inertia": [1, 1, 1], "b": 2, "k": [0, 0.6, 0.8000000001],
    "z0": [1, 0, 0]}, "initial": {"omega": [0, 0, 1]}, "integrator": {"method": "lgvi", "dt": 0.1}, "t_end": 1})");
  const auto& top = *problem_as<HeavyTop<double>>(*s.problem);
  EXPECT_NEAR(top.k.norm(), 1.0, 1e-16);
  EXPECT_EQ(top.b, 2.0);
}

// The runner's final state is the driver's, bit for bit: the scene layer adds no arithmetic.
TEST(Scene, RunnerMatchesTheLibraryBitForBit) {
  const Scene s = parse(kScene);
  const RunReport report = run_scene(s, RunOptions{});
  ASSERT_EQ(report.summary.status, RunStatus::completed);
  EXPECT_EQ(report.summary.t, 2.5);

  const auto& top = *problem_as<HeavyTop<double>>(*s.problem);
  Lgvi<HeavyTop<double>> stepper(top);
  State<double> x = s.initial;
  const double times[] = {1, 2.345, 2.5};
  integrate_times(stepper, x, 0.0, 0.01, std::span<const double>(times));
  EXPECT_EQ(report.final_state.R, x.R);
  EXPECT_EQ(report.final_state.Omega, x.Omega);
  EXPECT_EQ(report.summary.steps, 250 + 1);  // 250 grid steps and the side-step to 2.345
  EXPECT_GT(report.newton_iterations, 0);
}

struct Rows final : RowSink {
  std::vector<std::vector<double>> rows;
  void row(std::span<const double> columns) override { rows.emplace_back(columns.begin(), columns.end()); }
};

// A RowSink gets the numbers the CSV prints, row for row: a complete run, the scene's own columns, and a run stopped by
// its budget (its last good state as the last row).
TEST(Scene, ARowSinkGetsTheNumbersTheCsvHolds) {
  const std::string path = ::testing::TempDir() + "lgi_row_sink.csv";
  const std::string columns = R"({"problem": {"type": "free_body", "inertia": [1, 2, 3]}, "initial": {"omega": [1, 0.1, 0.2]},
    "integrator": {"method": "rkmk4", "dt": 0.01}, "t_end": 1, "output": {"interval": 0.1,
    "columns": ["t", "quaternion", "euler_zyx_deg", "invariants"]}})";
  const std::string stops = R"({"problem": {"type": "heavy_top", "inertia": [2, 2, 1], "b": 1},
    "initial": {"omega": [0.1, 0.2, 5]}, "integrator": {"method": "lgvi", "dt": 0.01}, "t_end": 3,
    "output": {"interval": 0.3}, "limits": {"max_steps": 50}})";
  for (const std::string& text : {std::string(kScene), columns, stops}) {
    const Scene s = parse(text);
    const std::vector<std::vector<double>> written = test::run_csv_rows(s, path);
    Rows sink;
    RunOptions options;
    options.rows = &sink;
    const RunReport report = run_scene(s, options);
    ASSERT_GE(written.size(), 2u) << text;
    EXPECT_EQ(sink.rows, written) << text;
    EXPECT_TRUE(report.has_rows);
    EXPECT_EQ(report.final_row, text == stops);  // the stopped run's last good state, at t = 0.5
    EXPECT_EQ(report.summary.status == RunStatus::completed, text != stops);
  }
}

TEST(JsonReader, DuplicateKeyPathInsideArrays) {
  try {
    parse_json(R"({"a": [1, {"b": 1}, {"c": 2, "c": 3}]})", "f.json");
    FAIL() << "duplicate key accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "f.json: /a/2: duplicate key \"c\"");
  }
}

TEST(JsonReader, PointerTokensAreEscaped) {
  try {
    const json j = parse_json(R"({"a/b": {"c~d": "x"}})", "f.json");
    Node(j, "", "f.json").at("a/b").at("c~d").number();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "f.json: /a~1b/c~0d: expected a number, got a string (\"x\")");
  }
}

// "Did you mean": a name in other case, one edit (insertion, deletion, substitution), two neighbours swapped, or
// two edits of a longer name → the intended name; a name too far from all, or a one-letter one → nothing.
TEST(JsonReader, MisspeltNamesSuggestTheClosest) {
  const std::vector<std::string_view> methods = {"lgvi", "rkmk4", "rkmk_dp5", "rkmk_dp5_cayley", "split_dmv",
                                                 "split_dmv4", "lagrange_split"};
  const std::vector<std::string_view> keys = {"method", "dt", "tolerance", "max_iterations", "c", "axis", "tensor"};
  const struct {
    const char* given;
    const std::vector<std::string_view>* names;
    const char* expected;
  } cases[] = {
      {"LGVI", &methods, "lgvi"},                       // case
      {"Rkmk_DP5", &methods, "rkmk_dp5"},               // case
      {"lgvl", &methods, "lgvi"},                       // substitution
      {"rkmk_dp5_caley", &methods, "rkmk_dp5_cayley"},  // deletion
      {"rkmk44", &methods, "rkmk4"},                    // insertion
      {"lgiv", &methods, "lgvi"},                       // transposition
      {"splt_dmv_4", &methods, "split_dmv4"},           // two edits of a longer name
      {"split_dvm", &methods, "split_dmv"},             // transposition, the nearer of two
      {"lagrangesplit", &methods, "lagrange_split"},
      {"dT", &keys, "dt"},
      {"tolerence", &keys, "tolerance"},
      {"max_iteration", &keys, "max_iterations"},
      {"rk45", &methods, ""},  // two edits of a short name: too far
      {"q", &keys, ""},        // one letter: any other letter would do
      {"gauss_legendre", &methods, ""},
      {"", &keys, ""},
  };
  for (const auto& c : cases)
    EXPECT_EQ(app::closest_name(c.given, *c.names), c.expected) << "given \"" << c.given << "\"";
  EXPECT_EQ(app::did_you_mean("LGVI", methods), "; did you mean \"lgvi\"?");
  EXPECT_EQ(app::did_you_mean("rk45", methods), "");
}

TEST(JsonReader, NumbersPrintShortestExact) {
  EXPECT_EQ(format_number(0.1), "0.1");
  EXPECT_EQ(format_number(1.0 / 3), "0.3333333333333333");
  EXPECT_EQ(format_number(1e300), "1e+300");
}

}  // namespace
}  // namespace lgi::app
