// benchmarks/lgi_step_count.cpp — a plain program for counting instructions per step under callgrind.
//
//   lgi_step_count METHOD PROBLEM NSTEPS
//     METHOD   one of `lgi_step_count --list` (lgi methods by scene name; rk4quat: the hand-written
//              baseline, heavy_top only)
//     PROBLEM  heavy_top | heavy_top_tilted | free_body          (cases: bench_cases.hpp)
//   lgi_step_count --list      the methods, one per line (benchmarks/callgrind_steps.sh runs them all)
//
// Runs NSTEPS steps of h = 0.01 in periods of 1000 from the initial state, exactly as bench_steps times
// them (same loop, same DoNotOptimize sink), and prints the final state so no work can be elided.
// Start-up and set-up cost cancel in a difference of two runs: callgrind_steps.sh reports
// (Ir(N2) − Ir(N1)) / (N2 − N1).
#include "bench_cases.hpp"

#include "registry.hpp"  // apps/: every method lgi knows (lgi::app::Methods)

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <type_traits>

namespace {

void print(const lgi::State<double>& y) {
  std::printf("R = [%.17g %.17g %.17g; %.17g %.17g %.17g; %.17g %.17g %.17g]\nOmega = [%.17g %.17g %.17g]\n",
              y.R(0, 0), y.R(0, 1), y.R(0, 2), y.R(1, 0), y.R(1, 1), y.R(1, 2), y.R(2, 0), y.R(2, 1), y.R(2, 2),
              y.Omega(0), y.Omega(1), y.Omega(2));
}
void print(const bench::QuatRk4::Internal& y) {
  std::printf("q = [%.17g %.17g %.17g %.17g]\nOmega = [%.17g %.17g %.17g]\n", y.q(0), y.q(1), y.q(2), y.q(3),
              y.w(0), y.w(1), y.w(2));
}

template <class S, class P>
int run(const P& problem, long nsteps) {
  S stepper(problem);
  const auto y0 = stepper.to_internal(bench::initial_state(problem), 0.0);
  auto y = y0;
  for (long done = 0; done < nsteps; done += bench::period_steps) {
    const int n = static_cast<int>(std::min<long>(bench::period_steps, nsteps - done));
    if (!bench::run_period(stepper, y0, y, n, [](auto& x) { benchmark::DoNotOptimize(x); })) {
      std::fprintf(stderr, "lgi_step_count: step failed\n");
      return 1;
    }
  }
  if constexpr (requires { stepper.to_state(y); })
    print(stepper.to_state(y));
  else
    print(y);
  if constexpr (requires { stepper.newton_iterations(); })
    std::printf("newton_per_step = %.4f\n", static_cast<double>(stepper.newton_iterations()) / static_cast<double>(nsteps));
  return 0;
}

// Every method of the registry that applies to heavy_top (lgi list), then the hand-written baseline.
void list_methods() {
  using P = lgi::HeavyTop<double>;
  lgi::app::for_each_method<P>(lgi::app::Methods{}, [&]<template <class> class M>() {
    std::printf("%s\n", std::string(M<P>::traits.name).c_str());
  });
  std::printf("rk4quat\n");
}

template <class P>
int run_method(std::string_view method, const P& problem, long nsteps) {
  int rc = -1;
  lgi::app::for_each_method<P>(lgi::app::Methods{}, [&]<template <class> class M>() {
    if (rc < 0 && M<P>::traits.name == method) rc = run<M<P>>(problem, nsteps);
  });
  if (rc >= 0) return rc;
  if constexpr (std::is_same_v<P, lgi::HeavyTop<double>>)
    if (method == "rk4quat") return run<bench::QuatRk4>(problem, nsteps);
  std::fprintf(stderr, "lgi_step_count: unknown method '%.*s' for this problem\n", static_cast<int>(method.size()),
               method.data());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::string_view(argv[1]) == "--list") {
    list_methods();
    return 0;
  }
  if (argc != 4) {
    std::fprintf(stderr, "usage: lgi_step_count METHOD heavy_top|heavy_top_tilted|free_body NSTEPS (METHOD: see --list)\n");
    return 2;
  }
  const std::string_view method = argv[1], problem = argv[2];
  char* end = nullptr;
  const long nsteps = std::strtol(argv[3], &end, 10);
  if (*end != '\0' || nsteps <= 0) {
    std::fprintf(stderr, "lgi_step_count: NSTEPS must be a positive integer\n");
    return 2;
  }
  if (method == "rk4quat" && problem != "heavy_top") {
    std::fprintf(stderr, "lgi_step_count: rk4quat runs the heavy_top case only\n");
    return 2;
  }
  if (problem == "heavy_top") return run_method(method, bench::heavy_top_hv(), nsteps);
  if (problem == "heavy_top_tilted") return run_method(method, bench::heavy_top_tilted(), nsteps);
  if (problem == "free_body") return run_method(method, bench::free_body_hv(), nsteps);
  std::fprintf(stderr, "lgi_step_count: unknown problem '%s'\n", argv[2]);
  return 2;
}
