// benchmarks/bench_free_body_exact.cpp — ns per call of the free body's exact solution (problems/free_body_exact.hpp).
//
// The Hairer–Vilmart body J = diag(0.6, 0.8, 1), m0 = (1.8, 0.4, −0.9) (axis-1 regime):
//   flow/W            flow(y, 0.01) with its constants in W (double, long double), recomputed from y each call as
//                     a splitting needs (split_exact); y continues from call to call
//   state_short/W     state(t) of a solved Solution, t cycling through 0 … 0.49
//   state_long/W      state(t) at t ≈ 1e3 (larger arguments of the elliptic functions and of the θ quadrature)
//   exact_step/T      the method `exact` (integrators/exact.hpp): one step's evaluation at t ≈ T (10, 1e3, 1e4) from the
//                     initial state, its solution cached by the stepper (constants and evaluation in double)
//   boost_jacobi      Boost's jacobi_elliptic(0.7, u) alone, double with its default policy (promotes to long
//                     double): the special function the solution evaluates
//
// Run (the machine is shared and noisy: quote medians, and ratios from one run):
//   build/benchmarks/bench_free_body_exact --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
#include <lgi/integrators/exact.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/free_body_exact.hpp>

#include <benchmark/benchmark.h>
#include <boost/math/special_functions/jacobi_elliptic.hpp>

namespace {

using lgi::Mat3;
using lgi::MomentumState;
using lgi::Vec3;

const Mat3<double> kInertia = Vec3<double>(0.6, 0.8, 1.0).asDiagonal();
const MomentumState<double> kStart{Mat3<double>::Identity(), Vec3<double>(1.8, 0.4, -0.9)};

template <class W>
void flow(benchmark::State& state) {
  const lgi::FreeBodyExact<double, W> exact(kInertia);
  MomentumState<double> y = kStart;
  for (auto _ : state) {
    y = exact.flow(y, 0.01);
    benchmark::DoNotOptimize(y);
  }
}

template <class W>
void state_at(benchmark::State& state, double t0, double dt, int cycle) {
  const lgi::FreeBodyExact<double, W> exact(kInertia);
  const auto solution = exact.solve(kStart);
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(solution.state(t0 + dt * (i % cycle)));
    ++i;
  }
}

void exact_step(benchmark::State& state, double T) {
  lgi::ExactFreeBody<lgi::FreeBody<double>> method(lgi::FreeBody<double>{kInertia});
  const lgi::State<double> x0{kStart.R, Vec3<double>(kInertia.inverse() * kStart.Pi)};
  auto y = method.to_internal(x0, 0.0);
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(method.step(y, T + 0.01 * (i++ % 1000), 0.01));
    benchmark::DoNotOptimize(y);
  }
}

void boost_jacobi(benchmark::State& state) {
  int i = 0;
  for (auto _ : state) {
    double cn, dn;
    const double sn = boost::math::jacobi_elliptic(0.7, 1e-3 * (i++ % 20000), &cn, &dn);
    benchmark::DoNotOptimize(sn + cn + dn);
  }
}

void state_short_double(benchmark::State& s) { state_at<double>(s, 0.0, 0.01, 50); }
void state_short_long_double(benchmark::State& s) { state_at<long double>(s, 0.0, 0.01, 50); }
void state_long_double(benchmark::State& s) { state_at<double>(s, 1e3, 1.0, 1000); }
void state_long_long_double(benchmark::State& s) { state_at<long double>(s, 1e3, 1.0, 1000); }

BENCHMARK(flow<double>)->Name("flow/double");
BENCHMARK(flow<long double>)->Name("flow/long_double");
BENCHMARK(state_short_double)->Name("state_short/double");
BENCHMARK(state_short_long_double)->Name("state_short/long_double");
BENCHMARK(state_long_double)->Name("state_long/double");
BENCHMARK(state_long_long_double)->Name("state_long/long_double");
BENCHMARK_CAPTURE(exact_step, 10, 10.0)->Name("exact_step/10");
BENCHMARK_CAPTURE(exact_step, 1e3, 1e3)->Name("exact_step/1e3");
BENCHMARK_CAPTURE(exact_step, 1e4, 1e4)->Name("exact_step/1e4");
BENCHMARK(boost_jacobi);

}  // namespace

BENCHMARK_MAIN();
