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

#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/integrators/splitting.hpp>
#include <lgi/integrators/commutator_free.hpp>
#include <lgi/integrators/composition.hpp>
#include <lgi/integrators/split_exact.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string_view>
#include <type_traits>

namespace {

// Every method run_method knows, in its order (--list).
constexpr const char* method_names[] = {
    "lgvi", "rkmk4", "lie_euler", "split_axes", "split_dmv", "split_dmv4", "split_dmv6", "split_dmv8", "split_dmv10",
    "split_exact", "cf4", "cg3", "lgvi_yoshida4", "lgvi_suzuki4", "lgvi_yoshida6", "lgvi_kahan_li6", "lgvi_yoshida8",
    "lgvi_kahan_li8", "lgvi_sofroniou_spaletta10", "split_dmv_yoshida4", "split_dmv_suzuki4", "split_dmv_kahan_li6",
    "split_dmv_kahan_li8", "split_dmv_sofroniou_spaletta10", "rk4quat"};

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

template <class P>
int run_method(std::string_view method, const P& problem, long nsteps) {
  if (method == "lgvi") return run<lgi::Lgvi<P>>(problem, nsteps);
  if (method == "rkmk4") return run<lgi::Rkmk4<P>>(problem, nsteps);
  if (method == "lie_euler") return run<lgi::LieEuler<P>>(problem, nsteps);
  if (method == "split_axes") return run<lgi::SplitAxes<P>>(problem, nsteps);
  if (method == "split_dmv") return run<lgi::SplitDmv<P>>(problem, nsteps);
  if (method == "split_dmv4") return run<lgi::SplitDmv4<P>>(problem, nsteps);
  if (method == "split_dmv6") return run<lgi::SplitDmv6<P>>(problem, nsteps);
  if (method == "split_dmv8") return run<lgi::SplitDmv8<P>>(problem, nsteps);
  if (method == "split_dmv10") return run<lgi::SplitDmv10<P>>(problem, nsteps);
  if (method == "split_exact") return run<lgi::SplitExact<P>>(problem, nsteps);
  if (method == "cf4") return run<lgi::Cf4<P>>(problem, nsteps);
  if (method == "cg3") return run<lgi::Cg3<P>>(problem, nsteps);
  if (method == "lgvi_yoshida4") return run<lgi::LgviYoshida4<P>>(problem, nsteps);
  if (method == "lgvi_suzuki4") return run<lgi::LgviSuzuki4<P>>(problem, nsteps);
  if (method == "lgvi_yoshida6") return run<lgi::LgviYoshida6<P>>(problem, nsteps);
  if (method == "lgvi_kahan_li6") return run<lgi::LgviKahanLi6<P>>(problem, nsteps);
  if (method == "lgvi_yoshida8") return run<lgi::LgviYoshida8<P>>(problem, nsteps);
  if (method == "lgvi_kahan_li8") return run<lgi::LgviKahanLi8<P>>(problem, nsteps);
  if (method == "lgvi_sofroniou_spaletta10") return run<lgi::LgviSofroniouSpaletta10<P>>(problem, nsteps);
  if (method == "split_dmv_yoshida4") return run<lgi::SplitDmvYoshida4<P>>(problem, nsteps);
  if (method == "split_dmv_suzuki4") return run<lgi::SplitDmvSuzuki4<P>>(problem, nsteps);
  if (method == "split_dmv_kahan_li6") return run<lgi::SplitDmvKahanLi6<P>>(problem, nsteps);
  if (method == "split_dmv_kahan_li8") return run<lgi::SplitDmvKahanLi8<P>>(problem, nsteps);
  if (method == "split_dmv_sofroniou_spaletta10") return run<lgi::SplitDmvSofroniouSpaletta10<P>>(problem, nsteps);
  if constexpr (std::is_same_v<P, lgi::HeavyTop<double>>)
    if (method == "rk4quat") return run<bench::QuatRk4>(problem, nsteps);
  std::fprintf(stderr, "lgi_step_count: unknown method '%.*s' for this problem\n", static_cast<int>(method.size()),
               method.data());
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 2 && std::string_view(argv[1]) == "--list") {
    for (const char* name : method_names) std::printf("%s\n", name);
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
