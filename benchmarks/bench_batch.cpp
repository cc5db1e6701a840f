// benchmarks/bench_batch.cpp — ns per body-step of the batched kick + LGVI and RKMK4 on the heavy top.
//
// N Hairer–Vilmart heavy tops (J = diag(0.6, 0.8, 1), b = 1, k = z0 = e3), uniformly random attitudes, body
// momenta JΩ in random directions with |JΩ| uniform in [0.5, 2] × |(1.8, 0.4, −0.9)| (the bench_steps body),
// h = 0.01; one benchmark iteration is one integrate_batch_lgvi (integrate_batch_rkmk4) call of `steps_per_call`
// steps for every body, continuing from where the previous iteration stopped. Methods: lgvi_heavy_top (kick +
// LGVI, integrators/batch_lgvi.hpp) and rkmk4_heavy_top (integrators/batch_rkmk.hpp). Kernels
// (integrators/batch_kernels.hpp):
//   per_body   the single-body stepper per body (integrate_batch<Lgvi>, <Rkmk4>): the scalar reference
//   baseline   lane blocks of 4, the build's flags (x86-64: SSE2)
//   avx2       lane blocks of 8, lgi::batch's AVX2 translation unit (skipped without AVX2+FMA)
//   avx512     lane blocks of 16, lgi::batch's AVX-512 translation unit (skipped without AVX-512F+DQ)
// each with 1 and 2 threads, for N = 4096 and 65536. The counter s_per_body_step (shown in ns) is the figure to quote.
//
// Run (the machine is shared and noisy: quote medians, and ratios from one run):
//   build/benchmarks/bench_batch --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
// Instructions per body-step under callgrind (no Google Benchmark loop): the plain mode
//   bench_batch --once KERNEL N STEPS [METHOD]   (KERNEL: per_body | baseline | avx2 | avx512; METHOD: lgvi
//                                                 (default) | rkmk4; 1 thread; valgrind cannot run AVX-512 code)
// run at two STEPS values; (Ir(S2) − Ir(S1)) / (N (S2 − S1)) is the per-body-step count.
#include <lgi/core/batch.hpp>
#include <lgi/core/so3.hpp>
#include <lgi/integrators/batch_lgvi.hpp>
#include <lgi/integrators/batch_rkmk.hpp>

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>

namespace {

constexpr double h = 0.01;
constexpr std::int64_t steps_per_call = 16;

lgi::BodyBatch ensemble(std::size_t n) {
  const lgi::HeavyTop<double> top = lgi::HeavyTop<double>::hairer_vilmart();
  std::mt19937_64 gen(2026);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> unit(0, 1);
  const double m_hv = lgi::Vec3<double>(1.8, 0.4, -0.9).norm();
  lgi::BodyBatch batch(n);
  for (std::size_t i = 0; i < n; ++i) {
    lgi::State<double> x;
    const lgi::Vec3<double> axis(normal(gen), normal(gen), normal(gen));
    x.R = lgi::so3::exp(lgi::Vec3<double>(axis.normalized() * (3.14159 * unit(gen))));
    const lgi::Vec3<double> dir(normal(gen), normal(gen), normal(gen));
    const lgi::Vec3<double> m = dir.normalized() * (m_hv * (0.5 + 1.5 * unit(gen)));
    x.Omega = top.inertia.inverse() * m;
    batch.set_state(i, x);
  }
  return batch;
}

lgi::BatchKernel kernel_of(const std::string& name) {
  if (name == "per_body") return lgi::BatchKernel::per_body;
  if (name == "baseline") return lgi::BatchKernel::baseline;
  if (name == "avx2") return lgi::BatchKernel::avx2;
  if (name == "avx512") return lgi::BatchKernel::avx512;
  std::fprintf(stderr, "bench_batch: unknown kernel '%s' (per_body, baseline, avx2, avx512)\n", name.c_str());
  std::exit(2);
}

enum class Method { lgvi, rkmk4 };

lgi::BatchKernel run(Method method, lgi::BodyBatch& batch, std::int64_t steps, lgi::BatchKernel kernel, int threads) {
  const lgi::HeavyTop<double> top = lgi::HeavyTop<double>::hairer_vilmart();
  if (method == Method::lgvi) return lgi::integrate_batch_lgvi(top, batch, 0.0, h, steps, {}, {.threads = threads}, {}, kernel);
  return lgi::integrate_batch_rkmk4(top, batch, 0.0, h, steps, {}, {.threads = threads}, {}, kernel);
}

void bm_batch(benchmark::State& st, Method method, lgi::BatchKernel kernel, std::size_t n, int threads) {
  if (!lgi::batch_kernel_available(kernel)) {
    st.SkipWithError((std::string(lgi::to_string(kernel)) + " kernel not available").c_str());
    return;
  }
  lgi::BodyBatch batch = ensemble(n);
  for (auto _ : st) {
    run(method, batch, steps_per_call, kernel, threads);
    benchmark::ClobberMemory();
  }
  for (std::size_t i = 0; i < n; ++i)
    if (batch.status[i] != lgi::StepStatus::ok) {
      st.SkipWithError("a body failed");
      return;
    }
  const double body_steps = static_cast<double>(st.iterations()) * static_cast<double>(n) * steps_per_call;
  st.SetItemsProcessed(static_cast<std::int64_t>(body_steps));
  // Seconds per body-step (printed with a unit, e.g. 12.3ns); in JSON the value is in seconds.
  st.counters["s_per_body_step"] = benchmark::Counter(body_steps, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

}  // namespace

int main(int argc, char** argv) {
  if ((argc == 5 || argc == 6) && std::string(argv[1]) == "--once") {  // for callgrind
    const lgi::BatchKernel kernel = kernel_of(argv[2]);
    const auto n = static_cast<std::size_t>(std::atol(argv[3]));
    const std::int64_t steps = std::atol(argv[4]);
    const std::string m = argc == 6 ? argv[5] : "lgvi";
    if (m != "lgvi" && m != "rkmk4") {
      std::fprintf(stderr, "bench_batch: unknown method '%s' (lgvi, rkmk4)\n", m.c_str());
      return 2;
    }
    lgi::BodyBatch batch = ensemble(n);
    run(m == "lgvi" ? Method::lgvi : Method::rkmk4, batch, steps, kernel, 1);
    double sum = 0;
    for (std::size_t i = 0; i < n; ++i) sum += batch.Omega[0][i];
    std::printf("sum_omega0 %.17g\n", sum);
    return 0;
  }
  for (const Method method : {Method::lgvi, Method::rkmk4})
    for (const char* name : {"per_body", "baseline", "avx2", "avx512"})
      for (const std::size_t n : {std::size_t{4096}, std::size_t{65536}})
        for (const int threads : {1, 2}) {
          const lgi::BatchKernel kernel = kernel_of(name);
          benchmark::RegisterBenchmark((std::string(method == Method::lgvi ? "lgvi_heavy_top/" : "rkmk4_heavy_top/") +
                                        name + "/N:" + std::to_string(n) + "/threads:" + std::to_string(threads))
                                           .c_str(),
                                       [=](benchmark::State& st) { bm_batch(st, method, kernel, n, threads); })
              ->Unit(benchmark::kMillisecond)
              ->UseRealTime();
        }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
