// benchmarks/exp_count.cpp — a plain program for callgrind: the cost of so3::exp_coefficients where it takes sin
// (0.1 ≤ θ ≤ π: core/trig.hpp's polynomial sin), and of RKMK4 steps that take it.
//
//   exp_count exp N          N calls of so3::exp_coefficients, θ cycling through [0.1, π) in 1000 steps
//   exp_count rkmk4 N        N RKMK4 steps of the Hairer–Vilmart heavy top at h = 0.05, JΩ0 = 3 (1.8, 0.4, −0.9)
//                            (|Ω| ≈ 9: stage and update angles 0.2–0.5), from the initial state every 1000 steps
//   exp_count rkmk4_small N  the same at h = 0.01 and JΩ0 = (1.8, 0.4, −0.9) (θ ≈ 0.03: the Taylor branch, as
//                            benchmarks/lgi_step_count)
//
// Instructions per call or step: (Ir(N2) − Ir(N1)) / (N2 − N1) of two runs under valgrind --tool=callgrind
// (start-up cancels), e.g. N1 = 10000, N2 = 110000 for exp and 1000, 11000 for rkmk4 (whole periods of 1000).
#include <lgi/core/so3.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
  const std::string mode = argc == 3 ? argv[1] : "";
  if (mode != "exp" && mode != "rkmk4" && mode != "rkmk4_small") {
    std::fprintf(stderr, "usage: exp_count exp|rkmk4|rkmk4_small N\n");
    return 2;
  }
  const long n = std::atol(argv[2]);
  double sink = 0;
  if (mode == "exp") {
    const lgi::Vec3<double> axis(0.36, -0.48, 0.8);
    for (long i = 0; i < n; ++i) {
      const double theta = 0.1 + (3.14159 - 0.1) * static_cast<double>(i % 1000) / 1000.0;
      const lgi::so3::Coefficients<double> k = lgi::so3::exp_coefficients(lgi::Vec3<double>(theta * axis));
      sink += k.A + k.B;
    }
  } else {
    const bool small = mode == "rkmk4_small";
    const double h = small ? 0.01 : 0.05, scale = small ? 1.0 : 3.0;
    lgi::Rkmk4<lgi::HeavyTop<double>> stepper(lgi::HeavyTop<double>::hairer_vilmart());
    lgi::State<double> x0;
    x0.Omega = lgi::Vec3<double>(scale * 1.8 / 0.6, scale * 0.4 / 0.8, -scale * 0.9);
    lgi::State<double> x = x0;
    for (long i = 0; i < n; ++i) {
      if (i % 1000 == 0) x = x0;
      stepper.step(x, 0.0, h);
      sink += x.Omega(0);
    }
  }
  std::printf("%.17g\n", sink);
  return 0;
}
