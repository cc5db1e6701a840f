// bench_fit — the cost of a fit: the first acceptance case, Ω0 of the skew heavy top (non-diagonal
// inertia, tilted k and z0; tests/test_problems.hpp) from 50 noise-free attitudes over T = 10 (h = 0.01,
// 1000 steps), started 20 % off, with LGVI and RKMK4. Google Benchmark; per fit it reports the solver's
// iterations, the integrations (one in double plus one in Jet<8> per evaluation with Jacobian) and the time
// per iteration. The fits run the instantiations of apps/fit_instances.hpp (the same code `lgi fit` runs).
//
//   build/benchmarks/bench_fit --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include "fit_instances.hpp"
#include "test_problems.hpp"  // the skew heavy top and its initial state, as in the tests

#include <lgi/core/driver.hpp>
#include <lgi/core/so3.hpp>

#include <benchmark/benchmark.h>

#include <vector>

namespace {

using namespace lgi;

const State<double> truth = test::skew_initial_state();

template <template <class> class Method>
void BM_FitOmega0(benchmark::State& state) {
  const HeavyTop<double> top = test::skew_heavy_top();
  const double h = 0.01, T = 10;
  std::vector<double> times;
  for (int i = 1; i <= 50; ++i) times.push_back(T * i / 50);
  std::vector<fit::Observation> obs;
  {
    Method<HeavyTop<double>> stepper(top);
    State<double> x = truth;
    integrate_times(stepper, x, 0.0, h, std::span<const double>(times), [&](double t, const State<double>& s) {
      if (t > 0) obs.push_back(fit::Observation::attitude(t, s.R, 1e-3));
    });
  }
  State<double> guess = truth;
  guess.Omega *= 1.2;
  const fit::Unknown unknowns[] = {{"initial.omega"}};
  fit::FitOptions options;
  options.dt = h;
  options.t_end = T;
  double iterations = 0, integrations = 0, error = 0;
  for (auto _ : state) {
    const auto r = fit::fit_observations<Method, 8>(top, guess, unknowns, obs, options);
    benchmark::DoNotOptimize(r.final_cost);
    iterations += r.iterations;
    integrations += static_cast<double>(r.integrations);
    error = std::max(error, (r.initial.Omega - truth.Omega).cwiseAbs().maxCoeff());
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["solver_iterations"] = iterations / n;
  state.counters["integrations"] = integrations / n;
  state.counters["time_per_iteration"] =
      benchmark::Counter(iterations, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["omega0_error"] = error;
}
BENCHMARK(BM_FitOmega0<Lgvi>)->Name("fit_omega0/lgvi")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitOmega0<Rkmk4>)->Name("fit_omega0/rkmk4")->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
