// `lgi run` when a run does not complete, and checkpoints, run as a separate process:
//   - failures (Newton, non-finite, adaptive step-size underflow) and budgets (scene "limits") end with their exit
//     status, the rows so far plus a last row with the last good state in -o FILE, no NaN, where and why on stderr;
//   - a run stopped by a budget, SIGTERM, or SIGKILL after a checkpoint, resumed from its checkpoint, writes the
//     very bytes of the uninterrupted run (LGVI, RKMK4, adaptive DP5, splitting, composition, projection, the
//     Euler-angle path);
//   - `lgi run` (the engine, apps/session.cpp) steps exactly as the library's (core/driver.hpp,
//     integrators/adaptive.hpp): the rows' R and Ω equal the library's states bit for bit;
//   - the same scene gives the same bytes on every run, with or without checkpoints.
#include <lgi/core/driver.hpp>
#include <lgi/integrators/adaptive.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/problems/heavy_top.hpp>

#include "lgi_process.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fs = std::filesystem;

namespace {

using lgi::test::slurp;

struct Result {
  int status;  // exit status, or 128 + signal
  std::string err;
};

class Checkpoints : public lgi::test::CommandTest {
 protected:
  Checkpoints() : CommandTest("ck") {}

  // Starts `lgi ARGS` with stdout to /dev/null (or `out`) and stderr to dir_/stderr.txt.
  pid_t spawn(const std::vector<std::string>& args, const std::string& out = "/dev/null") {
    const std::string err = (dir_ / "stderr.txt").string();
    const pid_t pid = ::fork();
    if (pid == 0) {
      const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int e = ::open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      ::dup2(o, 1);
      ::dup2(e, 2);
      std::vector<char*> argv;
      std::string exe = LGI_EXE;
      argv.push_back(exe.data());
      std::vector<std::string> copy = args;
      for (auto& a : copy) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(LGI_EXE, argv.data());
      ::_exit(127);
    }
    return pid;
  }
  Result wait(pid_t pid) {
    int raw = 0;
    ::waitpid(pid, &raw, 0);
    return {WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw), slurp(dir_ / "stderr.txt")};
  }
  Result lgi(const std::vector<std::string>& args, const std::string& out = "/dev/null") { return wait(spawn(args, out)); }

  // Waits (up to 60 s) until `file` exists; false if the process ended first.
  bool wait_for(const fs::path& file, pid_t pid) {
    for (int i = 0; i < 12000; ++i) {
      if (fs::exists(file)) return true;
      int raw = 0;
      if (::waitpid(pid, &raw, WNOHANG) == pid) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return false;
  }

  // No temporary files left in dir_ (outputs and checkpoints).
  void expect_no_temporary_files() {
    for (const auto& entry : fs::directory_iterator(dir_))
      EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  }

};

// A heavy-top scene (the one of test_cli) with the given integrator, duration, output and extra top-level keys.
std::string scene(const std::string& integrator, const std::string& t_end, const std::string& output,
                  const std::string& extra = "") {
  return R"({"problem": {"type": "heavy_top", "inertia": [[2, 0, 0], [0, 2, 0], [0, 0, 1]], "b": 1.0},
  "initial": {"omega": [0.1, 0.2, 5.0]}, "integrator": )" +
         integrator + R"(, "t_end": )" + t_end + R"(, "output": )" + output + extra + "}\n";
}

std::string with_omega(std::string s, const std::string& omega) {
  return s.replace(s.find("[0.1, 0.2, 5.0]"), 15, omega);
}

// The CSV's rows as numbers (the header skipped); every field must be a finite number.
std::vector<std::vector<double>> rows_of(const std::string& csv) {
  std::vector<std::vector<double>> rows;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) {
      char* end = nullptr;
      const double v = std::strtod(field.c_str(), &end);
      EXPECT_TRUE(end != field.c_str() && *end == '\0' && std::isfinite(v)) << "row " << rows.size() << ": " << field;
      row.push_back(v);
    }
    rows.push_back(row);
  }
  return rows;
}

// ---- failures and budgets ----------------------------------------------------------------------------------

// h|Ω| = 1.5 about the symmetry axis: the LGVI's implicit equation has no solution from the first step.
TEST_F(Checkpoints, NewtonFailureKeepsTheRowsAndTheLastGoodState) {
  const fs::path f2 = write("fail.json", with_omega(scene(R"({"method": "lgvi", "dt": 0.01})", "1", R"({"every": 1})"),
                                                    "[0, 0, 150]"));
  const fs::path out = dir_ / "fail.csv";
  const Result r = lgi({"run", f2.string(), "-o", out.string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("the step from t = 0 failed: Newton iteration did not converge (step 1 of the run"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find(out.string() + " holds the rows to t = 0"), std::string::npos) << r.err;
  const auto rows = rows_of(slurp(out));
  ASSERT_EQ(rows.size(), 1u);  // t = 0: the last good state is the initial one, written once
  EXPECT_EQ(rows[0][12], 150.0);
  expect_no_temporary_files();
}

// RKMK4 at h|Ω| = 4 on the free body is unstable: |Ω| grows until a step overflows. Every row before is kept,
// the last row is the last finite state, its time the one stderr names, and no field is NaN or infinite.
TEST_F(Checkpoints, NonFiniteStateMidRunKeepsEveryRowBefore) {
  const fs::path file = write(
      "blowup.json",
      R"({"problem": {"type": "free_body", "inertia": [1, 2, 3]}, "initial": {"omega": [1, 40, 1]},
          "integrator": {"method": "rkmk4", "dt": 0.1}, "t_end": 1000, "output": {"every": 1}})");
  const fs::path out = dir_ / "blowup.csv";
  const Result r = lgi({"run", file.string(), "-o", out.string()});
  EXPECT_EQ(r.status, 2) << r.err;
  const auto pos = r.err.find("the step from t = ");
  ASSERT_NE(pos, std::string::npos) << r.err;
  EXPECT_NE(r.err.find("failed: non-finite state"), std::string::npos) << r.err;
  const double t_fail = std::strtod(r.err.c_str() + pos + 18, nullptr);
  const auto rows = rows_of(slurp(out));  // all finite (checked by rows_of)
  ASSERT_GE(rows.size(), 3u);
  EXPECT_GT(t_fail, 0.0);
  EXPECT_EQ(rows.back()[0], t_fail);
  for (std::size_t i = 0; i < rows.size(); ++i) EXPECT_DOUBLE_EQ(rows[i][0], 0.1 * static_cast<double>(i)) << i;
  EXPECT_GT(std::abs(rows.back()[11]), 1e10);  // it did blow up
}

// Adaptive DP5 from a state whose every trial overflows: each non-finite trial divides h by 10
// (integrators/adaptive.hpp) until h < 16 ε max(|t|, t_end), then the run ends with the step's status.
TEST_F(Checkpoints, AdaptiveRetriesSmallerStepsThenGivesUp) {
  const fs::path huge = write("huge.json", with_omega(scene(R"({"method": "rkmk_dp5", "dt": 0.01, "rtol": 1e-8,
                                                                  "atol": 1e-8})", "1", R"({"every": 1})"),
                                                    "[1e150, 1e150, 1e150]"));
  const fs::path out = dir_ / "huge.csv";
  const Result r = lgi({"run", huge.string(), "-o", out.string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("the step from t = 0 failed: non-finite state"), std::string::npos) << r.err;
  // The retries the documented rule allows: h = 0.01, 0.001, … while h ≥ 16 ε · t_end.
  int expected = 0;
  for (double h = 0.01; h >= 16 * std::numeric_limits<double>::epsilon() * 1.0; h *= 0.1) ++expected;
  std::string rejected = "(";
  rejected += std::to_string(expected);
  rejected += " trial steps rejected)";
  EXPECT_NE(r.err.find(rejected), std::string::npos) << r.err;
  EXPECT_EQ(rows_of(slurp(out)).size(), 1u);
}

TEST_F(Checkpoints, StepBudgetStopsExactlyAndKeepsTheLastState) {
  const fs::path file = write("budget.json", scene(R"({"method": "rkmk4", "dt": 0.01})", "100", R"({"every": 100})",
                                                   R"(, "limits": {"max_steps": 1234})"));
  const fs::path out = dir_ / "budget.csv";
  const Result r = lgi({"run", file.string(), "-o", out.string()});
  EXPECT_EQ(r.status, 6);
  EXPECT_NE(r.err.find("stopped by /limits/max_steps = 1234 at t = 12.34 after 1234 steps"), std::string::npos) << r.err;
  const auto rows = rows_of(slurp(out));
  ASSERT_EQ(rows.size(), 14u);  // t = 0, 1, …, 12, and the last state at 12.34
  EXPECT_EQ(rows.back()[0], 1234 * 0.01);
  EXPECT_DOUBLE_EQ(rows[12][0], 12.0);
}

TEST_F(Checkpoints, WallClockBudget) {
  const fs::path file = write("wall.json", scene(R"({"method": "rkmk4", "dt": 1e-6})", "1000", R"({"every": 100000})",
                                                 R"(, "limits": {"max_wall_seconds": 0.3})"));
  const fs::path out = dir_ / "wall.csv";
  const auto start = std::chrono::steady_clock::now();
  const Result r = lgi({"run", file.string(), "-o", out.string()});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(r.status, 6);
  EXPECT_NE(r.err.find("stopped by /limits/max_wall_seconds = 0.3 at t = "), std::string::npos) << r.err;
  EXPECT_LT(seconds, 30.0);  // 1e9 steps would take minutes: the budget stopped it
  const auto rows = rows_of(slurp(out));
  ASSERT_GE(rows.size(), 2u);
  EXPECT_GT(rows.back()[0], 0.0);
  EXPECT_LT(rows.back()[0], 1000.0);
}

TEST_F(Checkpoints, SigtermWithoutCheckpointKeepsTheRows) {
  const fs::path file = write("long.json", scene(R"({"method": "rkmk4", "dt": 1e-6})", "100", R"({"every": 10000})"));
  const fs::path out = dir_ / "long.csv";
  const pid_t pid = spawn({"run", "-q", file.string(), "-o", out.string()});
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  ::kill(pid, SIGTERM);
  const Result r = wait(pid);
  EXPECT_EQ(r.status, 128 + SIGTERM);
  EXPECT_NE(r.err.find("interrupted by SIGTERM at t = "), std::string::npos) << r.err;
  const auto rows = rows_of(slurp(out));
  ASSERT_GE(rows.size(), 2u);
  for (std::size_t i = 1; i + 1 < rows.size(); ++i) EXPECT_DOUBLE_EQ(rows[i][0], 0.01 * static_cast<double>(i));
  EXPECT_LT(rows.back()[0], 100.0);
  expect_no_temporary_files();
}

// Progress: under a pseudo-terminal (script(1)) a long run (10⁸ steps) shows the simulated time, its fraction, the
// rate and the time left; with stderr not a terminal nothing, unless --progress (whole lines). SIGINT's message says
// how to continue: --checkpoint without one (with one, --resume: ResumedRunsWriteTheSameBytes… above).
TEST_F(Checkpoints, ProgressOnATerminalAndHowToContinueAfterSigint) {
  const fs::path file = write("long.json", scene(R"({"method": "lgvi", "dt": 1e-6})", "100", R"({"every": 1000000})"));
  const std::string out = (dir_ / "long.csv").string();
  // A terminal, stopped after 2 s.
  ASSERT_EQ(lgi::test::lgi_on_a_terminal("run " + file.string() + " -o " + out, dir_ / "screen.txt", 2), 128 + SIGINT);
  const std::string shown = slurp(dir_ / "screen.txt");
  EXPECT_NE(shown.find("\r  t = "), std::string::npos) << shown;
  EXPECT_NE(shown.find(" of 100 ("), std::string::npos) << shown;
  EXPECT_NE(shown.find(" s elapsed, about "), std::string::npos) << shown;
  EXPECT_NE(shown.find(" left"), std::string::npos) << shown;
  // Not a terminal: no progress; the message says how to make a run that can continue.
  pid_t pid = spawn({"run", file.string(), "-o", out});
  std::this_thread::sleep_for(std::chrono::milliseconds(2000));
  ::kill(pid, SIGINT);
  Result r = wait(pid);
  EXPECT_EQ(r.status, 128 + SIGINT);
  EXPECT_EQ(r.err.find("steps/s"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("interrupted by SIGINT at t = "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("; to be able to continue a stopped run, give it --checkpoint CK (with -o FILE): lgi run "
                       "--resume CK then goes on"),
            std::string::npos)
      << r.err;
  // --progress: lines, for logs.
  pid = spawn({"run", file.string(), "-o", out, "--progress"});
  std::this_thread::sleep_for(std::chrono::milliseconds(2000));
  ::kill(pid, SIGINT);
  r = wait(pid);
  EXPECT_EQ(r.status, 128 + SIGINT);
  EXPECT_EQ(r.err.rfind("lgi: progress: t = ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(" s elapsed, about "), std::string::npos) << r.err;
  expect_no_temporary_files();
}

TEST_F(Checkpoints, LimitsAreValidated) {
  const struct {
    const char* limits;
    const char* path;
    const char* message;
  } bad[] = {
      {R"({"max_steps": 0})", "/limits/max_steps", "expected an integer from 1 to"},
      {R"({"max_steps": 2.5})", "/limits/max_steps", "expected an integer"},
      {R"({"max_steps": "10"})", "/limits/max_steps", "expected a number"},
      {R"({"max_wall_seconds": -1})", "/limits/max_wall_seconds", "must be > 0"},
      {R"({"max_wall_seconds": 1e999})", "/limits/max_wall_seconds", "out of the range of a double"},
      {R"({"max_time": 1})", "/limits/max_time", "unknown key"},
      {R"([1000])", "/limits", "expected an object"},
  };
  for (const auto& b : bad) {
    SCOPED_TRACE(b.limits);
    const fs::path file =
        write("bad.json", scene(R"({"method": "lgvi", "dt": 0.1})", "1", "{}", std::string(R"(, "limits": )") + b.limits));
    const fs::path out = dir_ / "bad.csv";
    const Result r = lgi({"run", file.string(), "-o", out.string()});
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find(file.string() + ": " + b.path + ": "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(b.message), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
  }
}

TEST_F(Checkpoints, CommandLineIsValidated) {
  const fs::path file = write("ok.json", scene(R"({"method": "lgvi", "dt": 0.1})", "1", "{}"));
  const std::string ck = (dir_ / "ck.json").string(), out = (dir_ / "out.csv").string();
  const struct {
    std::vector<std::string> args;
    const char* message;
  } bad[] = {
      {{"run", file.string(), "--checkpoint", ck}, "--checkpoint needs -o FILE"},
      {{"run", file.string(), "-o", out, "--checkpoint-every", "10"}, "--checkpoint-every needs --checkpoint"},
      {{"run", file.string(), "-o", out, "--checkpoint", ck, "--checkpoint-every", "ten"}, "expected a number of steps"},
      {{"run", file.string(), "-o", out, "--checkpoint", ck, "--checkpoint-every", "-5s"}, "expected a number of steps"},
      {{"run", file.string(), "--resume", ck}, "give a SCENE file, or --resume CHECKPOINT"},
      {{"run"}, "give a SCENE file, or --resume CHECKPOINT"},
      {{"run", "--resume", ck}, "ck.json: cannot read the file"},
  };
  for (const auto& b : bad) {
    SCOPED_TRACE(b.message);
    const Result r = lgi(b.args);
    EXPECT_EQ(r.status, 1);
    EXPECT_NE(r.err.find(b.message), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_FALSE(fs::exists(ck));
  }
}

// ---- determinism and the drivers ---------------------------------------------------------------------------

TEST_F(Checkpoints, SameSceneSameBytes) {
  const fs::path file = write("det.json", scene(R"({"method": "lgvi", "dt": 0.001})", "20", R"({"every": 97})"));
  const fs::path a = dir_ / "a.csv", b = dir_ / "b.csv", c = dir_ / "c.csv";
  ASSERT_EQ(lgi({"run", "-q", file.string(), "-o", a.string()}).status, 0);
  ASSERT_EQ(lgi({"run", "-q", file.string(), "-o", b.string()}).status, 0);
  // checkpoints every 1024 steps change nothing in the output (and are removed at the end)
  ASSERT_EQ(lgi({"run", "-q", file.string(), "-o", c.string(), "--checkpoint", (dir_ / "ck.json").string(),
                 "--checkpoint-every", "1"})
                .status,
            0);
  const std::string sa = slurp(a);
  EXPECT_GT(sa.size(), 50000u);
  EXPECT_EQ(sa, slurp(b));
  EXPECT_EQ(sa, slurp(c));
  EXPECT_FALSE(fs::exists(dir_ / "ck.json"));
  expect_no_temporary_files();
}

// lgi run's rows hold the library drivers' states bit for bit (17 significant digits read back exactly).
TEST_F(Checkpoints, RunnerStepsLikeTheLibraryDrivers) {
  lgi::HeavyTop<double> top;
  top.inertia = lgi::Vec3<double>(2, 2, 1).asDiagonal();
  top.b = 1;
  lgi::State<double> x0;
  x0.Omega = {0.1, 0.2, 5.0};
  struct Case {
    const char* name;
    std::string integrator, t_end, output;
    std::vector<lgi::State<double>> (*library)();
  };
  static lgi::HeavyTop<double> problem;
  static lgi::State<double> start;
  problem = top;
  start = x0;
  const std::vector<Case> cases = {
      {"lgvi, off-grid times", R"({"method": "lgvi", "dt": 0.003})", "1.0", R"({"times": [0.1234, 0.5, 0.77]})",
       [] {
         std::vector<lgi::State<double>> xs;
         lgi::Lgvi<lgi::HeavyTop<double>> s(problem);
         lgi::State<double> x = start;
         const double times[] = {0.1234, 0.5, 0.77, 1.0};
         lgi::integrate_times(s, x, 0.0, 0.003, std::span<const double>(times),
                              [&](double, const lgi::State<double>& y) { xs.push_back(y); });
         return xs;
       }},
      {"rkmk4, every 7, t_end off the grid", R"({"method": "rkmk4", "dt": 0.01})", "1.005", R"({"every": 7})",
       [] {
         std::vector<lgi::State<double>> xs;
         lgi::Rkmk4<lgi::HeavyTop<double>> s(problem);
         lgi::State<double> x = start;
         lgi::integrate_every(s, x, 0.0, 0.01, 1.005, 7, [&](double, const lgi::State<double>& y) { xs.push_back(y); });
         return xs;
       }},
      {"rkmk_dp5 adaptive, times", R"({"method": "rkmk_dp5", "dt": 0.01, "rtol": 1e-9, "atol": 1e-10})", "5.0",
       R"({"times": [0.3, 1.7, 2.0, 4.99]})",
       [] {
         std::vector<lgi::State<double>> xs;
         lgi::StepperOptions o;
         o.rtol = 1e-9;
         o.atol = 1e-10;
         lgi::RkmkDp5<lgi::HeavyTop<double>> s(problem, o);
         lgi::State<double> x = start;
         const double times[] = {0.3, 1.7, 2.0, 4.99, 5.0};
         lgi::integrate_adaptive(s, x, 0.0, 0.01, std::span<const double>(times),
                                 [&](double, const lgi::State<double>& y) { xs.push_back(y); });
         return xs;
       }},
      {"rkmk_dp5 adaptive, every 3", R"({"method": "rkmk_dp5", "dt": 0.01, "rtol": 1e-7, "atol": 1e-7})", "5.0",
       R"({"every": 3})",
       [] {
         std::vector<lgi::State<double>> xs;
         lgi::StepperOptions o;
         o.rtol = 1e-7;
         o.atol = 1e-7;
         lgi::RkmkDp5<lgi::HeavyTop<double>> s(problem, o);
         lgi::State<double> x = start;
         const double times[] = {5.0};
         lgi::AdaptiveOptions a;
         a.every = 3;
         lgi::integrate_adaptive(s, x, 0.0, 0.01, std::span<const double>(times),
                                 [&](double, const lgi::State<double>& y) { xs.push_back(y); }, a);
         return xs;
       }},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path file = write("lib.json", scene(c.integrator, c.t_end, c.output));
    const fs::path out = dir_ / "lib.csv";
    ASSERT_EQ(lgi({"run", "-q", file.string(), "-o", out.string()}).status, 0);
    const auto rows = rows_of(slurp(out));
    const auto states = c.library();
    ASSERT_EQ(rows.size(), states.size());
    ASSERT_GE(rows.size(), 4u);
    for (std::size_t i = 0; i < rows.size(); ++i) {
      for (int k = 0; k < 9; ++k) EXPECT_EQ(rows[i][1 + static_cast<std::size_t>(k)], states[i].R(k / 3, k % 3)) << i;
      for (int k = 0; k < 3; ++k) EXPECT_EQ(rows[i][10 + static_cast<std::size_t>(k)], states[i].Omega(k)) << i;
    }
  }
}

// ---- checkpoint and resume -----------------------------------------------------------------------------------

struct ResumeCase {
  const char* name;
  std::string scene;
  int max_steps = 1777;  // the budget of BudgetStopsChainOfResumesGivesTheSameBytes
};

// Scenes of 0.2–0.6 s (about 5e5–1e6 steps) for a SIGTERM or SIGKILL to land in after the first checkpoint at
// 50 000 steps (heavy top, output every 2000 steps).
std::vector<ResumeCase> long_cases() {
  return {
      {"lgvi", scene(R"({"method": "lgvi", "dt": 1e-4})", "80", R"({"every": 2000})")},
      {"rkmk4", scene(R"({"method": "rkmk4", "dt": 1e-4})", "100", R"({"every": 2000})")},
      {"rkmk_dp5_adaptive",
       scene(R"({"method": "rkmk_dp5", "dt": 1e-3, "rtol": 1e-13, "atol": 1e-13})", "3000", R"({"every": 2000})")},
      {"split_dmv4", scene(R"({"method": "split_dmv4", "dt": 1e-4})", "100", R"({"every": 2000})")},
      {"lgvi_yoshida4", scene(R"({"method": "lgvi_yoshida4", "dt": 1e-4})", "40", R"({"every": 2000})")},
  };
}

// SIGTERM once the first periodic checkpoint exists, then resume: the same bytes as the run left alone. And
// SIGKILL once a checkpoint exists (no chance to clean up), then resume: the same bytes again.
TEST_F(Checkpoints, KilledRunsResumeToTheSameBytes) {
  for (const ResumeCase& c : long_cases()) {
    for (const int signal : {SIGTERM, SIGKILL}) {
      SCOPED_TRACE(std::string(c.name) + (signal == SIGTERM ? " SIGTERM" : " SIGKILL"));
      const fs::path file = write(std::string(c.name) + ".json", c.scene);
      const fs::path whole = dir_ / (std::string(c.name) + ".whole.csv");
      if (signal == SIGTERM) {
        ASSERT_EQ(lgi({"run", "-q", file.string(), "-o", whole.string()}).status, 0);
      }
      const fs::path out = dir_ / "part.csv", ck = dir_ / "ck.json";
      const pid_t pid = spawn({"run", "-q", file.string(), "-o", out.string(), "--checkpoint", ck.string(),
                               "--checkpoint-every", "50000"});
      ASSERT_TRUE(wait_for(ck, pid)) << slurp(dir_ / "stderr.txt");
      ::kill(pid, signal);
      const Result r = wait(pid);
      ASSERT_EQ(r.status, 128 + signal) << r.err;
      if (signal == SIGTERM) {
        EXPECT_NE(r.err.find("; checkpoint " + ck.string() + " (continue: lgi run --resume " + ck.string()),
                  std::string::npos)
            << r.err;
        EXPECT_TRUE(fs::exists(out));  // the rows so far, renamed into place
      } else {
        EXPECT_FALSE(fs::exists(out));  // the rows are in the temporary file the checkpoint names
      }
      const Result resumed = lgi({"run", "-q", "--resume", ck.string()});
      ASSERT_EQ(resumed.status, 0) << resumed.err;
      EXPECT_TRUE(slurp(out) == slurp(whole)) << "the resumed output differs from the uninterrupted one";
      EXPECT_FALSE(fs::exists(ck));  // a complete run removes its checkpoint
      expect_no_temporary_files();
      fs::remove(out);
    }
  }
}

// A step budget stops a run again and again (a budget counts from each invocation); resuming each time writes
// the uninterrupted run's bytes. Deterministic: every stop falls on a known step, off the monitor's 1024-step
// grid and off the output rows.
// A SIGKILL inside a checkpoint write leaves that write's temporary file (".ck.json.tmp-XXXXXX"); the run that
// completes removes it with the checkpoint, and leaves other temporary files alone. (Written here by hand: the
// kill in KilledRunsResumeToTheSameBytes lands inside a write only now and then.)
TEST_F(Checkpoints, CompletedRunRemovesItsCheckpointsOrphans) {
  const fs::path file = write("short.json", scene(R"({"method": "lgvi", "dt": 1e-3})", "1", R"({"every": 100})"));
  const fs::path ck = dir_ / "ck.json", orphan = dir_ / ".ck.json.tmp-AbC123", other = dir_ / ".other.csv.tmp-AbC123";
  write(orphan.filename().string(), "{\n \"lgi_checkpoint\": 2,\n \"lgi_ver");  // a write cut short
  write(other.filename().string(), "not ours");
  const Result r = lgi({"run", "-q", file.string(), "-o", (dir_ / "out.csv").string(), "--checkpoint", ck.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(ck));
  EXPECT_FALSE(fs::exists(orphan));
  EXPECT_TRUE(fs::exists(other));
  fs::remove(other);
}

TEST_F(Checkpoints, BudgetStopsChainOfResumesGivesTheSameBytes) {
  const std::vector<ResumeCase> cases = {
      {"lgvi", scene(R"({"method": "lgvi", "dt": 0.01})", "70", R"({"times": [0.015, 3, 17.777, 33, 50.5]})")},
      {"rkmk4_projected", scene(R"({"method": "rkmk4", "dt": 0.01, "projection": true})", "70", R"({"every": 333})")},
      {"rkmk_dp5", scene(R"({"method": "rkmk_dp5", "dt": 0.01, "rtol": 1e-10, "atol": 1e-10})", "70",
                         R"({"times": [0.5, 17.25, 40, 69.99]})"),
       577},
      {"dop853_quat", scene(R"({"method": "dop853_quat", "dt": 0.01, "rtol": 1e-9, "atol": 1e-9})", "70",
                            R"({"every": 5})"),
       177},
      {"split_axes", scene(R"({"method": "split_axes", "dt": 0.01})", "70", R"({"every": 500})")},
      {"lgvi_suzuki4", scene(R"({"method": "lgvi_suzuki4", "dt": 0.01})", "70", R"({"every": 250})")},
      // Chosen columns with a quaternion, whose sign continues from the last row before each stop (the top spins at
      // 5 rad/s: its rotation angle passes π every 1.3 s, so w changes sign between most stops).
      {"quaternion_columns",
       scene(R"({"method": "lgvi", "dt": 0.01})", "70",
             R"({"every": 7, "columns": ["t", "quaternion", "euler_zyx_deg", "omega", "invariants"]})")},
      {"euler_angles",
       R"({"problem": {"type": "lagrange_top_euler_angles", "I2": 2, "I3": 1, "b": 1, "k2": 0.6, "k3": 0.8},
           "initial": {"euler_angles": [0.1, 1.0, 0.2], "euler_rates": [0.3, 0.1, 5.0]},
           "integrator": {"method": "rkmk4", "dt": 0.01}, "t_end": 70, "output": {"every": 250}})"},
      // A gyrostat: the rotors' momenta are part of the checkpointed state.
      {"gyrostat",
       R"({"problem": {"type": "gyrostat", "inertia": [3, 2, 1],
                       "rotors": [{"axis": [1, 0, 0], "inertia": 0.1, "friction": 0.2, "rate": 5},
                                  {"axis": [0, 0.6, 0.8], "inertia": 0.1, "motor_torque": 0.01}]},
           "initial": {"omega": [0.1, 0.2, 1]},
           "integrator": {"method": "lgvi_yoshida4", "dt": 0.01}, "t_end": 70, "output": {"every": 250}})"},
  };
  for (const ResumeCase& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path file = write("chain.json", c.scene);
    const fs::path whole = dir_ / "whole.csv", out = dir_ / "chain.csv", ck = dir_ / "ck.json";
    const Result w = lgi({"run", "-q", file.string(), "-o", whole.string()});
    ASSERT_EQ(w.status, 0) << w.err;
    std::string limited = c.scene;
    limited.insert(limited.rfind('}'), R"(, "limits": {"max_steps": )" + std::to_string(c.max_steps) + "}");
    const fs::path budget = write("budget.json", limited);
    Result r = lgi({"run", "-q", budget.string(), "-o", out.string(), "--checkpoint", ck.string()});
    int sessions = 1;
    while (r.status == 6 && sessions < 20) {
      ASSERT_TRUE(fs::exists(ck)) << r.err;
      r = lgi({"run", "-q", "--resume", ck.string()});
      ++sessions;
    }
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_GE(sessions, 3);
    EXPECT_TRUE(slurp(out) == slurp(whole)) << "after " << sessions << " sessions";
    EXPECT_FALSE(fs::exists(ck));
    expect_no_temporary_files();
  }
}

// A resume refuses rows that are not those its checkpoint counts (their size, and their first and last 4 KiB),
// and a checkpoint that was changed.
TEST_F(Checkpoints, ResumeRefusesChangedRowsAndCheckpoints) {
  const fs::path file = write("s.json", scene(R"({"method": "rkmk4", "dt": 0.01})", "150", R"({"every": 10})",
                                              R"(, "limits": {"max_steps": 5000})"));
  const fs::path out = dir_ / "out.csv", ck = dir_ / "ck.json";
  ASSERT_EQ(lgi({"run", "-q", file.string(), "-o", out.string(), "--checkpoint", ck.string()}).status, 6);
  const std::string rows = slurp(out), checkpoint = slurp(ck);
  // a changed row
  std::string changed = rows;
  const std::size_t i = changed.find('1', changed.size() - 1000);
  changed[i] = '2';
  write("out.csv", changed);
  Result r = lgi({"run", "--resume", ck.string()});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("the rows it continues are in neither"), std::string::npos) << r.err;
  // a truncated file
  write("out.csv", rows.substr(0, rows.size() / 3));
  r = lgi({"run", "--resume", ck.string()});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("the rows it continues are in neither"), std::string::npos) << r.err;
  // a changed scene inside the checkpoint
  write("out.csv", rows);
  std::string edited = checkpoint;
  edited.replace(edited.find("\"b\": 1.0"), 8, "\"b\": 1.5");
  write("ck.json", edited);
  r = lgi({"run", "--resume", ck.string()});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(ck.string() + ": /checksum: does not match the file's bytes"), std::string::npos) << r.err;
  // a state number that is not a hexadecimal float
  edited = checkpoint;
  const auto at = edited.find("\"0x", edited.find("\"internal\""));
  edited.replace(at + 1, 2, "zz");
  write("ck.json", edited);
  r = lgi({"run", "--resume", ck.string()});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find(ck.string() + ": /checksum: does not match the file's bytes"), std::string::npos) << r.err;
  // the original continues
  write("ck.json", checkpoint);
  EXPECT_EQ(lgi({"run", "--resume", ck.string()}).status, 6);
}

// A scene that reads a torque table: the checkpoint records the table's hash, and a resume after the table changed is
// refused with one line naming the file (it would continue a different motion); the unchanged table resumes to the
// same bytes as an uninterrupted run.
TEST_F(Checkpoints, ResumeRefusesAChangedTorqueTable) {
  std::string table = "t,M1,M2,M3\n";
  for (int i = 0; i <= 60; ++i) table += std::to_string(i) + "," + std::to_string(0.01 * (i % 7)) + ",0.02,-0.01\n";
  write("torque.csv", table);
  const std::string text = R"({"problem": {"type": "rigid_body", "inertia": [1, 2, 3],
      "torques": [{"type": "table", "file": "torque.csv", "frame": "lab", "interpolation": "cubic"}]},
    "initial": {"omega": [0.1, 0.2, 1]}, "integrator": {"method": "rkmk4", "dt": 0.01}, "t_end": 60,
    "output": {"every": 10})";
  const fs::path whole = write("whole.json", text + "}"), stopped = write("stopped.json", text + R"(, "limits": {"max_steps": 2500}})");
  ASSERT_EQ(lgi({"run", "-q", whole.string(), "-o", (dir_ / "whole.csv").string()}).status, 0);
  const fs::path out = dir_ / "out.csv", ck = dir_ / "ck.json";
  ASSERT_EQ(lgi({"run", "-q", stopped.string(), "-o", out.string(), "--checkpoint", ck.string()}).status, 6);
  EXPECT_NE(slurp(ck).find("\"inputs\""), std::string::npos);
  std::string changed = table;
  changed.replace(changed.find("0.02"), 4, "0.03");
  write("torque.csv", changed);
  const Result r = lgi({"run", "--resume", ck.string()});
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find((dir_ / "torque.csv").string() + ": changed since the checkpoint " + ck.string() + " was written"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  write("torque.csv", table);
  Result resumed = lgi({"run", "-q", "--resume", ck.string()});
  for (int sessions = 2; resumed.status == 6 && sessions < 5; ++sessions) resumed = lgi({"run", "-q", "--resume", ck.string()});
  ASSERT_EQ(resumed.status, 0) << resumed.err;
  EXPECT_TRUE(slurp(out) == slurp(dir_ / "whole.csv"));
}

}  // namespace
