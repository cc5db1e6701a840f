// benchmarks/bench_steps.cpp — ns/step of every lgi integrator (the registry's: lgi list) on the HV heavy
// top, a heavy top with non-diagonal J and off-axis z0, and the HV free body (cases: bench_cases.hpp),
// plus the hand-written quaternion RK4 baseline (rk4quat) on the HV heavy top for the abstraction
// penalty. Each method runs as `lgi run` runs it: the lgi::Integrator that lgi_scene compiles for the scene's
// method and problem, stepped by its run_grid (the library's fixed-step loop, core/driver.hpp). Only the loop is
// timed: the integrator is built outside it. One benchmark iteration is one period of 1000 steps (h = 0.01,
// T = 10) from the initial state, so the reported time per iteration in µs is the time per step in ns; items/s
// are steps/s; the counter `s_per_step` says it directly (e.g. 62.9ns). Methods with Newton iterations (lgvi)
// also report `newton_per_step`, the mean Newton updates per step.
//
// Run (the machine is shared and noisy: quote medians):
//   build/benchmarks/bench_steps --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "bench_cases.hpp"

#include "registry.hpp"  // apps/: every method lgi knows (lgi::app::Methods)

#include "json_reader.hpp"
#include "runner_detail.hpp"
#include "scene.hpp"

#include <lgi/core/engine.hpp>

#include <benchmark/benchmark.h>

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace {

using lgi::app::Scene;

// The scene's problem and initial state as JSON (format_number: digits that read back as the same doubles).
std::string vector_json(const lgi::Vec3<double>& v) {
  using lgi::app::format_number;
  std::string text = "[";
  return text.append(format_number(v.x())).append(", ").append(format_number(v.y())).append(", ")
      .append(format_number(v.z())).append("]");
}
std::string inertia_json(const lgi::Mat3<double>& J) {
  std::string text = "[";
  for (int r = 0; r < 3; ++r) text.append(r ? ", " : "").append(vector_json(J.row(r).transpose()));
  return text.append("]");
}
std::string problem_json(const lgi::HeavyTop<double>& p) {
  std::string text = R"({"type": "heavy_top", "inertia": )";
  text.append(inertia_json(p.inertia)).append(R"(, "b": )").append(lgi::app::format_number(p.b));
  text.append(R"(, "k": )").append(vector_json(p.k)).append(R"(, "z0": )").append(vector_json(p.z0));
  return text.append("}");
}
std::string problem_json(const lgi::FreeBody<double>& p) {
  return std::string(R"({"type": "free_body", "inertia": )").append(inertia_json(p.inertia)).append("}");
}

template <class P>
Scene make_scene(const P& problem, const std::string& method) {
  const lgi::State<double> x0 = bench::initial_state(problem);
  if (!x0.R.isIdentity(0)) std::abort();  // the scene's default attitude
  std::string text = R"({"problem": )";
  text.append(problem_json(problem)).append(R"(, "initial": {"omega": )").append(vector_json(x0.Omega));
  text.append(R"(}, "integrator": {"method": ")").append(method).append(R"(", "dt": 0.01}, "t_end": 10})");
  return lgi::app::parse_scene(lgi::app::parse_json(text, "bench_steps.json"), "bench_steps.json");
}

// Nothing observed, no budget checks.
class NoSink final : public lgi::RunSink {
 public:
  void observe(double, bool) override {}
  std::int64_t check(const lgi::Cursor<double>&) override { return std::numeric_limits<std::int64_t>::max(); }
};

// The steps timed (one period of bench::period_steps an iteration), as items and as the counter s_per_step.
double report_steps(benchmark::State& st) {
  const auto steps = static_cast<double>(st.iterations()) * bench::period_steps;
  st.SetItemsProcessed(static_cast<std::int64_t>(steps));
  st.counters["s_per_step"] = benchmark::Counter(steps, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  return steps;
}

void bm_engine(benchmark::State& st, const Scene& scene) {
  const std::unique_ptr<lgi::app::runner_detail::ProblemRunner> runner = scene.problem->runner();
  const std::unique_ptr<lgi::Integrator> engine = runner->integrator(scene);
  const auto events = lgi::GridEvents<double>::steps(bench::period_steps, 0.0, bench::h);
  NoSink sink;
  lgi::IntegrationSummary summary;
  for (auto _ : st) {
    engine->set(lgi::Slot::current, scene.initial, 0.0);
    lgi::Cursor<double> cursor;
    bool moved = false;
    const lgi::Halt halt = engine->run_grid(bench::h, events, std::numeric_limits<std::int64_t>::max(), cursor,
                                            summary, moved, sink);
    if (halt != lgi::Halt::none || summary.status != lgi::RunStatus::completed) {
      st.SkipWithError("step failed");
      break;
    }
    benchmark::ClobberMemory();
  }
  const double steps = report_steps(st);
  if (const std::int64_t newton = engine->newton_iterations(); newton >= 0)
    st.counters["newton_per_step"] = static_cast<double>(newton) / steps;
}

// Every method of the registry that applies to the problem type (`lgi list`).
template <class P>
void add_all(const std::string& problem_name, const P& problem) {
  const lgi::app::ProblemInfo* info = lgi::app::find_problem(P::name);
  if (!info) return;  // a build without it (LGI_PROBLEMS)
  for (const std::string_view method : info->methods) {
    const Scene scene = make_scene(problem, std::string(method));
    const std::string name = std::string(method).append("/").append(problem_name);
    benchmark::RegisterBenchmark(name.c_str(),
                                 [scene](benchmark::State& st) { bm_engine(st, scene); })
        ->Unit(benchmark::kMicrosecond);
  }
}

// The hand-written baseline, stepped directly.
void bm_quat_rk4(benchmark::State& st) {
  const lgi::HeavyTop<double> problem = bench::heavy_top_hv();
  bench::QuatRk4 stepper(problem);
  const auto y0 = stepper.to_internal(bench::initial_state(problem), 0.0);
  auto y = y0;
  for (auto _ : st) {
    if (!bench::run_period(stepper, y0, y, bench::period_steps, [](auto& x) { benchmark::DoNotOptimize(x); })) {
      st.SkipWithError("step failed");
      break;
    }
    benchmark::ClobberMemory();
  }
  report_steps(st);
}

}  // namespace

int main(int argc, char** argv) {
  add_all("heavy_top", bench::heavy_top_hv());
  add_all("heavy_top_tilted", bench::heavy_top_tilted());
  add_all("free_body", bench::free_body_hv());
  benchmark::RegisterBenchmark("rk4quat/heavy_top", bm_quat_rk4)->Unit(benchmark::kMicrosecond);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
