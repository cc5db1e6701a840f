// benchmarks/work_precision.cpp — lgi against the libraries users would otherwise pick, in one process and
// one run: work-precision per case, long-horizon conservation at equal CPU time, all written as JSON for
// scripts/bench_report.py (docs/benchmarks.md and its plots). scripts/bench.sh runs it with everything else.
//
//   work_precision [--out FILE] [--cases DIR] [--refs DIR] [--only NAME[,NAME…]] [--reps N] [--max-run S]
//                  [--long-t T] [--no-long] [--smoke] [--make-refs] [--rhs-calls N]
//
//   --cases DIR   the case scene files, *.json (default: <source>/scenes/bench)
//   --refs DIR    cached references, <case>.json (default: <source>/benchmarks/ref). A missing or stale one
//                 (the scene changed: FNV-1a of the file) is computed and, outside --smoke, written there.
//   --make-refs   recompute and write every reference, then exit (the generator of benchmarks/ref/)
//   --rhs-calls N call each case's peer right-hand side N times, as the suite times it, then exit: run under
//                 callgrind at two N, the difference gives its instructions per call (benchmarks/callgrind_rhs.sh)
//   --smoke       tiny sizes for CI: 3 points per method, one repetition, long horizon T = 100, nothing
//                 written but --out (default for --out: work_precision.json in the current directory)
//
// Method (the fair rules):
//   - every solver integrates the same body from the same initial state (wp_common.hpp); lgi's methods on
//     SO(3) × R³, the peers on (quaternion, body momentum); same compiler and flags (this file's build), the peers
//     also for x86-64-v3 where the building machine has it (LGI_BENCH_PEER_ISA, benchmarks/CMakeLists.txt), the
//     instruction set of lgi's dispatched steps;
//   - fixed steps and adaptive steps on both sides: lgi's embedded pair rkmk_vern9_cayley also at fixed steps
//     (`rkmk_vern9_cayley_fixed`), and the peers' eighth-order steppers likewise (`odeint_rkf78_fixed`,
//     `gsl_rk8pd_fixed`, wp_peers.cpp), so that neither side's best kind of run is missing;
//   - solver creation and reset (initial state, re-initialisation) are outside the timed region: a sample
//     is [time of `inner` × (reset + run)] − [time of `inner` × reset], divided by `inner`, with `inner` chosen
//     so that a batch lasts ≥ 2 ms, on the thread's CPU clock (CLOCK_THREAD_CPUTIME_ID);
//   - a first pass discovers each method's sweep (fixed steps: N growing by 10^¼ from h|Ω0| = 1.5, and
//     shrinking from there while the error stays below 1e-5 when that first point already meets 1e-6;
//     adaptive: tol = 10^−3, 10^−3.5, …) and stops at error ≤ 1e-13, a run longer than --max-run, or a
//     round-off plateau; then --reps passes time every point, each pass in its own shuffled order of all the
//     case's points (every method's, and one batch of the peers' right-hand-side micro-benchmark), so that the
//     machine's slow spells (on a shared VM, 30–70 % slower for seconds) fall on random points of random methods
//     rather than on one method's whole sweep; the reported time is the median of the passes, and the ratio is
//     also given from the points' lower quartiles (a robust figure against such one-sided noise);
//   - error at T: |log(R_refᵀR)| + |Ω − Ω_ref| (wp_common.hpp) against the reference (wp_reference.cpp);
//     points within 10× of the reference's error bar are marked and used only as upper bounds (below);
//   - t(ε) for ε = 1e-6, 1e-8, 1e-10, 1e-12: on each method's Pareto front (time increasing, error decreasing),
//     log-log interpolation between the two points that bracket ε (none when ε is not reached; the cheapest
//     point's time when even it is below ε, flagged as an upper bound; likewise the cheapest point below the
//     reference's resolution, for ε ≥ 11 × its error bar). Per case: the fastest lgi method,
//     the fastest peer, their ratio lgi/peer (> 1: the peer wins), and its spread: the same ratio within each
//     timed pass (both methods' t(ε) from that pass's times), its quartiles over the passes (--reps, default 21).
//   - long horizon (hv_free_body, hv_heavy_top; T = --long-t, default 1e5): lgi's symplectic and projected methods at
//     fixed steps, and for each of them the peers tuned to its CPU time (their tolerance from probe runs over
//     T/100, extrapolated linearly in T); relative energy error, momentum (m·k; free body: m), the
//     Casimir |Π| (free body), ‖RᵀR − I‖ at 40 log-spaced times; drift exponents = least-squares slope of
//     log(running max of the error) against log t over [T/100, T].
#include "wp_common.hpp"

#include "scene.hpp"  // apps/: load_scene (validation, the problem registry)

#include <lgi/core/invariants.hpp>
#include <lgi/core/so3.hpp>

#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <sys/utsname.h>
#include <type_traits>
#include <vector>

#ifndef LGI_SOURCE_DIR
#define LGI_SOURCE_DIR "."
#endif
#ifndef LGI_BENCH_CXX_FLAGS
#define LGI_BENCH_CXX_FLAGS "?"
#endif
#ifndef LGI_BENCH_PEER_ISA
#define LGI_BENCH_PEER_ISA ""
#endif

namespace wp {

double state_error(const State& a, const State& b) {
  return lgi::so3::log(Mat3(a.R.transpose() * b.R)).norm() + (a.Omega - b.Omega).norm();
}
double orthogonality(const Mat3& R) { return (R.transpose() * R - Mat3::Identity()).norm(); }

namespace {

using json = nlohmann::ordered_json;
namespace fs = std::filesystem;

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
const std::vector<double> targets{1e-6, 1e-8, 1e-10, 1e-12};

struct Options {
  std::string out = "work_precision.json";
  std::string cases = std::string(LGI_SOURCE_DIR) + "/scenes/bench";
  std::string refs = std::string(LGI_SOURCE_DIR) + "/benchmarks/ref";
  std::vector<std::string> only;
  int reps = 21;
  double max_run = 0.1;     // seconds: longest single run in a sweep
  double min_batch = 2e-3;  // seconds: shortest timed batch
  int max_points = 24;
  double long_t = 1e5;  // at least 1e4. At 1e4 the best peer keeps the free body's energy to 2e-14, within 100× of round-off
  bool long_horizon = true;
  bool smoke = false;
  bool make_refs = false;
  long rhs_calls = 0;
};

[[noreturn]] void usage_error(const std::string& what) {
  std::fprintf(stderr, "work_precision: %s (see the header of benchmarks/work_precision.cpp)\n", what.c_str());
  std::exit(1);
}

double parse_number(const std::string& flag, const char* text) {
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(v) || v <= 0) usage_error(flag + " needs a positive number, got '" + text + "'");
  return v;
}

Options parse_args(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> const char* {
      if (i + 1 >= argc) usage_error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--out") o.out = value();
    else if (a == "--cases") o.cases = value();
    else if (a == "--refs") o.refs = value();
    else if (a == "--only") {
      std::stringstream ss(value());
      for (std::string s; std::getline(ss, s, ',');) o.only.push_back(s);
    } else if (a == "--reps") o.reps = static_cast<int>(parse_number(a, value()));
    else if (a == "--max-run") o.max_run = parse_number(a, value());
    else if (a == "--long-t") o.long_t = parse_number(a, value());
    else if (a == "--no-long") o.long_horizon = false;
    else if (a == "--smoke") o.smoke = true;
    else if (a == "--make-refs") o.make_refs = true;
    else if (a == "--rhs-calls") o.rhs_calls = static_cast<long>(parse_number(a, value()));
    else usage_error("unknown argument '" + a + "'");
  }
  if (o.smoke) {
    o.reps = 1;
    o.max_run = 0.005;
    o.min_batch = 0;
    o.max_points = 3;
    o.long_t = 100;
  }
  return o;
}

// ---- cases ----------------------------------------------------------------------------------------------

std::string fnv1a(const std::string& path) {
  std::uint64_t h = 1469598103934665603ULL;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) throw std::runtime_error("cannot read " + path);
  unsigned char buf[4096];
  for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;)
    for (std::size_t i = 0; i < n; ++i) h = (h ^ buf[i]) * 1099511628211ULL;
  std::fclose(f);
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

Case load_case(const fs::path& file) {
  const lgi::app::Scene scene = lgi::app::load_scene(file.string());
  Case c;
  c.name = file.stem().string();
  c.file = file.string();
  c.x0 = scene.initial;
  c.t_end = scene.t_end;
  const lgi::app::ProblemModel& model = *scene.problem;
  c.problem_type = std::string(model.type_name());
  bool ok = true;
  if (const auto* p = lgi::app::problem_as<lgi::FreeBody<double>>(model)) {
    c.kind = Kind::free_body;
    c.free_body = *p;
    c.body = {p->inertia, 0.0, Vec3::UnitZ(), Vec3::UnitZ()};
    c.heavy_top = {p->inertia, 0.0, Vec3::UnitZ(), Vec3::UnitZ()};
  } else if (const auto* h = lgi::app::problem_as<lgi::HeavyTop<double>>(model)) {
    c.kind = Kind::heavy_top;
    c.heavy_top = *h;
    c.body = {h->inertia, h->b, h->k, h->z0};
  } else if (const auto* l = lgi::app::problem_as<lgi::LagrangeTop<double>>(model)) {
    c.kind = Kind::lagrange_top;
    c.lagrange_top = *l;
    c.heavy_top = {l->inertia, l->b, l->k, Vec3::UnitZ()};
    c.body = {l->inertia, l->b, l->k, Vec3::UnitZ()};
  } else {
    ok = false;
  }
  if (!ok)
    throw std::runtime_error(c.file + ": /problem/type: the benchmark runs free_body, heavy_top and lagrange_top, not " +
                             c.problem_type);
  if (!(c.t_end > 0)) throw std::runtime_error(c.file + ": /t_end: must be > 0 for a benchmark case");
  return c;
}

// ---- references -----------------------------------------------------------------------------------------

json state_json(const State& x) {
  json R = json::array();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R.push_back(x.R(i, j));
  return {{"R", R}, {"Omega", {x.Omega.x(), x.Omega.y(), x.Omega.z()}}};
}

json reference_json(const Case& c, const Reference& r) {
  json j;
  j["case"] = c.name;
  j["scene"] = fs::path(c.file).filename().string();
  j["scene_fnv1a"] = r.scene_hash;
  j["generator"] = "build/benchmarks/work_precision --make-refs (benchmarks/wp_reference.cpp)";
  j["kind"] = r.kind;
  j["method"] = r.method;
  j["t_end"] = c.t_end;
  j["t_eval"] = r.t_eval;
  j["state"] = state_json(r.x);
  j["error_bar"] = r.error_bar;
  if (r.cross_check >= 0) j["cross_check_exact_vs_integration"] = r.cross_check;
  j["steps"] = {r.steps_coarse, r.steps_fine};
  j["guard"] = {{"perturbation", r.perturbation},
                {"max_amplification", r.max_amplification},
                {"times", r.guard_times},
                {"divergence", r.divergence},
                {"amplification_at_t_end", r.amplification}};
  return j;
}

Reference reference_from_json(const json& j) {
  Reference r;
  r.kind = j.at("kind").get<std::string>();
  r.method = j.at("method").get<std::string>();
  r.t_eval = j.at("t_eval").get<double>();
  const auto& R = j.at("state").at("R");
  const auto& W = j.at("state").at("Omega");
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) r.x.R(i, k) = R.at(static_cast<std::size_t>(3 * i + k)).get<double>();
  for (int i = 0; i < 3; ++i) r.x.Omega(i) = W.at(static_cast<std::size_t>(i)).get<double>();
  r.error_bar = j.at("error_bar").get<double>();
  if (j.contains("cross_check_exact_vs_integration")) r.cross_check = j["cross_check_exact_vs_integration"].get<double>();
  r.steps_coarse = j.at("steps").at(0).get<std::int64_t>();
  r.steps_fine = j.at("steps").at(1).get<std::int64_t>();
  const auto& g = j.at("guard");
  r.perturbation = g.at("perturbation").get<double>();
  r.max_amplification = g.at("max_amplification").get<double>();
  r.guard_times = g.at("times").get<std::vector<double>>();
  r.divergence = g.at("divergence").get<std::vector<double>>();
  r.amplification = g.at("amplification_at_t_end").get<double>();
  r.scene_hash = j.at("scene_fnv1a").get<std::string>();
  r.from_cache = true;
  return r;
}

Reference get_reference(const Case& c, const Options& o, bool force) {
  const std::string hash = fnv1a(c.file);
  const fs::path path = fs::path(o.refs) / (c.name + ".json");
  if (!force && fs::exists(path)) {
    try {
      std::ifstream in(path);
      const json j = json::parse(in);
      if (j.at("scene_fnv1a").get<std::string>() == hash) return reference_from_json(j);
      std::fprintf(stderr, "work_precision: %s is stale (the scene changed); recomputing\n", path.c_str());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "work_precision: %s unreadable (%s); recomputing\n", path.c_str(), e.what());
    }
  }
  std::fprintf(stderr, "work_precision: computing the reference of %s%s\n", c.name.c_str(), o.smoke ? " (reduced)" : "");
  Reference r = compute_reference(c, o.smoke);
  r.scene_hash = hash;
  if (!o.smoke) {
    fs::create_directories(o.refs);
    const fs::path tmp = path.string() + ".tmp";
    {
      std::ofstream out(tmp);
      out << reference_json(c, r).dump(2) << "\n";
      if (!out) throw std::runtime_error("cannot write " + tmp.string());
    }
    fs::rename(tmp, path);
    std::fprintf(stderr, "work_precision: wrote %s\n", path.c_str());
  }
  return r;
}

// ---- timing ---------------------------------------------------------------------------------------------

double cpu_now() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// One timed sample of a trial: [inner × (reset + run)] − [inner × reset], per run. False if a run failed.
bool time_sample(Trial& t, int inner, double& seconds) {
  bool ok = true;
  const double a = cpu_now();
  for (int i = 0; i < inner; ++i) {
    t.reset();
    ok = t.run() && ok;
  }
  const double b = cpu_now();
  for (int i = 0; i < inner; ++i) t.reset();
  const double c = cpu_now();
  seconds = std::max(((b - a) - (c - b)) / inner, 1e-9);
  return ok;
}

// Of the finite values (a failed pass leaves NaN in its slot).
double median(std::vector<double> v) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return nan;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// ---- work-precision -------------------------------------------------------------------------------------

struct Point {
  double param = 0;
  std::int64_t steps = 0;
  double error = nan;
  double first_seconds = nan;
  std::vector<double> samples;
  int inner = 1;
  bool ok = false;
  bool below_reference = false;
  std::string failure;
  std::unique_ptr<Trial> trial;
  double seconds() const { return samples.empty() ? first_seconds : median(samples); }
};

struct MethodRun {
  Method method;
  std::vector<Point> points;
  std::string status = "ok";
};

// Runs one configuration once (untimed for the error, timed roughly for the sweep's budget).
Point first_run(const Method& m, const Case& c, double t_eval, double param, const Reference& ref) {
  Point p;
  p.param = param;
  const double times[] = {t_eval};
  try {
    p.trial = m.make(c, std::span<const double>(times, 1), param);
    p.trial->reset();
    const double a = cpu_now();
    p.ok = p.trial->run();
    p.first_seconds = cpu_now() - a;
    p.steps = p.trial->steps();
    if (p.ok && !p.trial->samples().empty()) {
      p.error = state_error(ref.x, p.trial->samples().back().x);
      p.ok = std::isfinite(p.error);
      if (!p.ok) p.failure = "non-finite state";
    } else {
      p.failure = "solver reported failure";
    }
  } catch (const std::exception& e) {
    p.ok = false;
    p.failure = e.what();
  }
  p.below_reference = p.ok && p.error < 10 * ref.error_bar;
  return p;
}

MethodRun sweep(const Method& m, const Case& c, const Reference& ref, const Options& o) {
  MethodRun run{m, {}, "ok"};
  const double t_eval = ref.t_eval;
  const double omega = std::max(c.x0.Omega.norm(), 1e-3);
  double best = std::numeric_limits<double>::infinity();
  int worse = 0, failures = 0, usable = 0;
  for (int j = 0; j < 60 && usable < o.max_points; ++j) {
    double param;
    if (m.adaptive) {
      param = std::pow(10.0, -3.0 - 0.5 * j);
      if (param < 3e-15) break;
    } else {
      const double n0 = std::max(4.0, std::ceil(t_eval * omega / 1.5));
      param = std::ceil(n0 * std::pow(10.0, 0.25 * j));
    }
    Point p = first_run(m, c, t_eval, param, ref);
    const bool ok = p.ok;
    const double err = p.error, secs = p.first_seconds;
    if (!ok) {
      ++failures;
      run.points.push_back(std::move(p));
      if (failures >= 4 && best == std::numeric_limits<double>::infinity()) {
        run.status = "failed: " + run.points.back().failure;
        break;
      }
      if (secs > o.max_run) break;
      continue;
    }
    run.points.push_back(std::move(p));
    ++usable;
    if (err < best) {
      worse = err > 0.5 * best ? worse + 1 : 0;
      best = err;
    } else {
      ++worse;
    }
    if (err <= 1e-13 || secs > o.max_run) break;
    if (worse >= 2 && best < 1e-8) break;  // round-off plateau
  }
  // Fixed steps whose first point (h|Ω0| ≈ 1.5) already meets 1e-6 — methods that integrate a fast spin
  // exactly, or high orders on slow bodies — continue towards coarser steps, so that every t(ε) is
  // bracketed rather than bounded: n shrinks by 10^¼ until the error exceeds 1e-5, a run fails, or n = 1.
  if (!m.adaptive && usable > 0 && run.points.front().ok && run.points.front().error < 1e-6) {
    const double n0 = run.points.front().param;
    for (int j = 1; j < 60; ++j) {
      const double param = std::floor(n0 * std::pow(10.0, -0.25 * j));
      if (param < 1 || param >= run.points.front().param) break;
      Point p = first_run(m, c, t_eval, param, ref);
      const bool stop = !p.ok || p.error > 1e-5;
      run.points.insert(run.points.begin(), std::move(p));
      if (stop) break;
    }
  }
  return run;
}

// Pareto front (time increasing, error strictly decreasing) of the usable points, then t(ε).
struct TimeAt {
  double seconds = nan;
  bool upper_bound = false;  // even the cheapest point is below ε
};
// A point below the reference's resolution (error < 10 × its bar) is within 11 × the bar of the truth, so for
// ε ≥ 11 × the bar the cheapest such point bounds t(ε) from above (flagged) where it is cheaper than the front's t(ε)
// or the front has none: the exact solution's points, at round-off, are all of this kind.
// The q-quantile of the finite values (nearest rank).
double quantile_of(std::vector<double> v, double q) {
  v.erase(std::remove_if(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }), v.end());
  if (v.empty()) return nan;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5)];
}
constexpr int median_of_passes = -1, lower_quartile_of_passes = -2;
// A point's time: the median of its passes (median_of_passes), their lower quartile (lower_quartile_of_passes), or
// its time in that pass (NaN where that pass failed: the pass then gives no ratio).
double point_seconds(const Point& p, int pass) {
  if (pass == lower_quartile_of_passes) return p.samples.empty() ? p.first_seconds : quantile_of(p.samples, 0.25);
  if (pass < 0) return p.seconds();
  return static_cast<std::size_t>(pass) < p.samples.size() ? p.samples[static_cast<std::size_t>(pass)] : nan;
}
TimeAt below_reference_bound(const MethodRun& r, double eps, double bar, TimeAt t, int pass) {
  if (!(eps >= 11 * bar)) return t;
  for (const Point& p : r.points)
    if (p.ok && p.below_reference && std::isfinite(point_seconds(p, pass)) && !(point_seconds(p, pass) >= t.seconds))
      t = {point_seconds(p, pass), true};
  return t;
}
// t(ε) from the points' medians (pass < 0) or from their times in one timed pass.
TimeAt time_at(const MethodRun& r, double eps, double bar, int pass = -1) {
  std::vector<std::pair<double, double>> pts;  // (seconds, error)
  for (const Point& p : r.points)
    if (p.ok && !p.below_reference && p.error > 0 && std::isfinite(point_seconds(p, pass)))
      pts.emplace_back(point_seconds(p, pass), p.error);
  std::sort(pts.begin(), pts.end());
  std::vector<std::pair<double, double>> front;
  for (const auto& q : pts)
    if (front.empty() || q.second < front.back().second) front.push_back(q);
  TimeAt t;
  if (front.empty()) return below_reference_bound(r, eps, bar, t, pass);
  if (front.front().second <= eps) return below_reference_bound(r, eps, bar, {front.front().first, true}, pass);
  for (std::size_t i = 1; i < front.size(); ++i) {
    const auto& [t0, e0] = front[i - 1];
    const auto& [t1, e1] = front[i];
    if (e1 <= eps) {
      const double s = (std::log(eps) - std::log(e0)) / (std::log(e1) - std::log(e0));
      return below_reference_bound(r, eps, bar, {std::exp(std::log(t0) + s * (std::log(t1) - std::log(t0))), false}, pass);
    }
  }
  return below_reference_bound(r, eps, bar, t, pass);
}

std::string eps_key(double eps) {
  char buf[16];
  std::snprintf(buf, sizeof buf, "%.0e", eps);
  return buf;
}

json run_case(const Case& c, const Reference& ref, const Options& o) {
  std::vector<Method> methods = lgi_methods(c);
  for (Method& m : peer_methods(c)) methods.push_back(std::move(m));

  std::vector<MethodRun> runs;
  for (const Method& m : methods) {
    runs.push_back(sweep(m, c, ref, o));
    const MethodRun& r = runs.back();
    std::fprintf(stderr, "  %-32s %2zu points%s\n", m.name.c_str(), r.points.size(),
                 r.status == "ok" ? "" : ("  " + r.status).c_str());
  }
  // Calibrate each point's batch size, then the timed passes: each pass times every point once, and one batch of
  // the peers' right-hand side, in an order shuffled afresh (a fixed seed: the same orders every run).
  for (MethodRun& r : runs)
    for (Point& p : r.points)
      if (p.ok) p.inner = std::max(1, static_cast<int>(std::ceil(o.min_batch / std::max(p.first_seconds, 1e-7))));
  constexpr std::size_t rhs_batch = std::numeric_limits<std::size_t>::max();
  std::vector<std::pair<std::size_t, std::size_t>> order;  // (run, point), or (rhs_batch, 0)
  for (std::size_t k = 0; k < runs.size(); ++k)
    for (std::size_t j = 0; j < runs[k].points.size(); ++j)
      if (runs[k].points[j].ok) order.emplace_back(k, j);
  order.emplace_back(rhs_batch, 0);
  std::mt19937_64 shuffle_engine(0x6c6769);
  std::vector<double> rhs_seconds;
  const long rhs_calls = o.smoke ? 20000 : 200000;
  for (int rep = 0; rep < o.reps; ++rep) {
    std::shuffle(order.begin(), order.end(), shuffle_engine);
    for (const auto& [k, j] : order) {
      if (k == rhs_batch) {
        rhs_seconds.push_back(peer_rhs_seconds(c, 1, rhs_calls).front());
        continue;
      }
      Point& p = runs[k].points[j];
      double s = nan;
      p.samples.push_back(time_sample(*p.trial, p.inner, s) ? s : nan);  // one slot per pass
    }
  }

  json jc;
  jc["name"] = c.name;
  jc["scene"] = fs::relative(c.file, LGI_SOURCE_DIR).string();
  jc["problem"] = c.problem_type;
  jc["t_end"] = c.t_end;
  jc["t_eval"] = ref.t_eval;
  json jr = reference_json(c, ref);
  jr["from_cache"] = ref.from_cache;
  jc["reference"] = jr;
  {  // the peers' right-hand side alone: ns a call, median and quartiles of one batch of 2e5 calls a pass
    const auto q = [&](double f) { return 1e9 * quantile_of(rhs_seconds, f); };
    jc["peer_rhs_ns"] = {{"median", q(0.5)}, {"q1", q(0.25)}, {"q3", q(0.75)}, {"batches", rhs_seconds.size()}};
  }
  json jm = json::array();
  std::map<std::string, std::map<double, TimeAt>> t_at;
  for (const MethodRun& r : runs) {
    json m;
    m["name"] = r.method.name;
    m["library"] = r.method.library;
    m["description"] = r.method.description;
    m["order"] = r.method.order;
    m["exact_solution"] = r.method.exact_solution;
    m["adaptive"] = r.method.adaptive;
    m["symplectic"] = r.method.symplectic;
    m["projected"] = r.method.projected;
    m["status"] = r.status;
    json pts = json::array();
    for (const Point& p : r.points) {
      json jp;
      jp[r.method.adaptive ? "tol" : "n_steps"] = p.param;
      jp["steps"] = p.steps;
      jp["ok"] = p.ok;
      if (p.ok) {
        jp["error"] = p.error;
        jp["seconds"] = p.seconds();
        jp["samples"] = p.samples;
        jp["below_reference"] = p.below_reference;
      } else {
        jp["failure"] = p.failure;
      }
      pts.push_back(jp);
    }
    m["points"] = pts;
    json ta;
    for (const double eps : targets) {
      const TimeAt t = time_at(r, eps, ref.error_bar);
      t_at[r.method.name][eps] = t;
      ta[eps_key(eps)] = std::isfinite(t.seconds) ? json(t.seconds) : json(nullptr);
      if (t.upper_bound) ta[eps_key(eps) + "_upper_bound"] = true;
    }
    m["t_at"] = ta;
    jm.push_back(m);
  }
  jc["methods"] = jm;

  const auto run_named = [&](const std::string& name) -> const MethodRun& {
    return *std::find_if(runs.begin(), runs.end(), [&](const MethodRun& r) { return r.method.name == name; });
  };
  json summary;
  for (const double eps : targets) {
    std::string lgi_best, peer_best;
    double lgi_t = nan, peer_t = nan;
    bool lgi_bound = false, peer_bound = false;
    for (const MethodRun& r : runs) {
      const TimeAt& ta = t_at[r.method.name][eps];
      const double t = ta.seconds;
      if (!std::isfinite(t)) continue;
      if (r.method.name == "auto") continue;  // compared with the best below
      if (r.method.library == "lgi") {
        if (!(t >= lgi_t)) {
          lgi_t = t;
          lgi_best = r.method.name;
          lgi_bound = ta.upper_bound;
        }
      } else if (!(t >= peer_t)) {
        peer_t = t;
        peer_best = r.method.name;
        peer_bound = ta.upper_bound;
      }
    }
    json s;
    s["lgi_upper_bound"] = lgi_bound;
    s["peer_upper_bound"] = peer_bound;
    s["lgi_best"] = lgi_best.empty() ? json(nullptr) : json(lgi_best);
    s["lgi_seconds"] = std::isfinite(lgi_t) ? json(lgi_t) : json(nullptr);
    s["peer_best"] = peer_best.empty() ? json(nullptr) : json(peer_best);
    s["peer_seconds"] = std::isfinite(peer_t) ? json(peer_t) : json(nullptr);
    const double ratio = lgi_t / peer_t;
    s["ratio_lgi_over_peer"] = std::isfinite(ratio) ? json(ratio) : json(nullptr);
    {  // the same comparison from each point's lower quartile over the passes (each side's best chosen afresh)
      double lgi_lq = nan, peer_lq = nan;
      std::string lgi_lq_name, peer_lq_name;
      for (const MethodRun& r : runs) {
        if (r.method.name == "auto") continue;
        const double t = time_at(r, eps, ref.error_bar, lower_quartile_of_passes).seconds;
        if (!std::isfinite(t)) continue;
        double& best = r.method.library == "lgi" ? lgi_lq : peer_lq;
        std::string& name = r.method.library == "lgi" ? lgi_lq_name : peer_lq_name;
        if (!(t >= best)) {
          best = t;
          name = r.method.name;
        }
      }
      const double lq = lgi_lq / peer_lq;
      s["lower_quartiles"] = {{"lgi_best", lgi_lq_name.empty() ? json(nullptr) : json(lgi_lq_name)},
                              {"peer_best", peer_lq_name.empty() ? json(nullptr) : json(peer_lq_name)},
                              {"ratio_lgi_over_peer", std::isfinite(lq) ? json(lq) : json(nullptr)}};
    }
    // "auto" (its choice and probes timed) against the fastest lgi method at the same ε, with the per-pass spread.
    if (const auto a = t_at.find("auto"); a != t_at.end() && std::isfinite(a->second[eps].seconds)) {
      const double auto_t = a->second[eps].seconds;
      s["auto_seconds"] = auto_t;
      s["auto_upper_bound"] = a->second[eps].upper_bound;
      if (std::isfinite(lgi_t)) {
        s["ratio_auto_over_lgi_best"] = auto_t / lgi_t;
        std::vector<double> per_pass;
        for (int pass = 0; pass < o.reps; ++pass) {
          const double q = time_at(run_named("auto"), eps, ref.error_bar, pass).seconds /
                           time_at(run_named(lgi_best), eps, ref.error_bar, pass).seconds;
          if (std::isfinite(q)) per_pass.push_back(q);
        }
        if (!per_pass.empty()) {
          s["auto_ratio_q1"] = quantile_of(per_pass, 0.25);
          s["auto_ratio_q3"] = quantile_of(per_pass, 0.75);
        }
      }
    }
    // The spread: the ratio of the two methods' t(ε) within each timed pass (every pass times both, in the same
    // minutes of the machine), its quartiles over the passes.
    if (!lgi_best.empty() && !peer_best.empty()) {
      const MethodRun &a = run_named(lgi_best), &b = run_named(peer_best);
      std::vector<double> per_pass;
      for (int pass = 0; pass < o.reps; ++pass) {
        const double q = time_at(a, eps, ref.error_bar, pass).seconds / time_at(b, eps, ref.error_bar, pass).seconds;
        if (std::isfinite(q)) per_pass.push_back(q);
      }
      if (!per_pass.empty()) {
        s["ratio_passes"] = per_pass.size();
        s["ratio_q1"] = quantile_of(per_pass, 0.25);
        s["ratio_q3"] = quantile_of(per_pass, 0.75);
        s["peer_wins_passes"] = std::count_if(per_pass.begin(), per_pass.end(), [](double q) { return q > 1; });
      }
    }
    s["peer_wins"] = std::isfinite(ratio) ? json(ratio > 1) : json(nullptr);
    summary[eps_key(eps)] = s;
  }
  jc["summary"] = summary;
  return jc;
}

// ---- long horizon ---------------------------------------------------------------------------------------

struct Invariants {
  double energy, momentum_k;
  Vec3 momentum;
  double casimir;
};
Invariants invariants(const Case& c, const State& x) {
  const Body& b = c.body;
  Invariants v;
  v.energy = 0.5 * x.Omega.dot(b.J * x.Omega) + b.b * b.k.dot(x.R * b.z0);
  v.momentum = x.R * (b.J * x.Omega);
  v.momentum_k = b.k.dot(v.momentum);
  v.casimir = (b.J * x.Omega).norm();
  return v;
}

// Least-squares slope of log(running max of e) against log t over t ∈ [t_end/100, t_end].
double drift_exponent(const std::vector<double>& t, const std::vector<double>& e, double t_end) {
  double run = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    run = std::max(run, e[i]);
    if (t[i] < t_end / 100 || !(run > 0)) continue;
    const double x = std::log(t[i]), y = std::log(run);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
    ++n;
  }
  if (n < 3) return nan;
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

json long_run_json(const Case& c, const Method& m, double param, const Trial& t, double seconds) {
  const Invariants v0 = invariants(c, t.samples().front().x);
  std::vector<double> ts, energy, momentum, casimir, orth;
  for (const Sample& s : t.samples()) {
    if (s.t <= 0) continue;
    const Invariants v = invariants(c, s.x);
    ts.push_back(s.t);
    energy.push_back(std::abs(v.energy - v0.energy) / std::abs(v0.energy));
    momentum.push_back(c.body.torque() ? std::abs(v.momentum_k - v0.momentum_k) / v0.momentum.norm()
                                       : (v.momentum - v0.momentum).norm() / v0.momentum.norm());
    casimir.push_back(std::abs(v.casimir - v0.casimir) / v0.casimir);
    orth.push_back(s.orthogonality);
  }
  const double t_end = ts.empty() ? 0 : ts.back();
  json j;
  j["method"] = m.name;
  j["library"] = m.library;
  j["symplectic"] = m.symplectic;
  j["projected"] = m.projected;
  j[m.adaptive ? "tol" : "n_steps"] = param;
  j["steps"] = t.steps();
  j["seconds"] = seconds;
  j["times"] = ts;
  j["energy"] = energy;
  j["momentum"] = momentum;
  if (!c.body.torque()) j["casimir"] = casimir;
  j["orthogonality"] = orth;
  const auto max_of = [](const std::vector<double>& v) { return v.empty() ? nan : *std::max_element(v.begin(), v.end()); };
  j["max"] = {{"energy", max_of(energy)}, {"momentum", max_of(momentum)}, {"orthogonality", max_of(orth)}};
  if (!c.body.torque()) j["max"]["casimir"] = max_of(casimir);
  j["drift_exponent"] = {{"energy", drift_exponent(ts, energy, t_end)},
                         {"momentum", drift_exponent(ts, momentum, t_end)},
                         {"orthogonality", drift_exponent(ts, orth, t_end)}};
  return j;
}

json long_horizon(const Case& c, const Options& o) {
  const double T = o.long_t;
  // 40 log-spaced times in [1, T], multiples of 0.05 (a step that does not divide one reaches it by a
  // side-step from a copy: the trajectory stays on its grid).
  std::vector<double> times;
  for (int i = 0; i < 40; ++i) {
    const double t = std::round(std::pow(10.0, std::log10(T) * i / 39.0) / 0.05) * 0.05;
    if (t > 0 && (times.empty() || t > times.back())) times.push_back(t);
  }
  times.back() = T;
  const std::vector<Method> lgi_all = lgi_methods(c);
  const std::vector<Method> peers_all = peer_methods(c);
  const auto find = [](const std::vector<Method>& ms, const std::string& name) -> const Method* {
    for (const Method& m : ms)
      if (m.name == name) return &m;
    return nullptr;
  };
  const auto timed = [&](const Method& m, double param, const std::vector<double>& ts, double& seconds) {
    std::unique_ptr<Trial> t = m.make(c, std::span<const double>(ts), param);
    t->reset();
    const double a = cpu_now();
    const bool ok = t->run();
    seconds = cpu_now() - a;
    if (!ok) throw std::runtime_error(m.name + " failed on the long run");
    return t;
  };

  json runs = json::array();
  // lgi: second-order maps at h = 0.01, compositions at larger steps (about the same CPU time or a few
  // times more), rkmk4 as the non-symplectic contrast, and two projected methods (energy and the momentum
  // invariant restored after every step). Each symplectic or projected one sets a CPU budget the peers are
  // tuned to.
  const std::vector<std::pair<std::string, double>> lgi_list{
      {"split_dmv", 0.01},           {"lgvi", 0.01},
      {"split_dmv_kahan_li6", 0.05}, {"split_dmv_kahan_li8", 0.1},
      {"split_dmv_sofroniou_spaletta10", 0.2}, {"rkmk4", 0.01},
      {"rkmk4_projected", 0.02},     {"rkmk_dp8_cayley_projected", 1e-12}};  // adaptive: the tolerance
  std::vector<std::pair<std::string, double>> budgets;  // (lgi method, CPU seconds)
  std::map<std::string, double> lgi_energy;
  for (const auto& [name, h] : lgi_list) {
    const Method* m = find(lgi_all, name);
    if (m == nullptr) continue;
    double secs = 0;
    const double n = m->adaptive ? h : std::round(T / h);  // adaptive: rtol = atol = the list's value
    const auto t = timed(*m, n, times, secs);
    json r = long_run_json(c, *m, n, *t, secs);
    lgi_energy[name] = r["max"]["energy"].get<double>();
    runs.push_back(r);
    if ((m->symplectic || m->projected) && name != "lgvi")  // lgvi: the same map as split_dmv
      budgets.emplace_back(name, secs);
    std::fprintf(stderr, "  long %-32s %.3f s\n", name.c_str(), secs);
  }
  // Peers tuned to each budget: probe over T/100, pick the parameter whose extrapolated time matches.
  const std::vector<std::string> peer_list{"odeint_rkf78", "odeint_dopri5", "odeint_bulirsch_stoer", "odeint_rk4",
                                           "gsl_rk8pd", "cvode_adams", "arkode_erk8"};
  const std::vector<double> probe_times{T / 100};
  json matches = json::array();
  json best_match;
  double best_ratio = -1;
  for (const auto& [lgi_name, budget] : budgets) {
    double peer_e = nan;
    std::string peer_name;
    for (const std::string& name : peer_list) {
      const Method* m = find(peers_all, name);
      if (m == nullptr) continue;
      double param;
      try {
        if (!m->adaptive) {
          double secs = 0;
          const double n_probe = std::round(T / 100 / 0.01);
          timed(*m, n_probe, probe_times, secs);
          param = std::max(100.0, std::round(budget / (secs / n_probe)));
        } else {
          std::vector<std::pair<double, double>> probe;  // (log tol, log projected seconds)
          for (double tol = 1e-4; tol > 1e-14; tol /= 10) {
            double secs = 0;
            timed(*m, tol, probe_times, secs);
            probe.emplace_back(std::log(tol), std::log(std::max(secs * 100, 1e-9)));
            if (secs * 100 > 3 * budget) break;
          }
          param = std::exp(probe.back().first);
          const double lb = std::log(budget);
          if (lb <= probe.front().second) {
            param = std::exp(probe.front().first);
          } else {
            for (std::size_t i = 1; i < probe.size(); ++i)
              if (probe[i].second >= lb) {
                const double s = (lb - probe[i - 1].second) / (probe[i].second - probe[i - 1].second);
                param = std::exp(probe[i - 1].first + s * (probe[i].first - probe[i - 1].first));
                break;
              }
          }
        }
        double secs = 0;
        const auto t = timed(*m, param, times, secs);
        json r = long_run_json(c, *m, param, *t, secs);
        r["matched_to"] = lgi_name;
        const double e = r["max"]["energy"].get<double>();
        if (!(e >= peer_e)) peer_e = e, peer_name = name;
        runs.push_back(r);
        std::fprintf(stderr, "  long %-32s %.3f s (param %.3g, matched to %s)\n", name.c_str(), secs, param,
                     lgi_name.c_str());
      } catch (const std::exception& e) {
        std::fprintf(stderr, "  long %-32s failed: %s\n", name.c_str(), e.what());
      }
    }
    const double ratio = peer_e / lgi_energy[lgi_name];
    json mt = {{"lgi_method", lgi_name},
               {"budget_seconds", budget},
               {"lgi_max_energy_error", lgi_energy[lgi_name]},
               {"best_peer", peer_name},
               {"peer_max_energy_error", peer_e},
               {"ratio_peer_over_lgi", ratio}};
    if (ratio > best_ratio || best_match.is_null()) best_ratio = ratio, best_match = mt;
    matches.push_back(mt);
  }
  json j;
  j["case"] = c.name;
  j["t_end"] = T;
  j["runs"] = runs;
  j["matches"] = matches;
  // The headline: the lgi method whose energy error beats the peers tuned to its CPU time by the most.
  j["summary"] = best_match;
  return j;
}

// ---- machine --------------------------------------------------------------------------------------------

json machine_json() {
  json m;
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line, model = "?";
  int cores = 0;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) == 0 && model == "?") model = line.substr(line.find(':') + 2);
    if (line.rfind("processor", 0) == 0) ++cores;
  }
  m["cpu"] = model;
  m["logical_cpus"] = cores;
  utsname u{};
  if (uname(&u) == 0) m["kernel"] = std::string(u.sysname) + " " + u.release + " " + u.machine;
  m["compiler"] = std::string("g++ ") + __VERSION__;
  m["flags"] = LGI_BENCH_CXX_FLAGS;
  m["peer_isa"] = *LGI_BENCH_PEER_ISA ? LGI_BENCH_PEER_ISA : "x86-64 baseline";
  json libs;
  libs["eigen"] = std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) + "." +
                  std::to_string(EIGEN_MINOR_VERSION);
  for (const auto& [name, version] : peer_versions()) libs[name] = version;
  m["libraries"] = libs;
  const std::time_t now = std::time(nullptr);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
  m["date"] = buf;
  return m;
}

}  // namespace
}  // namespace wp

int main(int argc, char** argv) {
  using namespace wp;
  const Options o = parse_args(argc, argv);
  if (std::string_view(LGI_BENCH_PEER_ISA) == "x86-64-v3") {  // wp_peers.cpp's code needs it
    __builtin_cpu_init();
    if (!(__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi2"))) {
      std::fprintf(stderr, "work_precision: the peers were compiled for x86-64-v3 (AVX2, FMA, BMI2), which this CPU "
                           "lacks: rebuild with -DLGI_BENCH_PEERS_X86_64_V3=OFF\n");
      return 2;
    }
  }
  try {
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(o.cases))
      if (e.path().extension() == ".json") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    if (files.empty()) usage_error("no *.json case in " + o.cases);
    std::vector<Case> cases;
    for (const fs::path& f : files) {
      Case c = load_case(f);
      if (!o.only.empty() && std::find(o.only.begin(), o.only.end(), c.name) == o.only.end()) continue;
      cases.push_back(std::move(c));
    }
    if (cases.empty()) usage_error("--only matched no case");

    if (o.make_refs) {
      for (const Case& c : cases) get_reference(c, o, true);
      return 0;
    }
    if (o.rhs_calls > 0) {
      for (const Case& c : cases) (void)peer_rhs_seconds(c, 1, o.rhs_calls);
      return 0;
    }
    json out;
    out["schema"] = "lgi-work-precision-1";
    out["smoke"] = o.smoke;
    out["machine"] = machine_json();
    out["timing"] = {{"clock", "CLOCK_THREAD_CPUTIME_ID (thread CPU time)"},
                     {"repetitions", o.reps},
                     {"statistic", "median of the repetitions; each repetition a batch of >= 2 ms, reset cost subtracted"},
                     {"order", "each repetition times every point of a case once, in an order shuffled afresh"},
                     {"max_run_seconds", o.max_run}};
    out["error_measure"] = "|log(R_ref^T R)| + |Omega - Omega_ref| at t_eval (rotation angle + Euclidean norm)";
    out["targets"] = targets;
    json jcases = json::array();
    double worst_jacobian = 0;
    for (const Case& c : cases) {
      std::fprintf(stderr, "work_precision: case %s\n", c.name.c_str());
      worst_jacobian = std::max(worst_jacobian, jacobian_check(c));
      const Reference ref = get_reference(c, o, false);
      jcases.push_back(run_case(c, ref, o));
    }
    out["cases"] = jcases;
    out["peer_jacobian_check"] = worst_jacobian;
    json jlong = json::array();
    if (o.long_horizon)
      for (const Case& c : cases)
        if (c.name == "hv_free_body" || c.name == "hv_heavy_top") {
          std::fprintf(stderr, "work_precision: long horizon %s, T = %g\n", c.name.c_str(), o.long_t);
          jlong.push_back(long_horizon(c, o));
        }
    out["long_horizon"] = jlong;

    const std::string tmp = o.out + ".tmp";
    {
      std::ofstream f(tmp);
      f << out.dump(1) << "\n";
      if (!f) throw std::runtime_error("cannot write " + tmp);
    }
    fs::rename(tmp, o.out);
    std::fprintf(stderr, "work_precision: wrote %s\n", o.out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "work_precision: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
