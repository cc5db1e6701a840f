// benchmarks/bench_steps.cpp — ns/step of every lgi integrator (the registry's: lgi list) on the HV heavy
// top, a heavy top with non-diagonal J and off-axis z0, and the HV free body (cases: bench_cases.hpp),
// plus the hand-written quaternion RK4 baseline (rk4quat) on the HV heavy top for the abstraction
// penalty. Only the step loop is timed: stepper and internal state are built outside it. One benchmark
// iteration is one period of 1000 steps (h = 0.01, T = 10) from the initial state, so the reported time
// per iteration in µs is the time per step in ns; items/s are steps/s; the counter `s_per_step` says it
// directly (e.g. 62.9ns). lgvi also reports `newton_per_step`, its mean Newton updates per step.
//
// Run (the machine is shared and noisy: quote medians):
//   build-bench/benchmarks/bench_steps --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "bench_cases.hpp"

#include "registry.hpp"  // apps/: every method lgi knows (lgi::app::Methods)

#include <benchmark/benchmark.h>

#include <string>

namespace {

template <class S, class P>
void bm_steps(benchmark::State& st, const P& problem) {
  S stepper(problem);
  const auto y0 = stepper.to_internal(bench::initial_state(problem), 0.0);
  auto y = y0;
  for (auto _ : st) {
    if (!bench::run_period(stepper, y0, y, bench::period_steps, [](auto& x) { benchmark::DoNotOptimize(x); })) {
      st.SkipWithError("step failed");
      break;
    }
    benchmark::ClobberMemory();
  }
  const auto steps = static_cast<double>(st.iterations()) * bench::period_steps;
  st.SetItemsProcessed(static_cast<std::int64_t>(steps));
  st.counters["s_per_step"] = benchmark::Counter(steps, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  if constexpr (requires { stepper.newton_iterations(); })
    st.counters["newton_per_step"] = static_cast<double>(stepper.newton_iterations()) / steps;
}

template <class S, class P>
void add(const std::string& method, const std::string& problem_name, const P& problem) {
  benchmark::RegisterBenchmark((method + "/" + problem_name).c_str(),
                               [problem](benchmark::State& st) { bm_steps<S>(st, problem); })
      ->Unit(benchmark::kMicrosecond);
}

// Every method of the registry that applies to the problem (`lgi list`; the same list as lgi_step_count's).
template <class P>
void add_all(const std::string& problem_name, const P& problem) {
  lgi::app::for_each_method<P>(lgi::app::Methods{}, [&]<template <class> class M>() {
    add<M<P>>(std::string(M<P>::traits.name), problem_name, problem);
  });
}

}  // namespace

int main(int argc, char** argv) {
  add_all("heavy_top", bench::heavy_top_hv());
  add_all("heavy_top_tilted", bench::heavy_top_tilted());
  add_all("free_body", bench::free_body_hv());
  add<bench::QuatRk4>("rk4quat", "heavy_top", bench::heavy_top_hv());
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
