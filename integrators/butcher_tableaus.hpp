/// \file
/// lgi/integrators/butcher_tableaus.hpp — explicit Runge–Kutta coefficients, as constexpr data.
///
/// Each tableau carries the name under which its RKMK method is known to scenes, its classical order,
/// and its reference. Adding an explicit method to lgi is adding a tableau here and one alias in rkmk.hpp.
///
/// ~~~{.unparsed}
///   ButcherTableau<S>        a, b, c of an explicit method: Euler (1), Heun (2), Kutta 3 (3), classical
///                            RK4 and the 3/8 rule (4)
///   EmbeddedTableau<S, SE, D, C = double>  an embedded pair with its error weights e = b − b̂ and a continuous
///                            extension (dense output, degree D): Dormand–Prince 5(4), DOP853 8(5,3), Verner's 9(8);
///                            Verner's 8(7) is here as checked data but not offered as a method (see it below)
/// ~~~
///
/// Every coefficient set is checked against the Runge–Kutta order conditions (all rooted trees up to the
/// declared order, evaluated numerically) in tests/integrators/test_rkmk_family.cpp, and by observed order.
///
/// The tableaus the methods use are doubles (tableaus::dop853, verner9 and the rest), also when a method runs in
/// long double: the order conditions then hold only to ~1e-16 (e.g. Σ b_i − 1 of DOP853 and of 1/6, 1/3, 1/3, 1/6
/// in double; 1.3e-16 for Verner 9(8)), which adds an error of ~1e-16 per unit time to a long-double run, a floor
/// that the order fits of tests/order_measure.hpp stay above (docs/findings.md).
/// DOP853 and Verner 9(8) are also variable templates over the coefficient type C, `dop853_in<C>` and
/// `verner9_in<C>`, each literal written LGI_RK(…): C = double gives the compiler's double of each literal (the
/// double tableaus are `dop853_in<double>` and `verner9_in<double>`, the same bits as plain literals); another C gets
/// the literal's text parsed in C (tableaus::detail::coefficient): binary128 (__float128) to within one unit in
/// its last place, or a class type with its own C::from_decimal. Verner's 40 digits then hold his order
/// conditions to 4.1e-34 in binary128 and 3.2e-40 in 50 digits, DOP853's 28–30 digits (dop853.f) to 2.9e-29:
/// what tests/integrators/test_quad_order.cpp needs to measure the orders of rkmk_vern9_cayley and rkmk_dp8_cayley
/// beyond the double floor. Nothing here uses __float128 or Boost; the methods take such a tableau as they take any
/// (`Rkmk<tableaus::verner9_in<__float128>, P, −1, LieChart::cayley>` with P's scalar
/// boost::multiprecision::float128).
#pragma once

#include <array>
#include <string_view>
#include <type_traits>
#include <utility>

namespace lgi {

/// An explicit Runge–Kutta method of S stages (a, b, c) as data: Rkmk and EuclideanRk apply it.
template <int S>
struct ButcherTableau {
  static constexpr int stages = S;  ///< S
  std::string_view name;   ///< RKMK method name in scenes
  std::string_view title;  ///< a one-line description
  int order;               ///< the classical order
  std::array<std::array<double, S>, S> a;  ///< strictly lower triangular (explicit)
  std::array<double, S> b;                 ///< the weights
  std::array<double, S> c;                 ///< the nodes: stage i at t + c_i h
  std::string_view reference;              ///< the paper or book
};

/// Method coefficients as constexpr data: Butcher tableaus and embedded pairs (this header), commutator-free
/// tableaus (commutator_free.hpp).
namespace tableaus {

/// Forward Euler: order 1. As an RKMK method it is the Lie–Euler method R⁺ = R exp(hΩ), Ω⁺ = Ω + hΩ'
/// (Hairer–Lubich–Wanner, GNI 2nd ed., §IV.8.2, after Theorem 8.5).
inline constexpr ButcherTableau<1> euler{
    .name = "lie_euler",
    .title = "Lie-Euler (RKMK with forward Euler)",
    .order = 1,
    .a = {{{0.0}}},
    .b = {1.0},
    .c = {0.0},
    .reference = "Hairer-Lubich-Wanner GNI, sec. IV.8.2",
};

/// The classical fourth-order method of Kutta (1901); Hairer, Nørsett, Wanner, Solving ODEs I, Table II.1.2.
inline constexpr ButcherTableau<4> classical_rk4{
    .name = "rkmk4",
    .title = "Runge-Kutta-Munthe-Kaas, classical RK4",
    .order = 4,
    .a = {{{0.0, 0.0, 0.0, 0.0}, {0.5, 0.0, 0.0, 0.0}, {0.0, 0.5, 0.0, 0.0}, {0.0, 0.0, 1.0, 0.0}}},
    .b = {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6},
    .c = {0.0, 0.5, 0.5, 1.0},
    .reference = "Munthe-Kaas, BIT 38 (1998) 92; Hairer-Lubich-Wanner GNI, Algorithm IV.8.3",
};

/// Heun's method (the explicit trapezoidal rule): order 2. K. Heun, Z. Math. Phys. 45 (1900) 23–38;
/// Hairer, Nørsett, Wanner, Solving ODEs I, 2nd ed., §II.1 (its table number there not confirmed: the book
/// was not available to us).
inline constexpr ButcherTableau<2> heun{
    .name = "rkmk_heun",
    .title = "Runge-Kutta-Munthe-Kaas, Heun (explicit trapezoidal rule)",
    .order = 2,
    .a = {{{0.0, 0.0}, {1.0, 0.0}}},
    .b = {0.5, 0.5},
    .c = {0.0, 1.0},
    .reference = "Heun, Z. Math. Phys. 45 (1900) 23; Munthe-Kaas, BIT 38 (1998) 92",
};

/// Kutta's third-order method: c = (0, 1/2, 1), a21 = 1/2, a31 = −1, a32 = 2, b = (1/6, 2/3, 1/6).
/// W. Kutta, Z. Math. Phys. 46 (1901) 435–453; Hairer, Nørsett, Wanner, Solving ODEs I, §II.1 (its
/// table number there not confirmed: the book was not available to us).
inline constexpr ButcherTableau<3> kutta3{
    .name = "rkmk3",
    .title = "Runge-Kutta-Munthe-Kaas, Kutta's third-order method",
    .order = 3,
    .a = {{{0.0, 0.0, 0.0}, {0.5, 0.0, 0.0}, {-1.0, 2.0, 0.0}}},
    .b = {1.0 / 6, 2.0 / 3, 1.0 / 6},
    .c = {0.0, 0.5, 1.0},
    .reference = "Kutta, Z. Math. Phys. 46 (1901) 435; Munthe-Kaas, BIT 38 (1998) 92",
};

/// Kutta's 3/8 rule: order 4. Kutta (1901); Hairer, Nørsett, Wanner, Solving ODEs I, Table II.1.2 (right).
inline constexpr ButcherTableau<4> rule38{
    .name = "rkmk4_38",
    .title = "Runge-Kutta-Munthe-Kaas, Kutta's 3/8 rule",
    .order = 4,
    .a = {{{0.0, 0.0, 0.0, 0.0}, {1.0 / 3, 0.0, 0.0, 0.0}, {-1.0 / 3, 1.0, 0.0, 0.0}, {1.0, -1.0, 1.0, 0.0}}},
    .b = {1.0 / 8, 3.0 / 8, 3.0 / 8, 1.0 / 8},
    .c = {0.0, 1.0 / 3, 2.0 / 3, 1.0},
    .reference = "Kutta, Z. Math. Phys. 46 (1901) 435; Hairer-Norsett-Wanner I, Table II.1.2; Munthe-Kaas, BIT 38 (1998) 92",
};

}  // namespace tableaus

// ---- Embedded pairs with a continuous extension ------------------------------------------------------
///
/// An explicit pair (b of order p, b̂ of a lower order) with dense output. The layout extends ButcherTableau:
/// `stages` stages make a step and its error estimate; `dense_stages` ≥ `stages` adds the stages the
/// continuous extension needs (the first-same-as-last stage at the new point, and DOP853's three extra ones,
/// Verner's seven or nine), and `dense_degree` D is the degree of its weight polynomials (8 by default; 9 for
/// Verner's order-9 interpolant).
///
/// ~~~{.unparsed}
///   step:            y₁ = y₀ + h Σ_{i<stages} b_i k_i
///   error estimate:  δ = h Σ e_i k_i with e = b − b̂; DOP853 has a second one, δ₃ = h Σ e3_i k_i (else e3 = 0)
///   dense output:    y(t₀ + θh) = y₀ + h Σ_{i<dense_stages} b_i(θ) k_i,   b_i(θ) = Σ_{m=1..D} dense[i][m−1] θ^m
/// ~~~
///
/// The dense weights are built (constexpr) from the published Hermite-type form of Hairer's codes DOPRI5 and
/// DOP853, with s = θ, s' = 1 − θ, y₁ − y₀ = h Σ b_i k_i, k_f the stage at the new point (index `fsal`):
/// ~~~{.unparsed}
///   y(θ) = y₀ + s(r₁ + s'(r₂ + s(r₃ + s'(r₄ + s(r₅ + s'(r₆ + s r₇))))))
///   r₁ = y₁ − y₀,  r₂ = h k₁ − r₁,  r₃ = r₁ − h k_f − r₂ = 2r₁ − h(k₁ + k_f),  r_{3+j} = h Σ_i d[j][i] k_i.
/// ~~~
template <int S, int SE, int D = 8, class C = double>
struct EmbeddedTableau {
  using Coefficient = C;                   ///< the coefficients' type (double, or wider for extended precision)
  static constexpr int stages = S;         ///< stages of a step and its error estimate
  static constexpr int dense_stages = SE;  ///< stages including those of the continuous extension
  static constexpr int dense_degree = D;   ///< the degree D of the dense weight polynomials
  std::string_view name;                   ///< RKMK method name in scenes
  std::string_view title;                  ///< a one-line description
  int order;            ///< of b
  int embedded_order;   ///< of b̂ = b − e
  int dense_order;      ///< of the continuous extension
  int control_order;    ///< k in the step-size rule h ∝ err^(−1/k) (the estimate behaves like h^k)
  std::array<std::array<C, SE>, SE> a;  ///< strictly lower triangular; rows ≥ S: dense-output stages
  std::array<C, S> b;   ///< the weights of the solution, order `order`
  std::array<C, SE> c;  ///< the nodes, dense-output stages included
  std::array<C, S> e;   ///< b − b̂
  std::array<C, S> e3;  ///< DOP853: b − b̂₃ (third order); zero otherwise
  int fsal;             ///< index of the stage at the new point (a[fsal] = b)
  std::array<std::array<C, D>, SE> dense;  ///< b_i(θ) = Σ_{m=1..D} dense[i][m−1] θ^m
  std::string_view reference;              ///< the papers and codes
};

namespace tableaus::detail {

// 10^k in C by repeated multiplication: exact while 5^k fits C's significand (k ≤ 48 in binary128, 27 in
// x87 long double, 22 in double).
template <class C>
constexpr C power_of_ten(int k) {
  C p = C(1);
  for (int i = 0; i < k; ++i) p *= C(10);
  return p;
}

// The digits of a decimal literal's text ("-0.0389…", "5.26…e-2"): its first 57 significant digits as three
// exact integers of at most 19 digits, value = ±((chunk₀·10^length₁ + chunk₁)·10^length₂ + chunk₂)·10^exponent
// (digits past the 57th are dropped, those before the point counted in the exponent). Shared by parse_decimal
// and the multi-word coefficient of tests/quad_measure.hpp.
struct DecimalDigits {
  bool negative = false;
  unsigned long long chunk[3] = {0, 0, 0};
  int length[3] = {0, 0, 0};
  int exponent = 0;
};

constexpr DecimalDigits scan_decimal(const char* s) {
  DecimalDigits r;
  if (*s == '-' || *s == '+') r.negative = *s++ == '-';
  int k = 0;
  bool point = false, significant = false;
  for (; *s != '\0' && *s != 'e' && *s != 'E'; ++s) {
    if (*s == '.') {
      point = true;
      continue;
    }
    const int d = *s - '0';
    significant = significant || d != 0;
    if (!significant) {  // a leading zero
      if (point) --r.exponent;
    } else if (k < 3) {
      r.chunk[k] = 10 * r.chunk[k] + static_cast<unsigned long long>(d);
      if (++r.length[k] == 19) ++k;
      if (point) --r.exponent;
    } else if (!point) {  // a digit past the 57th, before the point
      ++r.exponent;
    }
  }
  if (*s == 'e' || *s == 'E') {
    ++s;
    bool negative_exponent = false;
    if (*s == '-' || *s == '+') negative_exponent = *s++ == '-';
    int e = 0;
    for (; *s != '\0'; ++s) e = 10 * e + (*s - '0');
    r.exponent += negative_exponent ? -e : e;
  }
  return r;
}

// A decimal literal's text parsed in C's arithmetic: the first 38 significant digits as two exact integers
// (≤ 19 digits each), m = head·10^n + tail (head·10^n is exact in binary128: 64 + 45 bits), then m/10^k or m·10^k
// — two roundings in binary128, so within one unit in the last place of the correctly rounded value (digits
// past the 38th are below 10⁻³⁷ relative and dropped). tests/integrators/test_quad_order.cpp, DecimalParsersAgree,
// checks that bound on every entry of Verner 9(8)'s tableau (how many come out correctly rounded:
// docs/findings.md).
template <class C>
constexpr C parse_decimal(const char* s) {
  const DecimalDigits d = scan_decimal(s);
  const int exponent = d.exponent + d.length[2];  // the third chunk dropped
  C m = C(d.chunk[0]);
  if (d.length[1] > 0) m = m * power_of_ten<C>(d.length[1]) + C(d.chunk[1]);
  const C v = exponent < 0 ? m / power_of_ten<C>(-exponent) : m * power_of_ten<C>(exponent);
  return d.negative ? -v : v;
}

// A tableau coefficient written as the literal x in the source, `text` its spelling (LGI_RK below). For
// C = double, x itself: the compiler's rounding of the literal, so the double tableaus are, bit for bit, the
// arrays of plain double literals they were. For a class type with a constexpr C::from_decimal(text), that
// (a multi-word coefficient that keeps all the digits: tests/quad_measure.hpp). For other C (binary128, long
// double) the text parsed in C, so that the coefficients are as accurate as C where the source has the digits
// (Verner's 40, DOP853's 28–30).
template <class C>
constexpr C coefficient(double x, const char* text) {
  if constexpr (std::is_same_v<C, double>)
    return x;
  else if constexpr (requires { C::from_decimal(text); })
    return C::from_decimal(text);
  else
    return parse_decimal<C>(text);
}

using Poly = std::array<double, 9>;  // coefficients of θ⁰ … θ⁸

// θ^m (1 − θ)^n
constexpr Poly theta_power(int m, int n) {
  Poly p{};
  p[0] = 1;
  for (int k = 0; k < m; ++k) {  // × θ
    for (int i = 8; i > 0; --i) p[i] = p[i - 1];
    p[0] = 0;
  }
  for (int k = 0; k < n; ++k)  // × (1 − θ)
    for (int i = 8; i > 0; --i) p[i] -= p[i - 1];
  return p;
}

// The monomial weights b_i(θ) of the Hermite-type form above, with D = d[0..ND) the rows r₄ … r_{3+ND}.
template <int S, int SE, int ND, class C>
constexpr std::array<std::array<C, 8>, SE> hermite_dense(const std::array<C, S>& b, int fsal,
                                                          const std::array<std::array<C, SE>, ND>& d) {
  std::array<std::array<C, 8>, SE> w{};
  const auto add = [&](int term, int i, C coefficient) {  // term m: θ^⌈m/2⌉ (1 − θ)^⌊m/2⌋
    const Poly p = theta_power((term + 1) / 2, term / 2);
    for (int k = 1; k < 9; ++k) w[i][k - 1] += coefficient * C(p[k]);
  };
  for (int i = 0; i < SE; ++i) {
    const C bi = i < S ? b[i] : C(0);
    add(1, i, bi);                                                         // r₁
    add(2, i, C(i == 0 ? 1 : 0) - bi);                                     // r₂
    add(3, i, C(2) * bi - C(i == 0 ? 1 : 0) - C(i == fsal ? 1 : 0));      // r₃
    for (int j = 0; j < ND; ++j) add(4 + j, i, d[j][i]);             // r₄ …
  }
  return w;
}

}  // namespace tableaus::detail

/// LGI_RK(literal): the literal as a coefficient of type C, the tableau's coefficient type in the variable
/// templates below (tableaus::detail::coefficient). `#undef`'d at the end of this file.
#define LGI_RK(x) ::lgi::tableaus::detail::coefficient<C>(x, #x)

namespace tableaus {

namespace detail {
// Dormand–Prince 5(4) (DOPRI5), 7 stages, the 7th at the new point (first same as last).
inline constexpr std::array<double, 7> dp5_b = {35.0 / 384, 0.0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84, 0.0};
// Shampine's dense output (Math. Comp. 46 (1986) 135), the r₄ row of Hairer's DOPRI5 code.
inline constexpr std::array<std::array<double, 7>, 1> dp5_d = {{{-12715105075.0 / 11282082432, 0.0,
                                                                 87487479700.0 / 32700410799,
                                                                 -10690763975.0 / 1880347072,
                                                                 701980252875.0 / 199316789632,
                                                                 -1453857185.0 / 822651844, 69997945.0 / 29380423}}};
}  // namespace detail

/// Dormand & Prince, J. Comput. Appl. Math. 6 (1980) 19–26 (the pair RK5(4)7M); Hairer, Nørsett, Wanner,
/// Solving ODEs I, 2nd ed. (1993), §II.5 (Table 5.2 there: a number from memory, also so cited in third-party
/// code, but not checked against the 2nd edition, which was not available to us; Hairer's dopri5.f names the
/// book without section or table; the 1st edition's appendix points to its Table 4.6 of §II.4, so a table
/// number needs its edition); dense output
/// of order 4 by Shampine, Math. Comp. 46 (1986) 135–150, in the form of Hairer & Wanner's DOPRI5 code
/// (HNW I §II.6). Coefficients cross-checked against two independent transcriptions of DOPRI5 and by the
/// order conditions (tests/integrators/test_rkmk_family.cpp).
inline constexpr EmbeddedTableau<7, 7> dormand_prince5{
    .name = "rkmk_dp5",
    .title = "Runge-Kutta-Munthe-Kaas, Dormand-Prince 5(4) with dense output (adaptive with rtol/atol)",
    .order = 5,
    .embedded_order = 4,
    .dense_order = 4,
    .control_order = 5,
    .a = {{{0, 0, 0, 0, 0, 0, 0},
           {1.0 / 5, 0, 0, 0, 0, 0, 0},
           {3.0 / 40, 9.0 / 40, 0, 0, 0, 0, 0},
           {44.0 / 45, -56.0 / 15, 32.0 / 9, 0, 0, 0, 0},
           {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729, 0, 0, 0},
           {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656, 0, 0},
           {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84, 0}}},
    .b = detail::dp5_b,
    .c = {0.0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1.0, 1.0},
    .e = {71.0 / 57600, 0.0, -71.0 / 16695, 71.0 / 1920, -17253.0 / 339200, 22.0 / 525, -1.0 / 40},
    .e3 = {},
    .fsal = 6,
    .dense = tableaus::detail::hermite_dense<7, 7, 1>(detail::dp5_b, 6, detail::dp5_d),
    .reference = "Dormand-Prince, J. Comput. Appl. Math. 6 (1980) 19; dense output Shampine, Math. Comp. 46 (1986) 135; "
                 "Hairer-Norsett-Wanner I, sec. II.5-II.6; Munthe-Kaas, BIT 38 (1998) 92",
};

namespace detail {
// DOP853: 12 stages for the step, the 13th at the new point, 3 more for the order-7 dense output.
// Coefficients of Hairer & Wanner's code dop853.f, as transcribed in SciPy's
// scipy/integrate/_ivp/dop853_coefficients.py (read for this file; agrees digit for digit with the
// Numerical Recipes 3rd ed. transcription of the b, bhh, er and d values).
template <class C>
inline constexpr std::array<std::array<C, 16>, 16> dop853_a = [] {
  std::array<std::array<C, 16>, 16> A{};
  A[1][0] = LGI_RK(5.26001519587677318785587544488e-2);
  A[2][0] = LGI_RK(1.97250569845378994544595329183e-2);
  A[2][1] = LGI_RK(5.91751709536136983633785987549e-2);
  A[3][0] = LGI_RK(2.95875854768068491816892993775e-2);
  A[3][2] = LGI_RK(8.87627564304205475450678981324e-2);
  A[4][0] = LGI_RK(2.41365134159266685502369798665e-1);
  A[4][2] = LGI_RK(-8.84549479328286085344864962717e-1);
  A[4][3] = LGI_RK(9.24834003261792003115737966543e-1);
  A[5][0] = LGI_RK(3.7037037037037037037037037037e-2);
  A[5][3] = LGI_RK(1.70828608729473871279604482173e-1);
  A[5][4] = LGI_RK(1.25467687566822425016691814123e-1);
  A[6][0] = LGI_RK(3.7109375e-2);
  A[6][3] = LGI_RK(1.70252211019544039314978060272e-1);
  A[6][4] = LGI_RK(6.02165389804559606850219397283e-2);
  A[6][5] = LGI_RK(-1.7578125e-2);
  A[7][0] = LGI_RK(3.70920001185047927108779319836e-2);
  A[7][3] = LGI_RK(1.70383925712239993810214054705e-1);
  A[7][4] = LGI_RK(1.07262030446373284651809199168e-1);
  A[7][5] = LGI_RK(-1.53194377486244017527936158236e-2);
  A[7][6] = LGI_RK(8.27378916381402288758473766002e-3);
  A[8][0] = LGI_RK(6.24110958716075717114429577812e-1);
  A[8][3] = LGI_RK(-3.36089262944694129406857109825);
  A[8][4] = LGI_RK(-8.68219346841726006818189891453e-1);
  A[8][5] = LGI_RK(2.75920996994467083049415600797e1);
  A[8][6] = LGI_RK(2.01540675504778934086186788979e1);
  A[8][7] = LGI_RK(-4.34898841810699588477366255144e1);
  A[9][0] = LGI_RK(4.77662536438264365890433908527e-1);
  A[9][3] = LGI_RK(-2.48811461997166764192642586468);
  A[9][4] = LGI_RK(-5.90290826836842996371446475743e-1);
  A[9][5] = LGI_RK(2.12300514481811942347288949897e1);
  A[9][6] = LGI_RK(1.52792336328824235832596922938e1);
  A[9][7] = LGI_RK(-3.32882109689848629194453265587e1);
  A[9][8] = LGI_RK(-2.03312017085086261358222928593e-2);
  A[10][0] = LGI_RK(-9.3714243008598732571704021658e-1);
  A[10][3] = LGI_RK(5.18637242884406370830023853209);
  A[10][4] = LGI_RK(1.09143734899672957818500254654);
  A[10][5] = LGI_RK(-8.14978701074692612513997267357);
  A[10][6] = LGI_RK(-1.85200656599969598641566180701e1);
  A[10][7] = LGI_RK(2.27394870993505042818970056734e1);
  A[10][8] = LGI_RK(2.49360555267965238987089396762);
  A[10][9] = LGI_RK(-3.0467644718982195003823669022);
  A[11][0] = LGI_RK(2.27331014751653820792359768449);
  A[11][3] = LGI_RK(-1.05344954667372501984066689879e1);
  A[11][4] = LGI_RK(-2.00087205822486249909675718444);
  A[11][5] = LGI_RK(-1.79589318631187989172765950534e1);
  A[11][6] = LGI_RK(2.79488845294199600508499808837e1);
  A[11][7] = LGI_RK(-2.85899827713502369474065508674);
  A[11][8] = LGI_RK(-8.87285693353062954433549289258);
  A[11][9] = LGI_RK(1.23605671757943030647266201528e1);
  A[11][10] = LGI_RK(6.43392746015763530355970484046e-1);
  // row 12: the weights b (the stage at the new point)
  A[12][0] = LGI_RK(5.42937341165687622380535766363e-2);
  A[12][5] = LGI_RK(4.45031289275240888144113950566);
  A[12][6] = LGI_RK(1.89151789931450038304281599044);
  A[12][7] = LGI_RK(-5.8012039600105847814672114227);
  A[12][8] = LGI_RK(3.1116436695781989440891606237e-1);
  A[12][9] = LGI_RK(-1.52160949662516078556178806805e-1);
  A[12][10] = LGI_RK(2.01365400804030348374776537501e-1);
  A[12][11] = LGI_RK(4.47106157277725905176885569043e-2);
  // rows 13–15: the extra stages of the dense output
  A[13][0] = LGI_RK(5.61675022830479523392909219681e-2);
  A[13][6] = LGI_RK(2.53500210216624811088794765333e-1);
  A[13][7] = LGI_RK(-2.46239037470802489917441475441e-1);
  A[13][8] = LGI_RK(-1.24191423263816360469010140626e-1);
  A[13][9] = LGI_RK(1.5329179827876569731206322685e-1);
  A[13][10] = LGI_RK(8.20105229563468988491666602057e-3);
  A[13][11] = LGI_RK(7.56789766054569976138603589584e-3);
  A[13][12] = LGI_RK(-8.298e-3);
  A[14][0] = LGI_RK(3.18346481635021405060768473261e-2);
  A[14][5] = LGI_RK(2.83009096723667755288322961402e-2);
  A[14][6] = LGI_RK(5.35419883074385676223797384372e-2);
  A[14][7] = LGI_RK(-5.49237485713909884646569340306e-2);
  A[14][10] = LGI_RK(-1.08347328697249322858509316994e-4);
  A[14][11] = LGI_RK(3.82571090835658412954920192323e-4);
  A[14][12] = LGI_RK(-3.40465008687404560802977114492e-4);
  A[14][13] = LGI_RK(1.41312443674632500278074618366e-1);
  A[15][0] = LGI_RK(-4.28896301583791923408573538692e-1);
  A[15][5] = LGI_RK(-4.69762141536116384314449447206);
  A[15][6] = LGI_RK(7.68342119606259904184240953878);
  A[15][7] = LGI_RK(4.06898981839711007970213554331);
  A[15][8] = LGI_RK(3.56727187455281109270669543021e-1);
  A[15][12] = LGI_RK(-1.39902416515901462129418009734e-3);
  A[15][13] = LGI_RK(2.9475147891527723389556272149);
  A[15][14] = LGI_RK(-9.15095847217987001081870187138);
  return A;
}();

template <class C>
inline constexpr std::array<C, 12> dop853_b = [] {
  std::array<C, 12> b{};
  for (int i = 0; i < 12; ++i) b[i] = dop853_a<C>[12][i];
  return b;
}();

// e3 = b − b̂₃, the third-order weights bhh₁, bhh₉, bhh₁₂ of dop853.f.
template <class C>
inline constexpr std::array<C, 12> dop853_e3 = [] {
  std::array<C, 12> e = dop853_b<C>;
  e[0] -= LGI_RK(0.244094488188976377952755905512);
  e[8] -= LGI_RK(0.733846688281611857341361741547);
  e[11] -= LGI_RK(0.220588235294117647058823529412e-1);
  return e;
}();

// The rows d₄ … d₇ of dop853.f's dense output (r₄ … r₇ above).
template <class C>
inline constexpr std::array<std::array<C, 16>, 4> dop853_d = [] {
  std::array<std::array<C, 16>, 4> D{};
  D[0][0] = LGI_RK(-0.84289382761090128651353491142e1);
  D[0][5] = LGI_RK(0.56671495351937776962531783590);
  D[0][6] = LGI_RK(-0.30689499459498916912797304727e1);
  D[0][7] = LGI_RK(0.23846676565120698287728149680e1);
  D[0][8] = LGI_RK(0.21170345824450282767155149946e1);
  D[0][9] = LGI_RK(-0.87139158377797299206789907490);
  D[0][10] = LGI_RK(0.22404374302607882758541771650e1);
  D[0][11] = LGI_RK(0.63157877876946881815570249290);
  D[0][12] = LGI_RK(-0.88990336451333310820698117400e-1);
  D[0][13] = LGI_RK(0.18148505520854727256656404962e2);
  D[0][14] = LGI_RK(-0.91946323924783554000451984436e1);
  D[0][15] = LGI_RK(-0.44360363875948939664310572000e1);
  D[1][0] = LGI_RK(0.10427508642579134603413151009e2);
  D[1][5] = LGI_RK(0.24228349177525818288430175319e3);
  D[1][6] = LGI_RK(0.16520045171727028198505394887e3);
  D[1][7] = LGI_RK(-0.37454675472269020279518312152e3);
  D[1][8] = LGI_RK(-0.22113666853125306036270938578e2);
  D[1][9] = LGI_RK(0.77334326684722638389603898808e1);
  D[1][10] = LGI_RK(-0.30674084731089398182061213626e2);
  D[1][11] = LGI_RK(-0.93321305264302278729567221706e1);
  D[1][12] = LGI_RK(0.15697238121770843886131091075e2);
  D[1][13] = LGI_RK(-0.31139403219565177677282850411e2);
  D[1][14] = LGI_RK(-0.93529243588444783865713862664e1);
  D[1][15] = LGI_RK(0.35816841486394083752465898540e2);
  D[2][0] = LGI_RK(0.19985053242002433820987653617e2);
  D[2][5] = LGI_RK(-0.38703730874935176555105901742e3);
  D[2][6] = LGI_RK(-0.18917813819516756882830838328e3);
  D[2][7] = LGI_RK(0.52780815920542364900561016686e3);
  D[2][8] = LGI_RK(-0.11573902539959630126141871134e2);
  D[2][9] = LGI_RK(0.68812326946963000169666922661e1);
  D[2][10] = LGI_RK(-0.10006050966910838403183860980e1);
  D[2][11] = LGI_RK(0.77771377980534432092869265740);
  D[2][12] = LGI_RK(-0.27782057523535084065932004339e1);
  D[2][13] = LGI_RK(-0.60196695231264120758267380846e2);
  D[2][14] = LGI_RK(0.84320405506677161018159903784e2);
  D[2][15] = LGI_RK(0.11992291136182789328035130030e2);
  D[3][0] = LGI_RK(-0.25693933462703749003312586129e2);
  D[3][5] = LGI_RK(-0.15418974869023643374053993627e3);
  D[3][6] = LGI_RK(-0.23152937917604549567536039109e3);
  D[3][7] = LGI_RK(0.35763911791061412378285349910e3);
  D[3][8] = LGI_RK(0.93405324183624310003907691704e2);
  D[3][9] = LGI_RK(-0.37458323136451633156875139351e2);
  D[3][10] = LGI_RK(0.10409964950896230045147246184e3);
  D[3][11] = LGI_RK(0.29840293426660503123344363579e2);
  D[3][12] = LGI_RK(-0.43533456590011143754432175058e2);
  D[3][13] = LGI_RK(0.96324553959188282948394950600e2);
  D[3][14] = LGI_RK(-0.39177261675615439165231486172e2);
  D[3][15] = LGI_RK(-0.14972683625798562581422125276e3);
  return D;
}();
}  // namespace detail

/// DOP853: the explicit order-8 method of Dormand & Prince with Hairer's error estimator of orders 5 and 3
/// and an order-7 continuous extension. Prince & Dormand, J. Comput. Appl. Math. 7 (1981) 67–75 (the
/// RK8(7)13M family); the 8(5,3) version and its dense output: Hairer, Nørsett, Wanner, Solving ODEs I,
/// 2nd ed. (1993), §II.5 and §II.6, code dop853.f (section numbers from memory; table and equation numbers
/// not confirmed — the book was not available to us, and dop853.f's header cites only the book). Error
/// estimate of dop853.f: err = ‖δ₅‖² / √(‖δ₅‖² + 0.01 ‖δ₃‖²) (RMS norms of the scaled
/// components), which behaves like h⁸: control_order 8. Checked by the order conditions (order 8 for b,
/// 5 for b − e, 3 for b − e3, 7 for the dense weights) in tests/integrators/test_rkmk_family.cpp.
template <class C>
inline constexpr EmbeddedTableau<12, 16, 8, C> dop853_in{
    .name = "rkmk_dp8",
    .title = "Runge-Kutta-Munthe-Kaas, DOP853 8(5,3) with dense output (adaptive with rtol/atol)",
    .order = 8,
    .embedded_order = 5,
    .dense_order = 7,
    .control_order = 8,
    .a = detail::dop853_a<C>,
    .b = detail::dop853_b<C>,
    .c = {LGI_RK(0.0), LGI_RK(0.526001519587677318785587544488e-01), LGI_RK(0.789002279381515978178381316732e-01),
          LGI_RK(0.118350341907227396726757197510), LGI_RK(0.281649658092772603273242802490),
          LGI_RK(0.333333333333333333333333333333), LGI_RK(0.25), LGI_RK(0.307692307692307692307692307692),
          LGI_RK(0.651282051282051282051282051282), LGI_RK(0.6), LGI_RK(0.857142857142857142857142857142), LGI_RK(1.0),
          LGI_RK(1.0), LGI_RK(0.1), LGI_RK(0.2), LGI_RK(0.777777777777777777777777777778)},
    .e = {LGI_RK(0.1312004499419488073250102996e-1), LGI_RK(0.0), LGI_RK(0.0), LGI_RK(0.0), LGI_RK(0.0),
          LGI_RK(-0.1225156446376204440720569753e1), LGI_RK(-0.4957589496572501915214079952),
          LGI_RK(0.1664377182454986536961530415e1), LGI_RK(-0.3503288487499736816886487290),
          LGI_RK(0.3341791187130174790297318841), LGI_RK(0.8192320648511571246570742613e-1),
          LGI_RK(-0.2235530786388629525884427845e-1)},
    .e3 = detail::dop853_e3<C>,
    .fsal = 12,
    .dense = tableaus::detail::hermite_dense<12, 16, 4>(detail::dop853_b<C>, 12, detail::dop853_d<C>),
    .reference =
        "Prince-Dormand, J. Comput. Appl. Math. 7 (1981) 67; Hairer-Norsett-Wanner I, sec. II.5-II.6 (dop853); "
        "Munthe-Kaas, BIT 38 (1998) 92",
};
/// DOP853 in double (rkmk_dp8, the embedding baselines dop853_*).
inline constexpr EmbeddedTableau<12, 16> dop853 = dop853_in<double>;

namespace detail {
// Verner's "most efficient" 9(8) pair RKV98.IIa with its order-9 interpolant: 16 stages for the step (b uses
// stages 1, 8–15; b̂ uses 1, 8–13 and 16), the 17th at the new point (a[16] = b), 9 more (18–26) for the
// interpolant. J. H. Verner, Numer. Algorithms 53 (2010) 383–396; coefficients from Verner's page, file
// RKV98.IIa.Efficient.000000349.081209 (FLOAT6040OnWeb), 40 digits, transcribed from two independent copies of
// it read for this file: vlovero/PyODEPack pyodepack/include/verner98e.h (a, c, b, b̂ − b) and SciML
// OrdinaryDiffEq.jl lib/OrdinaryDiffEqVerner/src/verner_tableaus.jl (Vern9ExtraStages, the BigFloat strings of
// Vern9InterpolationCoefficients); the two agree on every digit they share (stages 17–26). (The Float64
// literal of a(12,9) in the latter, −0.0035850052905728597, differs from Verner's −0.00358500529057287613…
// by 38 ulp; the 40 digits are used.)
template <class C>
inline constexpr std::array<std::array<C, 26>, 26> vern9_a = [] {
  std::array<std::array<C, 26>, 26> A{};
  A[1][0] = LGI_RK(0.0346200000000000);
  A[2][0] = LGI_RK(-0.0389335438857287327017042687229284478532);
  A[2][1] = LGI_RK(0.1359578945245091786499878854939346230295);
  A[3][0] = LGI_RK(0.03638413148954266723060635628912731569111);
  A[3][2] = LGI_RK(0.1091523944686280016918190688673819470733);
  A[4][0] = LGI_RK(2.025763914393969636805657604282571047511);
  A[4][2] = LGI_RK(-7.638023836496292020387602153091964592952);
  A[4][3] = LGI_RK(6.173259922102322383581944548809393545442);
  A[5][0] = LGI_RK(0.05112275589406060872792270881648288397197);
  A[5][3] = LGI_RK(0.1770823794555021537929910813839068684087);
  A[5][4] = LGI_RK(0.00080277624092225014536138698108025283759);
  A[6][0] = LGI_RK(0.1316006357975216279279871693164256985334);
  A[6][3] = LGI_RK(-0.2957276252669636417685183174672273730699);
  A[6][4] = LGI_RK(0.0878137803564295237421124704053886667082);
  A[6][5] = LGI_RK(0.6213052975225274774321435005639430026100);
  A[7][0] = LGI_RK(0.07166666666666666666666666666666666666667);
  A[7][5] = LGI_RK(0.3305533578915319409260346730051472207728);
  A[7][6] = LGI_RK(0.2427799754418013924072986603281861125606);
  A[8][0] = LGI_RK(0.07180664062500000000000000000000000000000);
  A[8][5] = LGI_RK(0.3294380283228177160744825466257672816401);
  A[8][6] = LGI_RK(0.1165190029271822839255174533742327183599);
  A[8][7] = LGI_RK(-0.03401367187500000000000000000000000000000);
  A[9][0] = LGI_RK(0.04836757646340646986611287718844085773549);
  A[9][5] = LGI_RK(0.03928989925676163974333190042057047002852);
  A[9][6] = LGI_RK(0.1054740945890344608263649267140088017604);
  A[9][7] = LGI_RK(-0.02143865284648312665982642293830533996214);
  A[9][8] = LGI_RK(-0.1041229174627194437759832813847147895623);
  A[10][0] = LGI_RK(-0.02664561487201478635337289243849737340534);
  A[10][5] = LGI_RK(0.03333333333333333333333333333333333333333);
  A[10][6] = LGI_RK(-0.1631072244872467239162704487554706387141);
  A[10][7] = LGI_RK(0.03396081684127761199487954930015522928244);
  A[10][8] = LGI_RK(0.1572319413814626097110769806810024118077);
  A[10][9] = LGI_RK(0.2152267478031879552303534778794770376960);
  A[11][0] = LGI_RK(0.03689009248708622334786359863227633989718);
  A[11][5] = LGI_RK(-0.1465181576725542928653609891758501156785);
  A[11][6] = LGI_RK(0.2242577768172024345345469822625833796001);
  A[11][7] = LGI_RK(0.02294405717066072637090897902753790803034);
  A[11][8] = LGI_RK(-0.0035850052905728761357394424889330334334);
  A[11][9] = LGI_RK(0.08669223316444385506869203619044453906053);
  A[11][10] = LGI_RK(0.4383840651968337846196219974168630120572);
  A[12][0] = LGI_RK(-0.4866012215113340846662212357570395295088);
  A[12][5] = LGI_RK(-6.304602650282852990657772792012007122988);
  A[12][6] = LGI_RK(-0.281245618289472564778284183790118418111);
  A[12][7] = LGI_RK(-2.679019236219849057687906597489223155566);
  A[12][8] = LGI_RK(0.518815663924157511565311164615012522024);
  A[12][9] = LGI_RK(1.365353187603341710683633635235238678626);
  A[12][10] = LGI_RK(5.885091088503946585721274891680604830712);
  A[12][11] = LGI_RK(2.802808786272062889819965117517532194812);
  A[13][0] = LGI_RK(0.4185367457753471441471025246471931649633);
  A[13][5] = LGI_RK(6.724547581906459363100870806514855026676);
  A[13][6] = LGI_RK(-0.425444280164611790606983409697113064616);
  A[13][7] = LGI_RK(3.343279153001265577811816947557982637749);
  A[13][8] = LGI_RK(0.617081663117537759528421117507709784737);
  A[13][9] = LGI_RK(-0.929966123939932833937749523988800852013);
  A[13][10] = LGI_RK(-6.099948804751010722472962837945508844846);
  A[13][11] = LGI_RK(-3.002206187889399044804158084895173690015);
  A[13][12] = LGI_RK(0.2553202529443445472336424602988558373637);
  A[14][0] = LGI_RK(-0.779374086122884664644623040843840506343);
  A[14][5] = LGI_RK(-13.93734253810777678786523664804936051203);
  A[14][6] = LGI_RK(1.252048853379357320949735183924200895136);
  A[14][7] = LGI_RK(-14.69150040801686878191527989293072091588);
  A[14][8] = LGI_RK(-0.494705058533141685655191992136962873577);
  A[14][9] = LGI_RK(2.242974909146236657906984549543692874755);
  A[14][10] = LGI_RK(13.36789380382864375813864978592679139881);
  A[14][11] = LGI_RK(14.39665048665068644512236935340272139005);
  A[14][12] = LGI_RK(-0.7975813331776800379127866056663258667437);
  A[14][13] = LGI_RK(0.4409353709534277758753793068298041158235);
  A[15][0] = LGI_RK(2.058051337466886442151242368989994043993);
  A[15][5] = LGI_RK(22.35793772796803295519317565842520212899);
  A[15][6] = LGI_RK(0.90949810997556332745009198137971890783);
  A[15][7] = LGI_RK(35.89110098240264104710550686568482456493);
  A[15][8] = LGI_RK(-3.442515027624453437985000403608480262211);
  A[15][9] = LGI_RK(-4.865481358036368826566013387928704014496);
  A[15][10] = LGI_RK(-18.90980381354342625688427480879773032857);
  A[15][11] = LGI_RK(-34.26354448030451782929251177395134170515);
  A[15][12] = LGI_RK(1.264756521695642578827783499806516664686);
  // row 16: the weights b (the stage at the new point)
  A[16][0] = LGI_RK(0.01461197685842315252051541915018784713459);
  A[16][7] = LGI_RK(-0.3915211862331339089410228267288242030810);
  A[16][8] = LGI_RK(0.2310932500289506415909675644868993669908);
  A[16][9] = LGI_RK(0.1274766769992852382560589467488989175618);
  A[16][10] = LGI_RK(0.2246434176204157731566981937082069688984);
  A[16][11] = LGI_RK(0.5684352689748512932705226972873692126743);
  A[16][12] = LGI_RK(0.05825871557215827200814768021863420902155);
  A[16][13] = LGI_RK(0.1364317403482215641609022744494239843327);
  A[16][14] = LGI_RK(0.03057013983082797397721005067920369646664);
  // rows 17–20: the extra stages of Verner's order-8 interpolant; rows 21–25: those of order 9
  A[17][0] = LGI_RK(0.01549973668189559302279946863304789372788);
  A[17][7] = LGI_RK(0.3355153219059635054403439303177105512242);
  A[17][8] = LGI_RK(0.2003613944191860651552622660712101217322);
  A[17][9] = LGI_RK(0.1252060659283549312946162355194540994211);
  A[17][10] = LGI_RK(0.2298676393184206750544046308957155868736);
  A[17][11] = LGI_RK(-0.2020250653476181447824906889122391003637);
  A[17][12] = LGI_RK(0.05917103230665456601422111997583025339897);
  A[17][13] = LGI_RK(-0.02651834783047638681693835956996437528251);
  A[17][14] = LGI_RK(-0.02384094602130971415278110567256446033405);
  A[17][16] = LGI_RK(0.02718171570208501807097257892166705118335);
  A[18][0] = LGI_RK(0.01302453943114338366054520296881099431474);
  A[18][7] = LGI_RK(-0.7452850902413112085299330666038981625179);
  A[18][8] = LGI_RK(0.2643867896429300961465132150322749722129);
  A[18][9] = LGI_RK(0.1313961758372753932588328082078842388890);
  A[18][10] = LGI_RK(0.2167253815122927263092467187957410643315);
  A[18][11] = LGI_RK(0.8734117564076052559016338094938888451419);
  A[18][12] = LGI_RK(0.01185905643935776688228545787724340848142);
  A[18][13] = LGI_RK(0.05876002941689550612992712203494447529933);
  A[18][14] = LGI_RK(0.003266518630202087866399279690939423159022);
  A[18][16] = LGI_RK(-0.008959308648417929824525368306101792182274);
  A[18][17] = LGI_RK(0.06941415157202692219907482080827253287034);
  A[19][0] = LGI_RK(0.01397089996925942721283716334050740168797);
  A[19][7] = LGI_RK(-0.4665765335957674596054673402956853940520);
  A[19][8] = LGI_RK(0.2416372787216257077935214889875485248580);
  A[19][9] = LGI_RK(0.1290363341345674735721677437066933999929);
  A[19][10] = LGI_RK(0.2216700671735105311080225734522323922813);
  A[19][11] = LGI_RK(0.6257275123364644931771253383573999863003);
  A[19][12] = LGI_RK(0.04355312415679284117869124964829805160429);
  A[19][13] = LGI_RK(0.1011962491667290833450024852274278874501);
  A[19][14] = LGI_RK(0.01808582254679721049279369742685497400353);
  A[19][16] = LGI_RK(-0.02079875587689169691156509689282083267654);
  A[19][17] = LGI_RK(-0.09022232517086218976198252891464664868640);
  A[19][18] = LGI_RK(-0.1212796735622254216011467740438097427634);
  A[20][0] = LGI_RK(0.01604638888318112738641232352800290501904);
  A[20][7] = LGI_RK(0.09517712399458336651642257453589397190702);
  A[20][8] = LGI_RK(0.1359187264655317806136927180199100622471);
  A[20][9] = LGI_RK(0.1237765280959854006935081364365637515893);
  A[20][10] = LGI_RK(0.2335656264102966047058755123098072346246);
  A[20][11] = LGI_RK(-0.09051508172625873314662090873741762206189);
  A[20][12] = LGI_RK(-0.02537574270006131028513276914038326155331);
  A[20][13] = LGI_RK(-0.1359631696887162048002744757083947500478);
  A[20][14] = LGI_RK(-0.04679214284145113075088049469061349990847);
  A[20][16] = LGI_RK(0.05177958859391748239949773879090325427473);
  A[20][17] = LGI_RK(0.09672595677476773313884172931875718705561);
  A[20][18] = LGI_RK(0.1477312690340742769720989417101989769314);
  A[20][19] = LGI_RK(-0.1150750712958503934434410263732282100773);
  A[21][0] = LGI_RK(0.01802918623893620731908165792176564180038);
  A[21][7] = LGI_RK(0.06983601042028873702545973390560096201728);
  A[21][8] = LGI_RK(-0.02541247660791663512384395986842781657182);
  A[21][9] = LGI_RK(0.008487827035463274491721441398893680307535);
  A[21][10] = LGI_RK(-0.002427525516089801645451101966852425715128);
  A[21][11] = LGI_RK(-0.1047839752893819879012607694745789515746);
  A[21][12] = LGI_RK(-0.01473147795248041942353840372690095884761);
  A[21][13] = LGI_RK(-0.03916338390816177165706892282751065537530);
  A[21][14] = LGI_RK(-0.01005657343293959419073236542225421561652);
  A[21][16] = LGI_RK(0.01102510392204834322538452331445716455061);
  A[21][17] = LGI_RK(0.005092830749095398308703438556315975226108);
  A[21][18] = LGI_RK(0.04759715599420644505591133410826632557391);
  A[21][19] = LGI_RK(0.03386307003288382751110965442296681690349);
  A[21][20] = LGI_RK(0.02764422831404797700452373965825845732168);
  A[22][0] = LGI_RK(0.01677431640522778042988664067637191163626);
  A[22][7] = LGI_RK(0.6220437408820475326702539861577894278533);
  A[22][8] = LGI_RK(-0.2060859809768841878234097076241307428139);
  A[22][9] = LGI_RK(0.1156394989766058889629372195583391792474);
  A[22][10] = LGI_RK(0.02664101793378358946544219293685167025971);
  A[22][11] = LGI_RK(-0.9376810793418770527505892794460093668860);
  A[22][12] = LGI_RK(-0.1367806466702160302637074581619101741312);
  A[22][13] = LGI_RK(-0.3678480995268296672182605288991379118419);
  A[22][14] = LGI_RK(-0.09547871314402478902820445838193201497337);
  A[22][16] = LGI_RK(0.1013492018422369748729008873270013785313);
  A[22][17] = LGI_RK(-0.08911323084568593396468400926074881389560);
  A[22][18] = LGI_RK(0.4664140988974760478895528270623735057521);
  A[22][19] = LGI_RK(0.4502736292354579812232681662308722738519);
  A[22][20] = LGI_RK(0.1838522463326818655346135218242696774099);
  A[23][0] = LGI_RK(0.01071149731491444187554380927165768658192);
  A[23][7] = LGI_RK(-0.07094336118221108191937165464264324417735);
  A[23][8] = LGI_RK(0.1002164900340091596740582334112699697590);
  A[23][9] = LGI_RK(0.1383453980468025108839271214703390659581);
  A[23][10] = LGI_RK(0.1796330633578163411338104055485109917477);
  A[23][11] = LGI_RK(0.09048246545576180974879274948815422276563);
  A[23][12] = LGI_RK(-0.005460662294523338383345981122023862069115);
  A[23][13] = LGI_RK(-0.03000457905119619782973021046143166498567);
  A[23][14] = LGI_RK(-0.01145192026962799093665613252151017277867);
  A[23][16] = LGI_RK(0.01003394686109385076849515422360600302176);
  A[23][17] = LGI_RK(-0.09506485282809046129031027932806241113157);
  A[23][18] = LGI_RK(0.04853358804093591445756711642658478691640);
  A[23][19] = LGI_RK(0.08013325919783924638483373011297347396327);
  A[23][20] = LGI_RK(-0.1251643326835242045676140618774248455713);
  A[24][0] = LGI_RK(0.01410172088869221367153586187761994182069);
  A[24][7] = LGI_RK(-0.3713379753704491105936205420001801316029);
  A[24][8] = LGI_RK(0.2231265548117180273161442520179150684520);
  A[24][9] = LGI_RK(0.1287005345918120122888629169443916280865);
  A[24][10] = LGI_RK(0.2224600659675494761192249831098918110654);
  A[24][11] = LGI_RK(0.5382853042550701952740528638168708946100);
  A[24][12] = LGI_RK(0.05417202616988763101781128062036252796548);
  A[24][13] = LGI_RK(0.1256968791308743925752109039299467082975);
  A[24][14] = LGI_RK(0.02784492789002054061504430663197543089132);
  A[24][16] = LGI_RK(-0.03077409246205059733390460511525401688205);
  A[24][17] = LGI_RK(0.008569805293689777608077303071761466118035);
  A[24][18] = LGI_RK(-0.1535174690587044615794997685221990516897);
  A[24][19] = LGI_RK(-0.02179957030548196497189489878038029238243);
  A[24][20] = LGI_RK(0.01447128819737186799295514239727801525027);
  A[25][0] = LGI_RK(0.01424600411735646609296566581447532773183);
  A[25][7] = LGI_RK(-0.3767107393295407091303982522049390741260);
  A[25][8] = LGI_RK(0.2252399780730421480874737297000189000070);
  A[25][9] = LGI_RK(0.1283603076292529988314451246143633426068);
  A[25][10] = LGI_RK(0.2230238705261692544876826347415151339678);
  A[25][11] = LGI_RK(0.5463127827750747224899202176094949607118);
  A[25][12] = LGI_RK(0.05526190791375779994553849469706124289752);
  A[25][13] = LGI_RK(0.1285613508749982456581494397108686240388);
  A[25][14] = LGI_RK(0.02857250681296406482698934635829147899039);
  A[25][16] = LGI_RK(-0.02398761886357108720930416967644499057175);
  A[25][17] = LGI_RK(0.05556224458910509454379297181908734648749);
  A[25][18] = LGI_RK(-0.01740675650762838674257930398070760254668);
  A[25][19] = LGI_RK(-0.03815462365996979065575121886854199471011);
  A[25][20] = LGI_RK(0.01111878504898917877407531966545730451506);
  return A;
}();

template <class C>
inline constexpr std::array<C, 16> vern9_b = [] {
  std::array<C, 16> b{};
  for (int i = 0; i < 16; ++i) b[i] = vern9_a<C>[16][i];
  return b;
}();

// The order-9 interpolant, b_i(θ) = Σ_{m=1..9} r_im θ^m, nonzero for the stages 1, 8–15, 17–26.
template <class C>
inline constexpr std::array<std::array<C, 9>, 26> vern9_dense = [] {
  std::array<std::array<C, 9>, 26> R{};
  R[0] = {LGI_RK(1.0),
          LGI_RK(-28.33048870061739823290767301658881994700),
          LGI_RK(257.6535452078577977252092979905248156497),
          LGI_RK(-1152.154455743457311528752964691951881858),
          LGI_RK(2909.390878345408890936564599116550031880),
          LGI_RK(-4355.005172868188498048946108887283528629),
          LGI_RK(3834.083497036262189455855371796461857871),
          LGI_RK(-1835.419052683407081215583427992189311730),
          LGI_RK(368.7958613829998340610814211036270246107)};
  R[7] = {LGI_RK(0.0),
          LGI_RK(2.649656243770091212685381903551424676261),
          LGI_RK(-96.30312807816005963630382777245983513008),
          LGI_RK(869.3095462492795755338599928089438369769),
          LGI_RK(-3395.688567551074115525201961265641584358),
          LGI_RK(6796.933987158715680563278170147156885480),
          LGI_RK(-7340.848417712071304684606060804637321789),
          LGI_RK(4082.848896992365666259441580054990759905),
          LGI_RK(-919.2934944890586676320942978986329899642)};
  R[8] = {LGI_RK(0.0),
          LGI_RK(-1.563945181928732780647121505551017046606),
          LGI_RK(56.84239739272860000194549791973820565214),
          LGI_RK(-513.1052300304284642178552372517916694426),
          LGI_RK(2004.286702110323162741493515173880535381),
          LGI_RK(-4011.853305913929339500285683507736138334),
          LGI_RK(4332.895839278586189971336003691596594090),
          LGI_RK(-2409.879347937144606091337260195738587773),
          LGI_RK(542.6079835318221405169412532400889768401)};
  R[9] = {LGI_RK(0.0),
          LGI_RK(-0.8627103334967223830653368770735555216700),
          LGI_RK(31.35565375185173442495465167501846267906),
          LGI_RK(-283.0413682227354209126847112083546012674),
          LGI_RK(1105.613463426006937052739159664962261462),
          LGI_RK(-2213.036200678452629288185991597653042989),
          LGI_RK(2390.131097754120588994847482867886207858),
          LGI_RK(-1329.348266146873716496636094950745123424),
          LGI_RK(299.3158071265785138462868993727082901209)};
  R[10] = {LGI_RK(0.0),
           LGI_RK(-1.520295337901214839055193576160469820911),
           LGI_RK(55.25592121120227100440616045452813504748),
           LGI_RK(-498.7844190970740738969945498750124435385),
           LGI_RK(1948.346888525776056658403461666308795237),
           LGI_RK(-3899.882136407551390287649940376076923682),
           LGI_RK(4211.964345158858030803618536151121927765),
           LGI_RK(-2342.619408856117128087568672414857706561),
           LGI_RK(527.4637482204278644179968961638568925209)};
  R[11] = {LGI_RK(0.0),
           LGI_RK(-3.846938844125523400516071820264700141179),
           LGI_RK(139.8189840986840520353362018994734906611),
           LGI_RK(-1262.118687621600386514715930156791825893),
           LGI_RK(4930.075848057311658057235318456802793199),
           LGI_RK(-9868.219486069539059368988308801366826185),
           LGI_RK(10657.90892434886730229746304583865145121),
           LGI_RK(-5927.738759872814112912292792695856187255),
           LGI_RK(1334.688551172190921099749059976639173619)};
  R[12] = {LGI_RK(0.0),
           LGI_RK(-0.3942713061200141454309326713125653612517),
           LGI_RK(14.32999476067649707020689155180345562459),
           LGI_RK(-129.3540665994558117853022852051786116929),
           LGI_RK(505.2816077002517600897861155496606850457),
           LGI_RK(-1011.390080139433268878243655218566636574),
           LGI_RK(1092.325051781891697669369143688906543465),
           LGI_RK(-607.5317019302810290917918493845279272648),
           LGI_RK(136.7917244480423273434147193694336909663)};
  R[13] = {LGI_RK(0.0),
           LGI_RK(-0.9233145622082101394378429409444333268499),
           LGI_RK(33.55834582309798808260613735851232640640),
           LGI_RK(-302.9246397549735936661321348695774835448),
           LGI_RK(1183.281306967867553342903125095128753568),
           LGI_RK(-2368.498986790111516106072390247333149007),
           LGI_RK(2558.034559755808027369106332027405169828),
           LGI_RK(-1422.733175577880214903071122439856598476),
           LGI_RK(320.3423358787481875842587982911148385364)};
  R[14] = {LGI_RK(0.0),
           LGI_RK(-0.2068862802930053801253649628830330891017),
           LGI_RK(7.519388975651662772174695012120581518594),
           LGI_RK(-67.87605708082904058354114755731111898667),
           LGI_RK(265.1367996984150421661637988925923843021),
           LGI_RK(-530.7074807559025368587558119659212235622),
           LGI_RK(573.1765495641490277116961329189087439579),
           LGI_RK(-318.7905688834868978004500126002971837241),
           LGI_RK(71.77882490212657594681492031347005327988)};
  R[16] = {LGI_RK(0.0),
           LGI_RK(-0.4472441906744099441704338175964823026105),
           LGI_RK(16.44684676010503791623763886833381020592),
           LGI_RK(-154.4086105921295528355180056633078150675),
           LGI_RK(641.8986298540248497333509289273669726482),
           LGI_RK(-1391.939225687982391028602609567895699003),
           LGI_RK(1643.890568302952013019278202625162156841),
           LGI_RK(-1004.065297223317845596795060426393517046),
           LGI_RK(248.6243327770222987362193390543305737239)};
  R[17] = {LGI_RK(0.0),
           LGI_RK(-0.1507876007899797948720901584434839156279),
           LGI_RK(5.527328824824632235316362126620825363280),
           LGI_RK(-51.33833743084618751433903968701557585387),
           LGI_RK(209.6022002703280347991393999433060881829),
           LGI_RK(-442.7692650421825928714839983614217797969),
           LGI_RK(505.0579312588052893780948070449787925777),
           LGI_RK(-295.6336410615619366143935619944592839974),
           LGI_RK(69.70457078142274038253812108643441743987)};
  R[18] = {LGI_RK(0.0),
           LGI_RK(-0.6413652207435296452288504944964177537185),
           LGI_RK(23.51013248624684600263471193689787394701),
           LGI_RK(-218.3642683246972281497485359238725613162),
           LGI_RK(891.5292818535365634586829868055833114383),
           LGI_RK(-1883.290177206007885518558760085145850658),
           LGI_RK(2148.230954488399755970660772306573864434),
           LGI_RK(-1257.458401521712336970840850120592935471),
           LGI_RK(296.4838434449778148523985255750527153802)};
  R[19] = {LGI_RK(0.0),
           LGI_RK(1.810729313444845732964058528284532356045),
           LGI_RK(-66.37479657295337371220255196726289169374),
           LGI_RK(616.4952025401106511929691356878863855003),
           LGI_RK(-2517.003030777322559684753470471663859295),
           LGI_RK(5316.984175781033401491488704359579721604),
           LGI_RK(-6064.976140789574108556866601189158423779),
           LGI_RK(3550.109538888391317555902194852386816092),
           LGI_RK(-837.0456783831301740195014698000522807852)};
  R[20] = {LGI_RK(0.0),
           LGI_RK(0.05176008760353717918864555990277480363987),
           LGI_RK(-1.897337862580348756406065418550014243949),
           LGI_RK(17.62264820793629244181715147639285955422),
           LGI_RK(-71.94907400242465946110661282550878163878),
           LGI_RK(151.9871383765666045085018751235590550206),
           LGI_RK(-173.3686498747860565970136435029707518663),
           LGI_RK(101.4806461521468075879782291473158292931),
           LGI_RK(-23.92713108446217690295957956014097092250)};
  R[21] = {LGI_RK(0.0),
           LGI_RK(31.32178255668799909977422939838912846070),
           LGI_RK(-355.6570858339106059687054319211280026146),
           LGI_RK(1752.685282489515979253875884672206842255),
           LGI_RK(-4708.092293138363367969732154806019707156),
           LGI_RK(7370.900776193488713149861391844801840850),
           LGI_RK(-6716.504964764565347011489385051202629762),
           LGI_RK(3303.940398161185772296756776169088470785),
           LGI_RK(-678.5938956640391428503413103061359428182)};
  R[22] = {LGI_RK(0.0),
           LGI_RK(-2.719607334185924760747802644504744092917),
           LGI_RK(86.64045615858264001154848875638486632034),
           LGI_RK(-454.1926030939030807863651114984001402596),
           LGI_RK(1014.749221100543425314268817989377200147),
           LGI_RK(-1133.583456714543865890388885909333783663),
           LGI_RK(610.4671827718666569168001429679645990946),
           LGI_RK(-109.0233499449543802317396567002119357593),
           LGI_RK(-12.33784294340547057337599296127606178639)};
  R[23] = {LGI_RK(0.0),
           LGI_RK(3.177214801432923432265738869490200556403),
           LGI_RK(-113.8098697715142983214434051918276259885),
           LGI_RK(978.0935981825675014833003847211971070224),
           LGI_RK(-3575.129377623670076451027372711378100786),
           LGI_RK(6764.361519838450570830405988615992045681),
           LGI_RK(-6987.161043852012362644872233028628887679),
           LGI_RK(3751.905762789571137088934326513342858381),
           LGI_RK(-821.4378043648253954175634277881875971878)};
  R[24] = {LGI_RK(0.0),
           LGI_RK(0.8772843083465530069477626269697233842708),
           LGI_RK(-31.51810423988375104361582759389916060143),
           LGI_RK(273.1229151353221133842213845530391043248),
           LGI_RK(-993.2198643101781966584366870874238565290),
           LGI_RK(1787.888078312663987193988385659681964836),
           LGI_RK(-1677.394835799640950953367739332661886275),
           LGI_RK(781.3579535062687952504707744453846824540),
           LGI_RK(-141.1134269128985501802080532710905715931)};
  R[25] = {LGI_RK(0.0),
           LGI_RK(1.719427581798715782378897599231938082126),
           LGI_RK(-62.89867309250732184389962568482931880335),
           LGI_RK(580.3335507873980391019057196688995930872),
           LGI_RK(-2348.110620506760958600472968113883922730),
           LGI_RK(4921.119298612906015908637628774963068611),
           LGI_RK(-5597.912448707916639109910311016358007839),
           LGI_RK(3288.597775149621789973016480733216881572),
           LGI_RK(-782.8483098245396412116558219612402319811)};
  return R;
}();
}  // namespace detail

/// Verner's most efficient 9(8) pair: order 9, an order-8 error estimate, 16 stages a step (the 16th feeds only
/// the estimate), and an order-9 continuous extension from 10 more stages (the first at the new point). The
/// estimate e = b − b̂ behaves like h⁹: control_order 9. Checked by the order conditions (order 9 for b, 8 for
/// b − e, 9 for the dense weights at every θ tried) in tests/integrators/test_rkmk_family.cpp.
template <class C>
inline constexpr EmbeddedTableau<16, 26, 9, C> verner9_in{
    .name = "rkmk_vern9",
    .title =
        "Runge-Kutta-Munthe-Kaas, Verner's efficient 9(8) pair with order-9 dense output (adaptive with rtol/atol)",
    .order = 9,
    .embedded_order = 8,
    .dense_order = 9,
    .control_order = 9,
    .a = detail::vern9_a<C>,
    .b = detail::vern9_b<C>,
    .c = {LGI_RK(0.0),
          LGI_RK(0.03462),
          LGI_RK(0.09702435063878044594828361677100617517633),
          LGI_RK(0.1455365259581706689224254251565092627645),
          LGI_RK(0.561),
          LGI_RK(0.2290079115904850126662751771814700052182),
          LGI_RK(0.5449920884095149873337248228185299947818),
          LGI_RK(0.645),
          LGI_RK(0.48375),
          LGI_RK(0.06757),
          LGI_RK(0.25),
          LGI_RK(0.6590650618730998549405331618649220295334),
          LGI_RK(0.8206),
          LGI_RK(0.9012),
          LGI_RK(1.0),
          LGI_RK(1.0),
          LGI_RK(1.0),
          LGI_RK(0.7404185470631561083004100761798676215811),
          LGI_RK(0.888),
          LGI_RK(0.696),
          LGI_RK(0.487),
          LGI_RK(0.025),
          LGI_RK(0.15),
          LGI_RK(0.32),
          LGI_RK(0.78),
          LGI_RK(0.96)},
    // e = b − b̂ = −(b̂ − b), Verner's "bhat − b" negated
    .e = {LGI_RK(-0.005357988290444578334669665030800840430050), LGI_RK(0.0), LGI_RK(0.0), LGI_RK(0.0), LGI_RK(0.0),
          LGI_RK(0.0), LGI_RK(0.0), LGI_RK(-2.583020491182463963471769926039661727945),
          LGI_RK(0.1425225315468662612826303441690357783613), LGI_RK(0.01342065351268867600756328623975571429440),
          LGI_RK(-0.02867296291409493339975957974875822883630), LGI_RK(2.624999655215792304429522291883350513167),
          LGI_RK(-0.2825509643291537215078618092038201722614), LGI_RK(0.1364317403482215641609022744494239843327),
          LGI_RK(0.03057013983082797397721005067920369646664), LGI_RK(-0.04834231373823958314376726739772871714902)},
    .e3 = {},
    .fsal = 16,
    .dense = detail::vern9_dense<C>,
    .reference =
        "Verner, Numer. Algorithms 53 (2010) 383 (RKV98.IIa, efficient, with interpolant of order 9); "
        "Munthe-Kaas, BIT 38 (1998) 92",
};
/// Verner's 9(8) pair in double (rkmk_vern9).
inline constexpr EmbeddedTableau<16, 26, 9> verner9 = verner9_in<double>;

namespace detail {
// Verner's "most efficient" 8(7) pair RKV87.IIa with its order-8 interpolant: 13 stages for the step (b uses
// stages 1, 6–12; b̂ uses 1, 6–10 and 13), the 14th at the new point (a[13] = b), 7 more (15–21) for the
// interpolant. J. H. Verner, Numer. Algorithms 53 (2010) 383–396; coefficients from Verner's page, file
// RKV87.IIa.Efficient.000000282866.081208 (FLOAT40OnWeb), 40 digits, transcribed from jacobwilliams/rklib
// src/rklib_variable_submodule.f90 (rkv87e: a, c, b, b̂) and SciML OrdinaryDiffEq.jl
// lib/OrdinaryDiffEqVerner/src/verner_tableaus.jl (the BigFloat strings of Vern8ExtraStages and
// Vern8InterpolationCoefficients; its stage 14 and its b agree with rklib's b on every digit).
inline constexpr std::array<std::array<double, 21>, 21> vern8_a = [] {
  std::array<std::array<double, 21>, 21> A{};
  A[1][0] = 0.05;
  A[2][0] = -0.0069931640625;
  A[2][1] = 0.1135556640625;
  A[3][0] = 0.0399609375;
  A[3][2] = 0.1198828125;
  A[4][0] = 0.3613975628004575124052940721184028345129;
  A[4][2] = -1.341524066700492771819987788202715834917;
  A[4][3] = 1.370126503900035259414693716084313000404;
  A[5][0] = 0.04904720279720279720279720279720279720280;
  A[5][3] = 0.2350972042214404739862988335493427143122;
  A[5][4] = 0.1808555929813567288109039636534544884850;
  A[6][0] = 0.06169289044289044289044289044289044289044;
  A[6][3] = 0.1123656831464027662262557035130015442303;
  A[6][4] = -0.03885046071451366767049048108111244567456;
  A[6][5] = 0.01979188712522045855379188712522045855379;
  A[7][0] = -1.767630240222326875735597119572145586714;
  A[7][3] = -62.5;
  A[7][4] = -6.061889377376669100821361459659331999758;
  A[7][5] = 5.650823198222763138561298030600840174201;
  A[7][6] = 65.62169641937623283799566054863063741227;
  A[8][0] = -1.180945066554970799825116282628297957882;
  A[8][3] = -41.50473441114320841606641502701994225874;
  A[8][4] = -4.434438319103725011225169229846100211776;
  A[8][5] = 4.260408188586133024812193710744693240761;
  A[8][6] = 43.75364022446171584987676829438379303004;
  A[8][7] = 0.007871425489912310687446475044226307550860;
  A[9][0] = -1.281405999441488405459510291182054246266;
  A[9][3] = -45.04713996013986630220754257136007322267;
  A[9][4] = -4.731362069449576477311464265491282810943;
  A[9][5] = 4.514967016593807841185851584597240996214;
  A[9][6] = 47.44909557172985134869022392235929015114;
  A[9][7] = 0.01059228297111661135687393955516542875228;
  A[9][8] = -0.005746842263844616254432318478286296232021;
  A[10][0] = -1.724470134262485191756709817484481861731;
  A[10][3] = -60.92349008483054016518434619253765246063;
  A[10][4] = -5.951518376222392455202832767061854868290;
  A[10][5] = 5.556523730698456235979791650843592496839;
  A[10][6] = 63.98301198033305336837536378635995939281;
  A[10][7] = 0.01464202825041496159275921391759452676003;
  A[10][8] = 0.06460408772358203603621865144977650714892;
  A[10][9] = -0.07930323169008878984024452548693373291447;
  A[11][0] = -3.301622667747079016353994789790983625569;
  A[11][3] = -118.0112723597525085666923303957898868510;
  A[11][4] = -10.14142238845611248642783916034510897595;
  A[11][5] = 9.139311332232057923544012273556827000619;
  A[11][6] = 123.3759428284042683684847180986501894364;
  A[11][7] = 4.623244378874580474839807625067630924792;
  A[11][8] = -3.383277738068201923652550971536811240814;
  A[11][9] = 4.527592100324618189451265339351129035325;
  A[11][10] = -5.828495485811622963193088019162985703755;
  A[12][0] = -3.039515033766309030040102851821200251056;
  A[12][3] = -109.2608680894176254686444192322164623352;
  A[12][4] = -9.290642497400293449717665542656897549158;
  A[12][5] = 8.430504981764911142134299253836167803454;
  A[12][6] = 114.2010010378331313557424041095523427476;
  A[12][7] = -0.9637271342145479358162375658987901652762;
  A[12][8] = -5.034884088802189791198680336183332323118;
  A[12][9] = 5.958130824002923177540402165388172072794;
  // row 13: the weights b (the stage at the new point)
  A[13][0] = 0.04427989419007951074716746668098518862111;
  A[13][5] = 0.3541049391724448744815552028733568354121;
  A[13][6] = 0.2479692154956437828667629415370663023884;
  A[13][7] = -15.69420203883808405099207034271191213468;
  A[13][8] = 25.08406496555856261343930031237186278518;
  A[13][9] = -31.73836778626027646833156112007297739997;
  A[13][10] = 22.93828327398878395231483560344797018313;
  A[13][11] = -0.2361324633071542145259900641263517600737;
  // rows 14–20: the extra stages of the interpolant
  A[14][0] = 0.04620700646754963101730413150238116432863;
  A[14][5] = 0.04503904160842480866828520384400679697151;
  A[14][6] = 0.2336816697713424410788701065340221126565;
  A[14][7] = 37.83901368421067410780338220861855254153;
  A[14][8] = -15.94911328945424610266139490307397370835;
  A[14][9] = 23.02836835181610285142510596329590091940;
  A[14][10] = -44.85578507769412524816130998016948002745;
  A[14][11] = -0.06379858768647444009509067402330140781326;
  A[14][13] = -0.01259503554386166268241032464519842162533;
  A[15][0] = 0.05037946855482040993065158747220696112586;
  A[15][5] = 0.04109836131046079339916530614028848248545;
  A[15][6] = 0.1718054153348195783296309209549424619697;
  A[15][7] = 4.61410531998151886974342237185977124648;
  A[15][8] = -1.791667883085396449712744996746836471721;
  A[15][9] = 2.531658930485041408462243518792913614971;
  A[15][10] = -5.32497786020573071925718815977276269909;
  A[15][11] = -0.03065532595385634734924449496356513113607;
  A[15][13] = -0.005254479979429613570549519094377878106127;
  A[15][14] = -0.08399194644224792997538653464258058697156;
  A[16][0] = 0.04082897132997079620207118756242653796386;
  A[16][5] = 0.4244479514247632218892086657732332485609;
  A[16][6] = 0.2326091531275234539465100096964845486081;
  A[16][7] = 2.677982520711806062780528871014035962908;
  A[16][8] = 0.7420826657338945216477607044022963622057;
  A[16][9] = 0.1460377847941461193920992339731312296021;
  A[16][10] = -3.579344509890565218033356743825917680543;
  A[16][11] = 0.1138844389600173704531638716149985665239;
  A[16][13] = 0.01267790651033190047378693537615687232109;
  A[16][14] = -0.07443436349946674429752785032561552478382;
  A[16][15] = 0.04782748079757851554575511473876987663388;
  A[17][0] = 0.05212682393668413629928136927994514676607;
  A[17][5] = 0.05392508396744797718209106862347065628649;
  A[17][6] = 0.01660758097434640828541930599928251901718;
  A[17][7] = -4.454485757926779655418936993298463071587;
  A[17][8] = 6.835218278632146381711296817968152631469;
  A[17][9] = -8.711334822181993739847172734848837971169;
  A[17][10] = 6.491635839232917053651267142703105653517;
  A[17][11] = -0.07072551809844346422069985227700294651922;
  A[17][13] = -0.01854031491993216429111842937941202966440;
  A[17][14] = 0.02350402105435384645116542087045962190647;
  A[17][15] = 0.2344795103407822090556377813402774776461;
  A[17][16] = -0.08241072501152898885823089698097768766651;
  A[18][0] = 0.05020102870355713598699964419977883461362;
  A[18][5] = 0.1552209034795498114932226104700567642339;
  A[18][6] = 0.1264268424089234914713091134864747506300;
  A[18][7] = -5.14920630353984701704917414605721854951;
  A[18][8] = 8.46834099903692926607453176331494311551;
  A[18][9] = -10.66213068108149527544209836207095498430;
  A[18][10] = 7.54183322495972836290996201569018333903;
  A[18][11] = -0.0743696811383214243944066492459357053774;
  A[18][13] = -0.02055887686618382619339821759221121764364;
  A[18][14] = 0.0775379526471029807261782993777862395844;
  A[18][15] = 0.1046259220352544296313761971333987587377;
  A[18][16] = -0.1179213306451979352145022687063013455111;
  A[19][0] = 0.03737341446457825692757506548800094134977;
  A[19][5] = 0.3504930705338316406767087468339071089224;
  A[19][6] = 0.4922652819373025433298989824173484805373;
  A[19][7] = 8.553695439359312242284304421725315855379;
  A[19][8] = -10.35317299030591348532574006719207803272;
  A[19][9] = 13.83320427252914990351082875460544773493;
  A[19][10] = -12.28092433078461863729523583784519048012;
  A[19][11] = 0.1719151595656509762746810113378644307112;
  A[19][13] = 0.03641583114314496380113822384214528216140;
  A[19][14] = 0.02961920580288763054890146412520723429115;
  A[19][15] = -0.2651793938627067002647615623738425030047;
  A[19][16] = 0.0942950396173806655317007970358739475630;
  A[20][0] = 0.03939058345528250943410670634923521987132;
  A[20][5] = 0.3558516141234424183136697322755323715063;
  A[20][6] = 0.4197382225952610029372225526720065366258;
  A[20][7] = 0.872044977807194166293172525204036071060;
  A[20][8] = 0.898952083487659486126627160171417043611;
  A[20][9] = -0.630580616105988359023456649527853470403;
  A[20][10] = -1.121887220595483550736681645425215081433;
  A[20][11] = 0.04298219512400197176967511031829197714867;
  A[20][13] = 0.01332557566873915707013495891889190564164;
  A[20][14] = 0.01876227053964148034446101291928097773800;
  A[20][15] = -0.1859411132922105570515379368592596513699;
  A[20][16] = 0.1773614271924602745226064729836361000042;
  return A;
}();

inline constexpr std::array<double, 13> vern8_b = [] {
  std::array<double, 13> b{};
  for (int i = 0; i < 13; ++i) b[i] = vern8_a[13][i];
  return b;
}();

// e = b − b̂ from Verner's 40-digit b and b̂, subtracted in long double before rounding to double.
inline constexpr std::array<double, 13> vern8_e = [] {
  using L = long double;
  std::array<L, 13> b{}, bhat{};
  b[0] = 0.04427989419007951074716746668098518862111L;
  b[5] = 0.3541049391724448744815552028733568354121L;
  b[6] = 0.2479692154956437828667629415370663023884L;
  b[7] = -15.69420203883808405099207034271191213468L;
  b[8] = 25.08406496555856261343930031237186278518L;
  b[9] = -31.73836778626027646833156112007297739997L;
  b[10] = 22.93828327398878395231483560344797018313L;
  b[11] = -0.2361324633071542145259900641263517600737L;
  bhat[0] = 0.04431261522908979212486436510209029764893L;
  bhat[5] = 0.3546095642343226447863179350895055038855L;
  bhat[6] = 0.2478480431366653069619986721504458660016L;
  bhat[7] = 4.448134732475784492725128317159648871312L;
  bhat[8] = 19.84688636611873369930932399297687935291L;
  bhat[9] = -23.58162337746561841969517960870394965085L;
  bhat[12] = -0.3601679437289775162124536737746202409110L;
  std::array<double, 13> e{};
  for (int i = 0; i < 13; ++i) e[i] = static_cast<double>(b[i] - bhat[i]);
  return e;
}();

// The order-8 interpolant, b_i(θ) = Σ_{m=1..8} r_im θ^m, nonzero for the stages 1, 6–12, 14–21.
inline constexpr std::array<std::array<double, 8>, 21> vern8_dense = [] {
  std::array<std::array<double, 8>, 21> R{};
  R[0] = {1.0, -10.03915465055451898280745009553727015838, 53.79210495862331394937504547285261606206,
          -165.0579057235472167092186792753028629327, 298.0264565434610102489744601822776142620,
          -311.9125448707900689751032283191627986699, 174.6059852691171542761046061351126284335,
          -40.37066163211959429657758663355894180800};
  R[5] = {0.0, 158.1976739121776138067531004299642556045, -1543.961417219490013383329186557376850919,
          6241.398747828780065219699818963300847515, -13136.51615640610824674042591770724411138,
          15106.94849316959941770760848348143558467, -8996.489626298230413000758717864256649583,
          2170.776389952444021264933974457050280938};
  R[6] = {0.0, 110.7811520079778201620910891542159716196, -1081.190514535617748557462051373884811281,
          4370.666940459977376891679103587685016930, -9199.113723922197066947453657458673365167,
          10578.94920962985483690180716390515207397, -6299.975594978841008450271944308599363057,
          1520.130500554341433782477059435641543286};
  R[7] = {0.0, -7011.442038211314089634068023254940106045, 68429.55220744077890209519664603903716349,
          -276623.5714822198169288202316196287008724, 582220.4545548494658856503006312634684934,
          -669551.5244611245601905652331468068626208, 398731.3087623332757943809792249308827732,
          -96210.47174510666745715793578288559674281};
  R[8] = {0.0, 11206.39756984814734031374482605836502113, -109371.0485495066182770525095928736321803,
          442127.8393698154661543505844693555049508, -930563.7629864562145364082427559715712707,
          1070145.133585590072636708771436125254933, -637292.8058429046904373075590712408701797,
          153773.3309185793956820086499888593205888};
  R[9] = {0.0, -14179.23164045568390825368995504736244876, 138385.0093196357218693716546019209270760,
          -559415.5490240869974273158302752589638112, 1177423.794699250413603625249340565972051,
          -1354033.322790821429356166591306087001182, 806353.8938825050195016379699232308969498,
          -194566.3328138133045593670938904445416121};
  R[10] = {0.0, 10247.76176792174468727263230424253072668, -100015.0532637523107509874155382267979521,
           404306.6240143429367125014776377339233105, -850959.9711689702682710993795157496434280,
           978601.0462088684697300958464199995189771, -582776.4729907748855939796622931794117500,
           140619.0037156383022701488158207833280861};
  R[11] = {0.0, -105.4930397685096787379931952745881034169, 1029.580139580310194120073236423148130618,
           -4162.034181876452751021493197688100770349, 8759.996193602336131526447045580160767641,
           -10073.96555688604885441046004449728532151, 5999.247741473950186438936812025268574829,
           -1447.567428588892382130036646632729629570};
  R[13] = {0.0, -14.86361337326743122469601010648237947608, 145.7635936489486611601020590400812969906,
           -587.6557063401913588520708808169444817103, 1227.372151254555709980234511427063838550,
           -1394.493105740553645217117387304216418608, 816.8562950730668774494805290335070403105,
           -192.9796145225588132959328212730088960570};
  R[14] = {0.0, 14.34968575290546223276673100484047073648, -150.2949344481665658851785896351738227010,
           629.4812425700290706612346725243246098946, -1352.518207309060677914698908083510085133,
           1575.896933708880305858556996706058962503, -946.7876580472948045886633971120598201035,
           229.8729377727072096359824945955196848017};
  R[15] = {0.0, -102.5452470111040085560664290210906322518, 1074.032661264680594125263250545103109541,
           -4498.377917100410634753487685261882069653, 9665.320624003280508099125255751992581938,
           -11261.62224831288113545795903649800929060, 6765.902468760784366342575368188597359812,
           -1642.710341604349689799450723704711058784};
  R[16] = {0.0, -38.13206313286473398334122725888547021750, 399.3854658292328681862496726489289700594,
           -1672.748720491971752312231602599596419744, 3594.107254858566583822606674735752304040,
           -4187.701556802926199931725021751236897492, 2515.941280649063720613355430002270532846,
           -610.8516609091004863949139257772330194915};
  R[17] = {0.0, -66.38279583069588062871084016403504860018, 595.8297683881103280237377269355990794854,
           -2188.737060092971609278770563269347103559, 4213.839795282852421559730676511794767863,
           -4484.035731929196864370162258757955490985, 2500.648251425346544829791147364129986790,
           -571.1622272434449401356158886201861909946};
  R[18] = {0.0, -90.41887573173058787343992868450872085904, 931.9503884048153706496188381219698380844,
           -3962.898377713156165984683269799703910403, 8733.317420025551238329244389917866097896,
           -10445.90818988766053535212385670877957360, 6426.218942917598693647793004359979629852,
           -1592.261308015418013416409177206823360972};
  R[19] = {0.0, -59.73884363038871206457816967313835076801, 544.8870146891724527559861176467523778088,
           -2090.430374926312850791322527518588562537, 4194.418982707226648046953315742901721971,
           -4603.369436819628073439413527693451638704, 2619.201413559297614510795648037620577207,
           -604.9687555793670790184208565420961249773};
  R[20] = {0.0, -59.20053764683937384859682230934791521325, 571.7660156218088014286377638724659591261,
           -2308.949564445360683785335401047607870804, 4881.234110686139058221334453291392021952,
           -5660.118807771202003386701685793459298252, 3408.706689037421803199133730396931709513,
           -833.4379054819676018284720384103746063216};
  return R;
}();
}  // namespace detail

/// Verner's most efficient 8(7) pair: order 8, an order-7 error estimate, 13 stages a step (the 13th feeds only
/// the estimate), and an order-8 continuous extension from 8 more stages (the first at the new point). The
/// estimate behaves like h⁸: control_order 8. Checked by the order conditions (order 8 for b, 7 for b − e, 8 for
/// the dense weights at every θ tried) in tests/integrators/test_rkmk_family.cpp.
/// Not offered as an RKMK method (no alias, not in the registry): measured, it does not pay. On the heavy tops
/// (benchmarks/work_precision) it is a little faster than DOP853 in either chart but slower than Verner 9(8) in
/// Cayley coordinates (docs/performance.md, "Design measurements behind the code"); and its large coefficients cost
/// accuracy: its a's (up to 123, against DOP853's 43) put more round-off on a step's end, the interpolant's
/// coefficients (up to 1.35e6) far more on its dense output, and with the double coefficients even long-double runs
/// stall above the errors at which its order 8 would show: above that floor the errors fall like h⁹ … h¹⁰
/// (docs/findings.md).
inline constexpr EmbeddedTableau<13, 21> verner8{
    .name = "rkmk_vern8",
    .title = "Runge-Kutta-Munthe-Kaas, Verner's efficient 8(7) pair with order-8 dense output (adaptive with rtol/atol)",
    .order = 8,
    .embedded_order = 7,
    .dense_order = 8,
    .control_order = 8,
    .a = detail::vern8_a,
    .b = detail::vern8_b,
    .c = {0.0, 0.05, 0.1065625, 0.15984375, 0.39, 0.465, 0.155, 0.943, 0.9018020417358569582597079406783721499560,
          0.909, 0.94, 1.0, 1.0, 1.0, 0.3110177634953863863927417318829099695921, 0.1725, 0.7846, 0.37, 0.5, 0.7,
          0.9},
    .e = detail::vern8_e,
    .e3 = {},
    .fsal = 13,
    .dense = detail::vern8_dense,
    .reference = "Verner, Numer. Algorithms 53 (2010) 383 (RKV87.IIa, efficient, with interpolant of order 8); "
                 "Munthe-Kaas, BIT 38 (1998) 92",
};

/// An embedded pair (EmbeddedTableau): error weights e and a dense output.
template <class Tab>
inline constexpr bool is_embedded_v = requires(const Tab& T) {
  T.e;
  T.dense;
};

/// Stages a fixed step needs: up to the last one with b_i ≠ 0 (an embedded pair's later stages feed only its error
/// estimate and dense output).
template <class Tab>
constexpr int update_stages(const Tab& T) {
  int n = 0;
  for (int i = 0; i < T.stages; ++i)
    if (T.b[static_cast<std::size_t>(i)] != 0) n = i + 1;
  return n;
}

/// Stages an embedded pair's dense output uses (dense_stages ≥ stages); a plain tableau's stages.
template <class Tab>
constexpr int dense_stages(const Tab& T) {
  if constexpr (is_embedded_v<Tab>) return T.dense_stages;
  else return T.stages;
}

/// True for an embedded pair with a second error estimate (DOP853: e3 not all zero).
template <class Tab>
constexpr bool has_second_estimate(const Tab& T) {
  if constexpr (is_embedded_v<Tab>) {
    for (const auto e : T.e3)
      if (e != 0) return true;
  }
  return false;
}

/// Which weights of an (embedded) tableau a sum takes: the update's b, the error estimate's e, the second
/// estimate's e3.
enum class Weights { b, e, e3 };

/// The I-th weight of kind W of Tableau (b_I, e_I or e3_I), at compile time.
template <const auto& Tableau, Weights W, int I>
constexpr auto weight() {
  if constexpr (W == Weights::b)
    return Tableau.b[I];
  else if constexpr (W == Weights::e)
    return Tableau.e[I];
  else
    return Tableau.e3[I];
}

/// Σ_i w_i K_i over the first N stages, in stage order, the zero weights skipped at compile time.
template <const auto& Tableau, Weights W, int N, class V, std::size_t M>
V weighted_sum(const std::array<V, M>& K) {
  using Scalar = typename V::Scalar;
  V s = V::Zero();
  [&]<int... I>(std::integer_sequence<int, I...>) {
    ([&] {
      if constexpr (weight<Tableau, W, I>() != 0) s += Scalar(weight<Tableau, W, I>()) * K[I];
    }(), ...);
  }(std::make_integer_sequence<int, N>{});
  return s;
}

}  // namespace tableaus
}  // namespace lgi

#undef LGI_RK
