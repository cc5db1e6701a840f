// `lgi fit`, run as a separate process on data that `lgi run` wrote: the command recovers Ω0 (the fitting
// issue's first acceptance case, through files), R0 with the moments, and a periodic orbit; a fit whose
// Jacobian is rank deficient exits 5 with the result written and "usable": false; bad fit files get one
// message naming the file and the JSON path (or CSV line), exit 1, and no output file.
#include "figures.hpp"
#include "lgi_process.hpp"
#include "test_problems.hpp"

#include <lgi/problems/free_body.hpp>
#include <lgi/problems/free_body_exact.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

using Result = lgi::test::CommandResult;
using lgi::test::slurp;

std::string num(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}
// Built with += : g++ 12 at -O3 warns (-Wrestrict, a known false positive, GCC PR 105329) on "[" + std::string.
std::string vec(const lgi::Vec3<double>& v) {
  std::string s("[");
  s += num(v(0));
  s += ", ";
  s += num(v(1));
  s += ", ";
  s += num(v(2));
  s += "]";
  return s;
}
std::string mat(const lgi::Mat3<double>& m) {
  std::string s("[");
  for (int i = 0; i < 3; ++i) {
    s += vec(m.row(i).transpose());
    s += i < 2 ? ", " : "]";
  }
  return s;
}

class CliFit : public lgi::test::CommandTest {
 protected:
  CliFit() : CommandTest("cli_fit") {}
};

// The skew heavy top of the fitting tests (non-diagonal inertia, tilted k and z0) as scene text.
std::string skew_top_problem() {
  const lgi::HeavyTop<double> p = lgi::test::skew_heavy_top();
  return R"("problem": {"type": "heavy_top", "inertia": )" + mat(p.inertia) + R"(, "b": )" + num(p.b) +
         R"(, "k": )" + vec(p.k) + R"(, "z0": )" + vec(p.z0) + "}";
}

// A scene whose output every `every` steps serves as observations.
std::string truth_scene(const std::string& problem, const lgi::State<double>& x0, const std::string& method, double dt,
                        double t_end, int every) {
  return "{" + problem + R"(, "initial": {"R": )" + mat(x0.R) + R"(, "omega": )" + vec(x0.Omega) +
         R"(}, "integrator": {"method": ")" + method + R"(", "dt": )" + num(dt) + R"(}, "t_end": )" + num(t_end) +
         R"(, "output": {"every": )" + std::to_string(every) + "}}";
}

lgi::Vec3<double> vec_of(const json& j) { return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()}; }

// Acceptance case 1 of the fitting issue, through files: Ω0 of the skew heavy top from its attitudes every
// 0.2 over T = 10 (51 rows of `lgi run` output, h = 0.01), starting 20 % off, with LGVI and RKMK4.
TEST_F(CliFit, RecoversOmega0FromTheAttitudesLgiRunWrote) {
  const lgi::State<double> truth = lgi::test::skew_initial_state();
  for (const std::string method : {"lgvi", "rkmk4"}) {
    SCOPED_TRACE(method);
    write("truth.json", truth_scene(skew_top_problem(), truth, method, 0.01, 10, 20));
    const Result run = lgi("run " + (dir_ / "truth.json").string() + " -q -o " + (dir_ / "obs.csv").string());
    ASSERT_EQ(run.status, 0) << run.err;
    lgi::State<double> guess = truth;
    guess.Omega *= 1.2;
    const std::string fit = truth_scene(skew_top_problem(), guess, method, 0.01, 10, 20);
    write("fit.json", fit.substr(0, fit.size() - 1) +
                          R"(, "fit": {"unknowns": ["initial.omega"],
                                       "observations": {"csv": "obs.csv", "sigma_attitude": 1e-3}}})");
    const Result r = lgi("fit " + (dir_ / "fit.json").string() + " -o " + (dir_ / "result.json").string());
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_TRUE(r.out.empty());
    const json res = json::parse(slurp(dir_ / "result.json"));
    const double error = (vec_of(res.at("initial").at("omega")) - truth.Omega).cwiseAbs().maxCoeff();
    std::printf("%s: |Omega0 - truth|_max = %.3e, %d iterations, %s\n", method.c_str(), error,
                res.at("iterations").get<int>(), res.at("termination").get<std::string>().c_str());
    // Noise-free (a fit stopped one iteration early leaves ≈ 1e-7): round-off, held to ≈ 5×.
    lgi::test::expect_figure("lgi fit, noise-free Omega0, " + method, error, 2.5e-14);
    EXPECT_TRUE(res.at("usable").get<bool>());
    EXPECT_EQ(res.at("observations").get<int>(), 51);
    EXPECT_EQ(res.at("method").get<std::string>(), method);
    // σ of Ω0 from σ = 1e-3 rad attitudes: positive, finite, small.
    for (int k = 0; k < 3; ++k) {
      const double s = res.at("sigma").at("initial").at("omega").at(k).get<double>();
      EXPECT_GT(s, 0);
      EXPECT_LT(s, 1e-2);
    }
    EXPECT_EQ(res.at("coordinates").size(), 3u);
    EXPECT_NE(r.err.find("usable"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("CONVERGENCE"), std::string::npos) << r.err;
  }
}

// R0, Ω0 and two principal moments (I3 held: the data fix only ratios) of a free body from inline
// attitude and gyro observations and the same data as a CSV table.
// Observations as they come: `lgi run`'s attitudes rounded to 6 decimals (|RᵀR − I| up to 2e-6), and the same
// attitudes as float32 quaternions (|q| − 1 up to 6e-8), are made exact, said so, and fit: Ω0 within the fit's
// own σ of the estimate from the exact observations (σ = 1e-6 rad).
TEST_F(CliFit, RoundedObservationsAreMadeExactAndFitWithinTheirSigma) {
  const lgi::State<double> truth = lgi::test::skew_initial_state();
  write("truth.json", truth_scene(skew_top_problem(), truth, "lgvi", 0.01, 10, 20));
  const Result run = lgi("run " + (dir_ / "truth.json").string() + " -q -o " + (dir_ / "exact.csv").string());
  ASSERT_EQ(run.status, 0) << run.err;
  lgi::State<double> guess = truth;
  guess.Omega *= 1.1;
  const std::string scene = truth_scene(skew_top_problem(), guess, "lgvi", 0.01, 10, 20);
  const auto fit = [&](const std::string& observations, double& sigma_max, std::string& err) {
    write("fit.json", scene.substr(0, scene.size() - 1) + R"(, "fit": {"unknowns": ["initial.omega"], "observations": )" +
                          observations + "}}");
    const Result r = lgi("fit " + (dir_ / "fit.json").string() + " -o " + (dir_ / "result.json").string());
    EXPECT_EQ(r.status, 0) << r.err;
    err = r.err;
    const json res = json::parse(slurp(dir_ / "result.json"));
    sigma_max = 0;
    for (int k = 0; k < 3; ++k) sigma_max = std::max(sigma_max, res.at("sigma").at("initial").at("omega").at(k).get<double>());
    return vec_of(res.at("initial").at("omega"));
  };
  double sigma = 0;
  std::string err;
  const lgi::Vec3<double> exact = fit(R"({"csv": "exact.csv", "sigma_attitude": 1e-6})", sigma, err);
  EXPECT_EQ(err.find("input "), std::string::npos) << err;

  // The table rounded to 6 decimals.
  std::istringstream in(slurp(dir_ / "exact.csv"));
  std::string line, rounded, inline_q;
  std::getline(in, line);
  rounded = line + "\n";
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::istringstream cells(line);
    for (std::string c; std::getline(cells, c, ',');) v.push_back(std::strtod(c.c_str(), nullptr));
    for (std::size_t i = 0; i < v.size(); ++i) {
      char buf[32];
      std::snprintf(buf, sizeof buf, i == 0 ? "%.17g" : "%.6f", v[i]);
      rounded += (i ? "," : "") + std::string(buf);
    }
    rounded += "\n";
    // The row's attitude as a float32 quaternion, inline.
    lgi::Mat3<double> R;
    for (int e = 0; e < 9; ++e) R(e / 3, e % 3) = v[static_cast<std::size_t>(1 + e)];
    const Eigen::Quaterniond q(R);
    char obs[200];
    std::snprintf(obs, sizeof obs, R"(%s{"t": %.17g, "q": [%.9g, %.9g, %.9g, %.9g], "sigma": 1e-6})",
                  inline_q.empty() ? "" : ", ", v[0], static_cast<double>(static_cast<float>(q.w())),
                  static_cast<double>(static_cast<float>(q.x())), static_cast<double>(static_cast<float>(q.y())),
                  static_cast<double>(static_cast<float>(q.z())));
    inline_q += obs;
  }
  std::ofstream(dir_ / "rounded.csv") << rounded;
  double sigma6 = 0;
  const lgi::Vec3<double> six = fit(R"({"csv": "rounded.csv", "sigma_attitude": 1e-6})", sigma6, err);
  EXPECT_NE(err.find("lgi: warning: "), std::string::npos) << err;
  EXPECT_NE(err.find("  input            " + (dir_ / "rounded.csv").string() + " 51 of 51 attitudes projected onto SO(3)"),
            std::string::npos) << err;
  double sigma32 = 0;
  const lgi::Vec3<double> f32 = fit("[" + inline_q + "]", sigma32, err);
  EXPECT_EQ(err.find("lgi: warning: "), std::string::npos) << err;  // float32 rounding: below the warning's 1e-6
  EXPECT_NE(err.find("  input            /fit/observations/1/q normalised (its length was 1 "), std::string::npos) << err;
  // A table of quaternion columns (output.columns), as lgi run writes it: the same names are read back.
  std::string q_scene = truth_scene(skew_top_problem(), truth, "lgvi", 0.01, 10, 20);
  q_scene.insert(q_scene.rfind('}') - 1, R"(, "columns": ["t", "quaternion", "omega"])");
  write("truth_q.json", q_scene);
  ASSERT_EQ(lgi("run " + (dir_ / "truth_q.json").string() + " -q -o " + (dir_ / "q.csv").string()).status, 0);
  EXPECT_EQ(slurp(dir_ / "q.csv").substr(0, 23), "t,q_w,q_x,q_y,q_z,omega");
  double sigma_q = 0;
  const lgi::Vec3<double> from_q = fit(R"({"csv": "q.csv", "sigma_attitude": 1e-6})", sigma_q, err);
  const double d6 = (six - exact).cwiseAbs().maxCoeff(), d32 = (f32 - exact).cwiseAbs().maxCoeff(),
               dq = (from_q - exact).cwiseAbs().maxCoeff();
  std::printf("Omega0 from rounded observations against the exact ones: 6 decimals %.2e, float32 quaternions %.2e "
              "(the fits' sigma %.2e, %.2e); from a table of quaternion columns %.2e\n", d6, d32, sigma6, sigma32, dq);
  EXPECT_LT(d6, sigma6);
  EXPECT_LT(d32, sigma32);
  EXPECT_LT(dq, 1e-12);  // the same attitudes, written as quaternions
}

TEST_F(CliFit, RecoversAttitudeAndMomentsFromInlineObservations) {
  const lgi::State<double> truth{lgi::so3::exp(lgi::Vec3<double>(0.4, 0.2, -0.3)), lgi::Vec3<double>(0.7, -0.4, 1.1)};
  const std::string problem = R"("problem": {"type": "free_body", "inertia": [0.9, 1.3, 1.7]})";
  write("truth.json", truth_scene(problem, truth, "lgvi", 0.01, 4, 25));
  ASSERT_EQ(lgi("run " + (dir_ / "truth.json").string() + " -q -o " + (dir_ / "obs.csv").string()).status, 0);
  // The CSV rows as inline observations: attitude and gyro at each time.
  std::ifstream in(dir_ / "obs.csv");
  std::string line;
  std::getline(in, line);  // header: t, R11..R33, omega1..3, ...
  std::string obs;
  while (std::getline(in, line)) {
    std::vector<double> v;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) v.push_back(std::stod(cell));
    const std::string R = "[[" + num(v[1]) + "," + num(v[2]) + "," + num(v[3]) + "],[" + num(v[4]) + "," + num(v[5]) +
                          "," + num(v[6]) + "],[" + num(v[7]) + "," + num(v[8]) + "," + num(v[9]) + "]]";
    obs += std::string(obs.empty() ? "" : ",\n") + R"({"t": )" + num(v[0]) + R"(, "R": )" + R + R"(, "sigma": 1e-3},)" +
           R"({"t": )" + num(v[0]) + R"(, "omega": [)" + num(v[10]) + "," + num(v[11]) + "," + num(v[12]) +
           R"(], "sigma": 1e-2})";
  }
  const lgi::State<double> guess{truth.R * lgi::so3::exp(lgi::Vec3<double>(0.05, -0.04, 0.03)), truth.Omega * 1.05};
  const std::string base = truth_scene(R"("problem": {"type": "free_body", "inertia": [0.85, 1.4, 1.7]})", guess,
                                       "lgvi", 0.01, 4, 25);
  write("fit.json", base.substr(0, base.size() - 1) +
                        R"(, "fit": {"unknowns": ["initial.R", "initial.omega", {"name": "problem.inertia", "fixed": [2]}],
                                     "observations": [)" + obs + "]}}");
  const Result r = lgi("fit " + (dir_ / "fit.json").string());
  ASSERT_EQ(r.status, 0) << r.err;
  const json res = json::parse(r.out);
  const json& R = res.at("initial").at("R");
  double eR = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) eR = std::max(eR, std::abs(R.at(i).at(j).get<double>() - truth.R(i, j)));
  const double eW = (vec_of(res.at("initial").at("omega")) - truth.Omega).cwiseAbs().maxCoeff();
  const lgi::Vec3<double> I = vec_of(res.at("problem").at("inertia"));
  const double eI = (I - lgi::Vec3<double>(0.9, 1.3, 1.7)).cwiseAbs().maxCoeff();
  std::printf("free body R0, Omega0, I1, I2: |R0 - truth| %.2e, |Omega0 - truth| %.2e, |I - truth| %.2e\n", eR, eW, eI);
  lgi::test::expect_figure("lgi fit, noise-free free body, R0", eR, 3.6e-15);
  lgi::test::expect_figure("lgi fit, noise-free free body, Omega0", eW, 3.6e-15);
  lgi::test::expect_figure("lgi fit, noise-free free body, I1 and I2", eI, 3.6e-15);
  EXPECT_EQ(res.at("sigma").at("initial").at("R").size(), 3u);          // three angles
  EXPECT_EQ(res.at("sigma").at("problem").at("inertia").at(2).get<double>(), 0.0);  // fixed
  EXPECT_EQ(res.at("coordinates").size(), 8u);
}

// With all three moments free the scale is not fixed: the fit matches the data but has no covariance, so it
// is not usable — exit 5, the result still written.
TEST_F(CliFit, UnidentifiableScaleExitsFiveWithTheResultWritten) {
  const lgi::State<double> truth{lgi::Mat3<double>::Identity(), lgi::Vec3<double>(0.7, -0.4, 1.1)};
  write("truth.json", truth_scene(R"("problem": {"type": "free_body", "inertia": [0.9, 1.3, 1.7]})", truth, "lgvi",
                                  0.01, 2, 20));
  ASSERT_EQ(lgi("run " + (dir_ / "truth.json").string() + " -q -o " + (dir_ / "obs.csv").string()).status, 0);
  const std::string base = truth_scene(R"("problem": {"type": "free_body", "inertia": [1, 1.3, 1.7]})", truth, "lgvi",
                                       0.01, 2, 20);
  write("fit.json", base.substr(0, base.size() - 1) +
                        R"(, "fit": {"unknowns": ["problem.inertia"],
                                     "observations": {"csv": "obs.csv", "sigma_attitude": 1e-3, "sigma_omega": 1e-3}}})");
  const Result r = lgi("fit " + (dir_ / "fit.json").string() + " -q -o " + (dir_ / "result.json").string());
  EXPECT_EQ(r.status, 5) << r.err;
  EXPECT_NE(r.err.find("not usable"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("rank deficient"), std::string::npos) << r.err;
  ASSERT_TRUE(fs::exists(dir_ / "result.json"));
  const json res = json::parse(slurp(dir_ / "result.json"));
  EXPECT_FALSE(res.at("usable").get<bool>());
  EXPECT_FALSE(res.contains("covariance"));
  // The ratios are still right.
  const lgi::Vec3<double> I = vec_of(res.at("problem").at("inertia"));
  EXPECT_NEAR(I(0) / I(2), 0.9 / 1.7, 1e-8);
  EXPECT_NEAR(I(1) / I(2), 1.3 / 1.7, 1e-8);
}

// A periodic orbit of the Hairer–Vilmart free body: Ω0 (first component held) and the period, from a guess
// 5 % off in Ω0 and the period; the period of the fitted Ω0 from the exact solution (docs/free_body_exact.md).
TEST_F(CliFit, FindsAPeriodicOrbitOfTheFreeBody) {
  const lgi::FreeBody<double> body = lgi::FreeBody<double>::hairer_vilmart();
  const lgi::State<double> x0 = lgi::test::hairer_vilmart_state(body);
  const double T_exact = static_cast<double>(lgi::FreeBodyExact<double>(body.inertia).solve(x0).period());
  const lgi::Vec3<double> guess(x0.Omega(0), 1.05 * x0.Omega(1), 0.95 * x0.Omega(2));
  const std::string text = R"({"problem": {"type": "free_body", "inertia": )" + vec(body.inertia.diagonal()) +
                           R"(}, "initial": {"omega": )" + vec(guess) +
                           R"(}, "integrator": {"method": "rkmk4", "dt": 0.01},
    "fit": {"unknowns": [{"name": "initial.omega", "fixed": [0]}, "period"],
            "periodic": {"period": )" + num(1.05 * T_exact) + R"(, "steps": 1000}}})";
  write("periodic.json", text);
  const Result r = lgi("fit " + (dir_ / "periodic.json").string());
  ASSERT_EQ(r.status, 0) << r.err;
  const json res = json::parse(r.out);
  lgi::State<double> fitted = x0;
  fitted.Omega = vec_of(res.at("initial").at("omega"));
  const double T_fit = res.at("period").get<double>();
  const double T_ref = static_cast<double>(lgi::FreeBodyExact<double>(body.inertia).solve(fitted).period());
  std::printf("periodic free body (rkmk4, 1000 steps): residual %.2e, T - T_exact(fitted Omega0) = %.2e\n",
              res.at("max_residual").get<double>(), T_fit - T_ref);
  EXPECT_LE(res.at("max_residual").get<double>(), 1e-10);
  EXPECT_LE(std::abs(T_fit - T_ref), 1e-8);  // RKMK4 at 1000 steps: 1.0e-10 in test_fit_periodic
  EXPECT_EQ(res.at("mode").get<std::string>(), "periodic");
  EXPECT_FALSE(res.contains("sigma"));
}

// The example fit files, as the docs tell users to run them: `lgi run truth.json -o obs.csv`, then
// `lgi fit fit.json`; and the periodic orbit of the hanging heavy top.
TEST_F(CliFit, ExamplesRunAsDocumented) {
  for (const char* f : {"truth.json", "fit.json", "periodic.json"})
    fs::copy_file(fs::path(LGI_EXAMPLES_DIR) / "fit" / f, dir_ / f);
  ASSERT_EQ(lgi("run " + (dir_ / "truth.json").string() + " -q -o " + (dir_ / "obs.csv").string()).status, 0);
  Result r = lgi("fit " + (dir_ / "fit.json").string());
  ASSERT_EQ(r.status, 0) << r.err;
  json res = json::parse(r.out);
  const double eW = (vec_of(res.at("initial").at("omega")) - lgi::Vec3<double>(0.7, -0.4, 1.1)).cwiseAbs().maxCoeff();
  const lgi::Vec3<double> I = vec_of(res.at("problem").at("inertia"));
  const double eI = (I - lgi::Vec3<double>(0.9, 1.3, 1.7)).cwiseAbs().maxCoeff();
  std::printf("examples/fit/fit.json: |Omega0 - truth| %.2e, |I - truth| %.2e, %d iterations\n", eW, eI,
              res.at("iterations").get<int>());
  lgi::test::expect_figure("lgi fit examples/fit/fit.json, Omega0", eW, 3.6e-15);
  lgi::test::expect_figure("lgi fit examples/fit/fit.json, inertia", eI, 7e-15);
  r = lgi("fit " + (dir_ / "periodic.json").string());
  ASSERT_EQ(r.status, 0) << r.err;
  res = json::parse(r.out);
  std::printf("examples/fit/periodic.json: residual %.2e, T = %.10f, phase %.3e\n", res.at("max_residual").get<double>(),
              res.at("period").get<double>(), res.at("phase").get<double>());
  EXPECT_LE(res.at("max_residual").get<double>(), 1e-10);
  EXPECT_EQ(res.at("steps").get<int>(), 1000);
}

// On a terminal (script(1)) a fit that takes seconds shows its iterations (examples/fit at h = 3e-5, ≈ 2 s: the
// integrations are 330 000 steps); the line is cleared before the report.
TEST_F(CliFit, ProgressOnATerminal) {
  for (const char* f : {"truth.json", "fit.json"}) fs::copy_file(fs::path(LGI_EXAMPLES_DIR) / "fit" / f, dir_ / f);
  ASSERT_EQ(lgi("run " + (dir_ / "truth.json").string() + " -q -o " + (dir_ / "obs.csv").string()).status, 0);
  json fit = json::parse(slurp(dir_ / "fit.json"));
  fit["integrator"]["dt"] = 3e-5;
  write("slow.json", fit.dump());
  EXPECT_EQ(lgi::test::lgi_on_a_terminal("fit " + (dir_ / "slow.json").string() + " -o " +
                                             (dir_ / "slow_result.json").string(),
                                         dir_ / "screen.txt"),
            0);
  const std::string shown = slurp(dir_ / "screen.txt");
  EXPECT_NE(shown.find("\r  iteration "), std::string::npos) << shown;
  EXPECT_NE(shown.find(", max |gradient| "), std::string::npos) << shown;
  EXPECT_NE(shown.find(" s elapsed"), std::string::npos) << shown;
  EXPECT_NE(shown.find("lgi fit: "), std::string::npos) << shown;
  // Not a terminal: lines with --progress, nothing without.
  const Result lines = lgi("fit --progress " + (dir_ / "slow.json").string() + " -o " + (dir_ / "slow_result.json").string());
  EXPECT_EQ(lines.status, 0) << lines.err;
  EXPECT_EQ(lines.err.rfind("lgi: progress: iteration ", 0), 0u) << lines.err;
}

struct BadFit {
  const char* name;
  std::string fit;       // the "fit" section's members, or a whole replacement when it starts with '{'
  std::string where;     // the JSON path or CSV line the message must name
  std::string message;   // a phrase it must contain
};

TEST_F(CliFit, BadFitFilesGetOneMessageNamingThePath) {
  write("obs.csv", "t,R11,R12,R13,R21,R22,R23,R31,R32,R33\n0,1,0,0,0,1,0,0,0,1\n0.5,1,0,0,0,1,0\n");
  write("late.csv", "t,omega1,omega2,omega3\n0,1,2,3\n7,1,2,3\n");
  write("nan.csv", "t,omega1,omega2,omega3\n0,1,2,3\n0.5,1,nan,3\n");
  const std::string R_id = R"([[1,0,0],[0,1,0],[0,0,1]])";
  const std::string scene = R"("problem": {"type": "heavy_top", "inertia": [2, 2, 1], "b": 1},
      "initial": {"omega": [0.1, 0.2, 3]}, "integrator": {"method": "lgvi", "dt": 0.01}, "t_end": 1)";
  const std::vector<BadFit> cases = {
      {"no fit section", "{" + scene + "}", "/", "fit"},
      {"unknown unknown", R"("unknowns": ["initial.omega", "initial.spin"], "observations": [{"t": 0.5, "R": )" + R_id +
                              R"(, "sigma": 1e-3}])",
       "/fit/unknowns/1", "initial.spin"},
      {"misspelt unknown", R"("unknowns": [{"name": "initial.omgea"}], "observations": [{"t": 0.5, "R": )" + R_id +
                               R"(, "sigma": 1e-3}])",
       "/fit/unknowns/0/name", "unknown unknown \"initial.omgea\"; did you mean \"initial.omega\"?"},
      {"observation after t_end", R"("unknowns": ["initial.omega"], "observations": [{"t": 1.5, "R": )" + R_id +
                                      R"(, "sigma": 1e-3}])",
       "/fit/observations/0/t", "outside [0, 1]"},
      {"times not increasing", R"("unknowns": ["initial.omega"], "observations": [{"t": 0.5, "R": )" + R_id +
                                   R"(, "sigma": 1e-3}, {"t": 0.2, "R": )" + R_id + R"(, "sigma": 1e-3}])",
       "/fit/observations/1/t", "increasing"},
      {"zero sigma", R"("unknowns": ["initial.omega"], "observations": [{"t": 0.5, "omega": [1, 2, 3], "sigma": 0}])",
       "/fit/observations/0/sigma", "> 0"},
      {"negative sigma", R"("unknowns": ["initial.omega"], "observations": [{"t": 0.5, "omega": [1, 2, 3], "sigma": -1}])",
       "/fit/observations/0/sigma", "> 0"},
      {"not a rotation", R"("unknowns": ["initial.omega"], "observations": [{"t": 0.5, "R": [[1,0,0],[0,1,0],[0,0,2]], "sigma": 1e-3}])",
       "/fit/observations/0/R", "must be a rotation matrix (to 0.01): |R^T R - I| = 3"},
      {"mismatched size", R"("unknowns": ["initial.omega"], "observations": [{"t": 0.5, "omega": [1, 2], "sigma": 1e-3}])",
       "/fit/observations/0/omega", "array of 3"},
      {"two kinds in one", R"("unknowns": ["initial.omega"], "observations": [{"t": 0.5, "omega": [1, 2, 3], "R": )" +
                               R_id + R"(, "sigma": 1e-3}])",
       "/fit/observations/0", "exactly one"},
      {"quaternion not unit", R"("unknowns": ["initial.omega"], "observations": [{"t": 0.5, "q": [1, 0, 0, 0.2], "sigma": 1e-3}])",
       "/fit/observations/0/q", "must be a unit quaternion (to 0.01), its length is 1.0198"},
      {"unknown loss", R"("unknowns": ["initial.omega"], "observations": [{"t": 0.5, "omega": [1, 2, 3], "sigma": 1, "loss": "l1"}])",
       "/fit/observations/0/loss", "l1"},
      {"fixed out of range", R"("unknowns": [{"name": "initial.omega", "fixed": [3]}], "observations": [{"t": 0.5, "omega": [1, 2, 3], "sigma": 1}])",
       "/fit/unknowns/0/fixed/0", "from 0 to 2"},
      {"nothing free", R"("unknowns": [{"name": "initial.omega", "fixed": [0, 1, 2]}], "observations": [{"t": 0.5, "omega": [1, 2, 3], "sigma": 1}])",
       "/fit/unknowns", "nothing to fit"},
      {"no observations", R"("unknowns": ["initial.omega"], "observations": [])", "/fit/observations", "no observations"},
      {"unknown key", R"("unknowns": ["initial.omega"], "observation": [])", "/fit", "observation"},
      {"csv row size", R"("unknowns": ["initial.omega"], "observations": {"csv": "obs.csv", "sigma_attitude": 1e-3})",
       "obs.csv:3", "row has 7 values"},
      {"csv time outside", R"("unknowns": ["initial.omega"], "observations": {"csv": "late.csv", "sigma_omega": 1e-3})",
       "late.csv:3: column t", "outside [0, 1]"},
      {"csv not a number", R"("unknowns": ["initial.omega"], "observations": {"csv": "nan.csv", "sigma_omega": 1e-3})",
       "nan.csv:3", "column omega2"},
      {"csv missing", R"("unknowns": ["initial.omega"], "observations": {"csv": "none.csv", "sigma_omega": 1e-3})",
       "none.csv", "cannot read"},
      {"csv without sigma", R"("unknowns": ["initial.omega"], "observations": {"csv": "obs.csv"})", "/fit/observations",
       "sigma_attitude"},
      {"continuation order", R"("unknowns": ["initial.omega"], "continuation": [0.5, 0.2], "observations": [{"t": 0.5, "omega": [1, 2, 3], "sigma": 1}])",
       "/fit/continuation", "increase"},
      {"periodic with observations", R"("unknowns": ["initial.omega", "period"], "periodic": {"period": 2}, "observations": [])",
       "/fit/observations", "no observations"},
      {"period outside periodic", R"("unknowns": ["initial.omega", "period"], "observations": [{"t": 0.5, "omega": [1, 2, 3], "sigma": 1}])",
       "/fit/unknowns/1", "period"},
  };
  for (const BadFit& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string text = c.fit.starts_with("{") ? c.fit : "{" + scene + R"(, "fit": {)" + c.fit + "}}";
    const fs::path file = write("bad.json", text);
    const fs::path out = dir_ / "result.json";
    const Result r = lgi("fit " + file.string() + " -o " + out.string());
    EXPECT_EQ(r.status, 1) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_EQ(r.err.rfind("lgi: error: " + file.string() + ": ", 0), 0u) << r.err;
    EXPECT_NE(r.err.find(c.where), std::string::npos) << "expected '" << c.where << "' in: " << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << "expected '" << c.message << "' in: " << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(r.out.empty());
  }
}

// A damped body under a constant disturbance (`rigid_body`): `lgi run` writes its attitudes with the forced LGVI,
// `lgi fit` recovers the damping coefficient and the disturbance from them (noise-free: to round-off); rkmk4 and a
// periodic fit of rigid_body are refused with one line naming the JSON path.
TEST_F(CliFit, RecoversDampingAndDisturbanceOfARigidBody) {
  const std::string problem = R"("problem": {"type": "rigid_body", "inertia": [0.9, 1.3, 1.7],
      "torques": [{"type": "damping", "coefficient": DAMPING}, {"type": "constant", "frame": "body", "torque": TORQUE}]})";
  const auto scene = [&](const std::string& damping, const std::string& torque, const std::string& method) {
    std::string p = problem;
    p.replace(p.find("DAMPING"), 7, damping);
    p.replace(p.find("TORQUE"), 6, torque);
    return "{" + p + R"(, "initial": {"omega": [0.7, -0.4, 1.1]}, "integrator": {"method": ")" + method +
           R"(", "dt": 0.02}, "t_end": 10, "output": {"every": 10})";
  };
  write("truth.json", scene("0.15", "[0.02, -0.03, 0.015]", "lgvi") + "}");
  const Result run = lgi("run " + (dir_ / "truth.json").string() + " -q -o " + (dir_ / "obs.csv").string());
  ASSERT_EQ(run.status, 0) << run.err;
  const std::string fit = R"(, "fit": {"unknowns": ["problem.damping", "problem.body_torque"],
                                       "observations": {"csv": "obs.csv", "sigma_attitude": 1e-3}}})";
  write("fit.json", scene("0.05", "[0, 0, 0]", "lgvi") + fit);
  const Result r = lgi("fit " + (dir_ / "fit.json").string() + " -o " + (dir_ / "result.json").string());
  ASSERT_EQ(r.status, 0) << r.err;
  const json res = json::parse(slurp(dir_ / "result.json"));
  const double c = res.at("problem").at("damping").get<double>();
  const Eigen::Vector3d M = vec_of(res.at("problem").at("body_torque"));
  const double error = std::max(std::abs(c - 0.15), (M - Eigen::Vector3d(0.02, -0.03, 0.015)).cwiseAbs().maxCoeff());
  std::printf("lgi fit, rigid_body: c = %.15f, M_body = (%.15f, %.15f, %.15f), largest error %.2e, %d iterations\n", c,
              M(0), M(1), M(2), error, res.at("iterations").get<int>());
  EXPECT_LT(error, 1e-10);
  EXPECT_TRUE(res.at("usable").get<bool>());

  // -o naming a torque table of the scene: refused, the table untouched.
  const std::string table = "t,M1,M2,M3\n0,0,0,0\n20,0,0,0\n";
  write("zero.csv", table);
  std::string with_table = scene("0.05", "[0, 0, 0]", "lgvi") + fit;
  with_table.replace(with_table.find("\"torques\": ["), 12,
                     R"("torques": [{"type": "table", "file": "zero.csv", "frame": "body"}, )");
  write("table.json", with_table);
  const Result onto = lgi("fit " + (dir_ / "table.json").string() + " -o " + (dir_ / "zero.csv").string());
  EXPECT_EQ(onto.status, 1);
  EXPECT_NE(onto.err.find("is the scene's torque table"), std::string::npos) << onto.err;
  EXPECT_EQ(slurp(dir_ / "zero.csv"), table);

  write("rkmk4.json", scene("0.05", "[0, 0, 0]", "rkmk4") + fit);
  Result bad = lgi("fit " + (dir_ / "rkmk4.json").string());
  EXPECT_EQ(bad.status, 1);
  EXPECT_EQ(bad.err, "lgi: error: " + (dir_ / "rkmk4.json").string() +
                         ": /integrator/method: lgi fit offers rigid_body with the method lgvi (got \"rkmk4\"; the "
                         "library lgi::fit takes any)\n");
  write("periodic.json", scene("0.05", "[0, 0, 0]", "lgvi") +
                             R"(, "fit": {"unknowns": ["initial.omega"], "periodic": {"period": 3}}})");
  bad = lgi("fit " + (dir_ / "periodic.json").string());
  EXPECT_EQ(bad.status, 1);
  EXPECT_NE(bad.err.find("/fit/periodic: lgi fit offers rigid_body with observations only"), std::string::npos)
      << bad.err;
}

// A spacecraft slewing on three wheels with friction (`gyrostat`): `lgi run` writes its attitudes with the gyrostat
// LGVI, `lgi fit` recovers the wheels' friction and the wheel PD law's gains from them (noise-free: to round-off).
TEST_F(CliFit, RecoversRotorFrictionAndWheelGainsOfAGyrostat) {
  const auto scene = [&](const std::string& friction, const std::string& k_R, const std::string& method) {
    std::vector<std::string> c;
    for (std::size_t at = 0, next; at <= friction.size(); at = next + 1) {
      next = std::min(friction.find(',', at), friction.size());
      c.push_back(friction.substr(at, next - at));
    }
    return R"({"problem": {"type": "gyrostat", "inertia": [12, 10, 8],
        "rotors": [{"axis": [1, 0, 0], "inertia": 0.05, "friction": )" + c[0] + R"(, "rate": 50},
                   {"axis": [0, 1, 0], "inertia": 0.05, "friction": )" + c[1] + R"(, "rate": -30},
                   {"axis": [0, 0, 1], "inertia": 0.05, "friction": )" + c[2] + R"(, "rate": 40}],
        "wheel_control": {"target": {"axis_angle": {"axis": [0, 0, 1], "angle": 0.8}}, "k_R": )" + k_R + R"(, "k_Omega": 6}},
      "initial": {"omega": [0.02, -0.01, 0.03]}, "integrator": {"method": ")" + method +
           R"(", "dt": 0.02}, "t_end": 20, "output": {"every": 20})";
  };
  write("truth.json", scene("0.002,0.003,0.0015", "2", "lgvi") + "}");
  const Result run = lgi("run " + (dir_ / "truth.json").string() + " -q -o " + (dir_ / "obs.csv").string());
  ASSERT_EQ(run.status, 0) << run.err;
  const std::string fit = R"(, "fit": {"unknowns": ["problem.rotor_friction", "problem.wheel_k_R"],
                                       "observations": {"csv": "obs.csv", "sigma_attitude": 1e-3}}})";
  write("fit.json", scene("0.001,0.001,0.001", "1.5", "lgvi") + fit);
  const Result r = lgi("fit " + (dir_ / "fit.json").string() + " -o " + (dir_ / "result.json").string());
  ASSERT_EQ(r.status, 0) << r.err;
  const json res = json::parse(slurp(dir_ / "result.json"));
  const Eigen::Vector3d c = vec_of(res.at("problem").at("rotor_friction"));
  const double k_R = res.at("problem").at("wheel_k_R").get<double>();
  const double error = std::max(std::abs(k_R - 2.0), (c - Eigen::Vector3d(0.002, 0.003, 0.0015)).cwiseAbs().maxCoeff());
  std::printf("lgi fit, gyrostat: friction (%.15f, %.15f, %.15f), k_R = %.15f, largest error %.2e, %d iterations\n",
              c(0), c(1), c(2), k_R, error, res.at("iterations").get<int>());
  EXPECT_LT(error, 1e-10);
  EXPECT_TRUE(res.at("usable").get<bool>());

  write("rkmk4.json", scene("0.001,0.001,0.001", "1.5", "rkmk4") + fit);
  const Result bad = lgi("fit " + (dir_ / "rkmk4.json").string());
  EXPECT_EQ(bad.status, 1);
  EXPECT_EQ(bad.err, "lgi: error: " + (dir_ / "rkmk4.json").string() +
                         ": /integrator/method: lgi fit offers gyrostat with the method lgvi (got \"rkmk4\"; the "
                         "library lgi::fit takes any of the gyrostat's methods)\n");
}

TEST_F(CliFit, MethodsAndProblemsOutsideTheCompiledSetAreNamed) {
  const std::string obs = R"("fit": {"unknowns": ["initial.omega"], "observations": [{"t": 0.5, "omega": [1, 2, 3], "sigma": 1}]})";
  write("method.json", R"({"problem": {"type": "free_body", "inertia": [1, 2, 2.5]}, "initial": {"omega": [1, 2, 3]},
                          "integrator": {"method": "split_dmv", "dt": 0.01}, "t_end": 1, )" + obs + "}");
  Result r = lgi("fit " + (dir_ / "method.json").string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("/integrator/method: lgi fit offers the methods lgvi, rkmk4"), std::string::npos) << r.err;
  write("problem.json", R"({"problem": {"type": "lagrange_top", "inertia": [2, 2, 1], "b": 1}, "initial": {"omega": [1, 2, 3]},
                           "integrator": {"method": "lgvi", "dt": 0.01}, "t_end": 1, )" + obs + "}");
  r = lgi("fit " + (dir_ / "problem.json").string());
  EXPECT_EQ(r.status, 1);
  EXPECT_NE(r.err.find("/problem/type: lgi fit offers the problems free_body, heavy_top"), std::string::npos) << r.err;
}

}  // namespace
