// tests/figures.hpp — the figures the documentation publishes, measured by the tests and held to bounds close to them.
//
// expect_figure(name, measured, bound) prints one line
//     [figure] <name>: measured <measured>, bound <bound>
// and expects measured ≤ bound (a NaN fails); expect_figure_at_least, measured ≥ bound. A bound is within a small factor of what is measured — at most 5,
// wide enough for the rounding that differs between machines and libm versions — so that a regression of the
// figure fails the test rather than hiding under a bound sized for another case. scripts/validation_table.py
// collects these lines from a ctest log into the table of docs/validation.md, so the published figure is the one
// last measured.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace lgi::test {

inline void expect_figure(const std::string& name, double measured, double bound) {
  std::printf("[figure] %s: measured %.3g, bound %.3g\n", name.c_str(), measured, bound);
  EXPECT_LE(measured, bound) << name;
}

// A figure that must stay at or above `bound` (a factor gained, a count of steps saved): prints
// "[figure] <name>: measured <measured>, bound >= <bound>".
inline void expect_figure_at_least(const std::string& name, double measured, double bound) {
  std::printf("[figure] %s: measured %.3g, bound >= %.3g\n", name.c_str(), measured, bound);
  EXPECT_GE(measured, bound) << name;
}

// The bound on ‖RᵀR − I‖_F after `updates` multiplications of R by an orthogonal factor (R exp(hû), R cay(hû), the
// LGVI's R F): each rounds R off the group by O(ε) in a direction of its own, so the departure is a random walk,
// ≈ c ε √updates with c = 0.4 … 0.9 measured on the long runs of the tests (RKMK family, LGVI, compositions);
// bound 2 ε √updates.
inline double orthogonality_walk_bound(double updates) {
  return 2 * std::numeric_limits<double>::epsilon() * std::sqrt(updates);
}

}  // namespace lgi::test
