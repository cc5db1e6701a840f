// lgi/integrators/butcher_tableaus.hpp — explicit Runge–Kutta coefficients, as constexpr data.
//
// Each tableau carries the name under which its RKMK method is known to scenes, its classical order,
// and its reference. Adding an explicit method to lgi is adding a tableau here and one alias in rkmk.hpp.
#pragma once

#include <array>
#include <string_view>

namespace lgi {

template <int S>
struct ButcherTableau {
  static constexpr int stages = S;
  std::string_view name;   // RKMK method name in scenes
  std::string_view title;
  int order;
  std::array<std::array<double, S>, S> a;  // strictly lower triangular (explicit)
  std::array<double, S> b;
  std::array<double, S> c;
  std::string_view reference;
};

namespace tableaus {

// Forward Euler: order 1. As an RKMK method it is the Lie–Euler method R⁺ = R exp(hΩ), Ω⁺ = Ω + hΩ'
// (Hairer–Lubich–Wanner, GNI 2nd ed., §IV.8.2, after Theorem 8.5).
inline constexpr ButcherTableau<1> euler{
    .name = "lie_euler",
    .title = "Lie-Euler (RKMK with forward Euler)",
    .order = 1,
    .a = {{{0.0}}},
    .b = {1.0},
    .c = {0.0},
    .reference = "Hairer-Lubich-Wanner GNI, sec. IV.8.2",
};

// The classical fourth-order method of Kutta (1901); Hairer, Nørsett, Wanner, Solving ODEs I, Table II.1.2.
inline constexpr ButcherTableau<4> classical_rk4{
    .name = "rkmk4",
    .title = "Runge-Kutta-Munthe-Kaas, classical RK4",
    .order = 4,
    .a = {{{0.0, 0.0, 0.0, 0.0}, {0.5, 0.0, 0.0, 0.0}, {0.0, 0.5, 0.0, 0.0}, {0.0, 0.0, 1.0, 0.0}}},
    .b = {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6},
    .c = {0.0, 0.5, 0.5, 1.0},
    .reference = "Munthe-Kaas, BIT 38 (1998) 92; Hairer-Lubich-Wanner GNI, Algorithm IV.8.3",
};

}  // namespace tableaus
}  // namespace lgi
