// tests/core/dispatch_fma_control.cpp — the negative control of test_dispatch: the splitting steps compiled with FMA
// contraction (-mavx2 -mfma -ffp-contract=fast at -O2, tests/CMakeLists.txt), as a dispatched copy would be if its
// flags allowed contraction. A program of its own, so that none of its inline functions can stand in for the
// baseline's at link time. It runs split_dmv for 3000 steps of h = 0.01 on the skew top of test_problems.hpp and
// writes the final R and Ω as 12 hexadecimal bit patterns, one a line; test_dispatch compares them with its own run.
#include "test_problems.hpp"

#include <lgi/integrators/splitting.hpp>

#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstring>

int main() {
  const lgi::HeavyTop<double> top = lgi::test::skew_heavy_top();
  lgi::SplitDmv<lgi::HeavyTop<double>> stepper(top);
  auto y = stepper.to_internal(lgi::test::skew_initial_state(), 0.0);
  for (int n = 0; n < 3000; ++n)
    if (stepper.step_inline(y, n * 0.01, 0.01) != lgi::StepStatus::ok) return 1;
  const lgi::State<double> x = stepper.to_state(y);
  for (int i = 0; i < 12; ++i) {
    const double v = i < 9 ? x.R.data()[i] : x.Omega[i - 9];
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    std::printf("%016" PRIx64 "\n", bits);
  }
  return 0;
}
