// lgi/integrators/butcher_tableaus.hpp — explicit Runge–Kutta coefficients, as constexpr data.
//
// Each tableau carries the name under which its RKMK method is known to scenes, its classical order,
// and its reference. Adding an explicit method to lgi is adding a tableau here and one alias in rkmk.hpp.
//
//   ButcherTableau<S>        a, b, c of an explicit method: Euler (1), Heun (2), Kutta 3 (3), classical
//                            RK4 and the 3/8 rule (4)
//   EmbeddedTableau<S, SE>   an embedded pair with its error weights e = b − b̂ and a continuous extension
//                            (dense output): Dormand–Prince 5(4), DOP853 8(5,3)
//
// Every coefficient set is checked against the Runge–Kutta order conditions (all rooted trees up to the
// declared order, evaluated numerically) in tests/test_rkmk_family.cpp, and by observed order.
//
// The coefficients are doubles, also when a method runs in long double: the order conditions then hold only
// to ~1e-16 (e.g. Σ b_i − 1 of DOP853 and of 1/6, 1/3, 1/3, 1/6 in double), which adds an error of ~1e-16 per
// unit time to a long-double run — measured for DOP853 on the quaternion embedding: 3.3e-16 over T = 2 (skew
// heavy top), 1.1e-15 over T = 10 (free body) against a long-double reference (tests/order_measure.hpp).
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

// Heun's method (the explicit trapezoidal rule): order 2. K. Heun, Z. Math. Phys. 45 (1900) 23–38;
// Hairer, Nørsett, Wanner, Solving ODEs I, 2nd ed., §II.1 (its table number there not confirmed: the book
// was not available to us).
inline constexpr ButcherTableau<2> heun{
    .name = "rkmk_heun",
    .title = "Runge-Kutta-Munthe-Kaas, Heun (explicit trapezoidal rule)",
    .order = 2,
    .a = {{{0.0, 0.0}, {1.0, 0.0}}},
    .b = {0.5, 0.5},
    .c = {0.0, 1.0},
    .reference = "Heun, Z. Math. Phys. 45 (1900) 23; Munthe-Kaas, BIT 38 (1998) 92",
};

// Kutta's third-order method: c = (0, 1/2, 1), a21 = 1/2, a31 = −1, a32 = 2, b = (1/6, 2/3, 1/6).
// W. Kutta, Z. Math. Phys. 46 (1901) 435–453; Hairer, Nørsett, Wanner, Solving ODEs I, §II.1 (its
// table number there not confirmed: the book was not available to us).
inline constexpr ButcherTableau<3> kutta3{
    .name = "rkmk3",
    .title = "Runge-Kutta-Munthe-Kaas, Kutta's third-order method",
    .order = 3,
    .a = {{{0.0, 0.0, 0.0}, {0.5, 0.0, 0.0}, {-1.0, 2.0, 0.0}}},
    .b = {1.0 / 6, 2.0 / 3, 1.0 / 6},
    .c = {0.0, 0.5, 1.0},
    .reference = "Kutta, Z. Math. Phys. 46 (1901) 435; Munthe-Kaas, BIT 38 (1998) 92",
};

// Kutta's 3/8 rule: order 4. Kutta (1901); Hairer, Nørsett, Wanner, Solving ODEs I, Table II.1.2 (right).
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
//
// An explicit pair (b of order p, b̂ of a lower order) with dense output. The layout extends ButcherTableau:
// `stages` stages make a step and its error estimate; `dense_stages` ≥ `stages` adds the stages the
// continuous extension needs (the first-same-as-last stage at the new point, and DOP853's three extra ones).
//
//   step:            y₁ = y₀ + h Σ_{i<stages} b_i k_i
//   error estimate:  δ = h Σ e_i k_i with e = b − b̂; DOP853 has a second one, δ₃ = h Σ e3_i k_i (else e3 = 0)
//   dense output:    y(t₀ + θh) = y₀ + h Σ_{i<dense_stages} b_i(θ) k_i,   b_i(θ) = Σ_{m=1..8} dense[i][m−1] θ^m
//
// The dense weights are built (constexpr) from the published Hermite-type form of Hairer's codes DOPRI5 and
// DOP853, with s = θ, s' = 1 − θ, y₁ − y₀ = h Σ b_i k_i, k_f the stage at the new point (index `fsal`):
//   y(θ) = y₀ + s(r₁ + s'(r₂ + s(r₃ + s'(r₄ + s(r₅ + s'(r₆ + s r₇))))))
//   r₁ = y₁ − y₀,  r₂ = h k₁ − r₁,  r₃ = r₁ − h k_f − r₂ = 2r₁ − h(k₁ + k_f),  r_{3+j} = h Σ_i d[j][i] k_i.
template <int S, int SE>
struct EmbeddedTableau {
  static constexpr int stages = S;
  static constexpr int dense_stages = SE;
  std::string_view name;
  std::string_view title;
  int order;            // of b
  int embedded_order;   // of b̂ = b − e
  int dense_order;      // of the continuous extension
  int control_order;    // k in the step-size rule h ∝ err^(−1/k) (the estimate behaves like h^k)
  std::array<std::array<double, SE>, SE> a;  // strictly lower triangular; rows ≥ S: dense-output stages
  std::array<double, S> b;
  std::array<double, SE> c;
  std::array<double, S> e;   // b − b̂
  std::array<double, S> e3;  // DOP853: b − b̂₃ (third order); zero otherwise
  int fsal;                  // index of the stage at the new point (a[fsal] = b)
  std::array<std::array<double, 8>, SE> dense;
  std::string_view reference;
};

namespace tableaus::detail {

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
template <int S, int SE, int ND>
constexpr std::array<std::array<double, 8>, SE> hermite_dense(const std::array<double, S>& b, int fsal,
                                                               const std::array<std::array<double, SE>, ND>& d) {
  std::array<std::array<double, 8>, SE> w{};
  const auto add = [&](int term, int i, double coefficient) {  // term m: θ^⌈m/2⌉ (1 − θ)^⌊m/2⌋
    const Poly p = theta_power((term + 1) / 2, term / 2);
    for (int k = 1; k < 9; ++k) w[i][k - 1] += coefficient * p[k];
  };
  for (int i = 0; i < SE; ++i) {
    const double bi = i < S ? b[i] : 0.0;
    add(1, i, bi);                                                   // r₁
    add(2, i, (i == 0 ? 1.0 : 0.0) - bi);                            // r₂
    add(3, i, 2 * bi - (i == 0 ? 1.0 : 0.0) - (i == fsal ? 1.0 : 0.0));  // r₃
    for (int j = 0; j < ND; ++j) add(4 + j, i, d[j][i]);             // r₄ …
  }
  return w;
}

}  // namespace tableaus::detail

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

// Dormand & Prince, J. Comput. Appl. Math. 6 (1980) 19–26 (the pair RK5(4)7M); Hairer, Nørsett, Wanner,
// Solving ODEs I, 2nd ed. (1993), §II.5 (Table 5.2 there: a number from memory, also so cited in third-party
// code, but not checked against the 2nd edition, which was not available to us; Hairer's dopri5.f names the
// book without section or table; the 1st edition's appendix points to its Table 4.6 of §II.4, so a table
// number needs its edition); dense output
// of order 4 by Shampine, Math. Comp. 46 (1986) 135–150, in the form of Hairer & Wanner's DOPRI5 code
// (HNW I §II.6). Coefficients cross-checked against two independent transcriptions of DOPRI5 and by the
// order conditions (tests/test_rkmk_family.cpp).
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
inline constexpr std::array<std::array<double, 16>, 16> dop853_a = [] {
  std::array<std::array<double, 16>, 16> A{};
  A[1][0] = 5.26001519587677318785587544488e-2;
  A[2][0] = 1.97250569845378994544595329183e-2;
  A[2][1] = 5.91751709536136983633785987549e-2;
  A[3][0] = 2.95875854768068491816892993775e-2;
  A[3][2] = 8.87627564304205475450678981324e-2;
  A[4][0] = 2.41365134159266685502369798665e-1;
  A[4][2] = -8.84549479328286085344864962717e-1;
  A[4][3] = 9.24834003261792003115737966543e-1;
  A[5][0] = 3.7037037037037037037037037037e-2;
  A[5][3] = 1.70828608729473871279604482173e-1;
  A[5][4] = 1.25467687566822425016691814123e-1;
  A[6][0] = 3.7109375e-2;
  A[6][3] = 1.70252211019544039314978060272e-1;
  A[6][4] = 6.02165389804559606850219397283e-2;
  A[6][5] = -1.7578125e-2;
  A[7][0] = 3.70920001185047927108779319836e-2;
  A[7][3] = 1.70383925712239993810214054705e-1;
  A[7][4] = 1.07262030446373284651809199168e-1;
  A[7][5] = -1.53194377486244017527936158236e-2;
  A[7][6] = 8.27378916381402288758473766002e-3;
  A[8][0] = 6.24110958716075717114429577812e-1;
  A[8][3] = -3.36089262944694129406857109825;
  A[8][4] = -8.68219346841726006818189891453e-1;
  A[8][5] = 2.75920996994467083049415600797e1;
  A[8][6] = 2.01540675504778934086186788979e1;
  A[8][7] = -4.34898841810699588477366255144e1;
  A[9][0] = 4.77662536438264365890433908527e-1;
  A[9][3] = -2.48811461997166764192642586468;
  A[9][4] = -5.90290826836842996371446475743e-1;
  A[9][5] = 2.12300514481811942347288949897e1;
  A[9][6] = 1.52792336328824235832596922938e1;
  A[9][7] = -3.32882109689848629194453265587e1;
  A[9][8] = -2.03312017085086261358222928593e-2;
  A[10][0] = -9.3714243008598732571704021658e-1;
  A[10][3] = 5.18637242884406370830023853209;
  A[10][4] = 1.09143734899672957818500254654;
  A[10][5] = -8.14978701074692612513997267357;
  A[10][6] = -1.85200656599969598641566180701e1;
  A[10][7] = 2.27394870993505042818970056734e1;
  A[10][8] = 2.49360555267965238987089396762;
  A[10][9] = -3.0467644718982195003823669022;
  A[11][0] = 2.27331014751653820792359768449;
  A[11][3] = -1.05344954667372501984066689879e1;
  A[11][4] = -2.00087205822486249909675718444;
  A[11][5] = -1.79589318631187989172765950534e1;
  A[11][6] = 2.79488845294199600508499808837e1;
  A[11][7] = -2.85899827713502369474065508674;
  A[11][8] = -8.87285693353062954433549289258;
  A[11][9] = 1.23605671757943030647266201528e1;
  A[11][10] = 6.43392746015763530355970484046e-1;
  // row 12: the weights b (the stage at the new point)
  A[12][0] = 5.42937341165687622380535766363e-2;
  A[12][5] = 4.45031289275240888144113950566;
  A[12][6] = 1.89151789931450038304281599044;
  A[12][7] = -5.8012039600105847814672114227;
  A[12][8] = 3.1116436695781989440891606237e-1;
  A[12][9] = -1.52160949662516078556178806805e-1;
  A[12][10] = 2.01365400804030348374776537501e-1;
  A[12][11] = 4.47106157277725905176885569043e-2;
  // rows 13–15: the extra stages of the dense output
  A[13][0] = 5.61675022830479523392909219681e-2;
  A[13][6] = 2.53500210216624811088794765333e-1;
  A[13][7] = -2.46239037470802489917441475441e-1;
  A[13][8] = -1.24191423263816360469010140626e-1;
  A[13][9] = 1.5329179827876569731206322685e-1;
  A[13][10] = 8.20105229563468988491666602057e-3;
  A[13][11] = 7.56789766054569976138603589584e-3;
  A[13][12] = -8.298e-3;
  A[14][0] = 3.18346481635021405060768473261e-2;
  A[14][5] = 2.83009096723667755288322961402e-2;
  A[14][6] = 5.35419883074385676223797384372e-2;
  A[14][7] = -5.49237485713909884646569340306e-2;
  A[14][10] = -1.08347328697249322858509316994e-4;
  A[14][11] = 3.82571090835658412954920192323e-4;
  A[14][12] = -3.40465008687404560802977114492e-4;
  A[14][13] = 1.41312443674632500278074618366e-1;
  A[15][0] = -4.28896301583791923408573538692e-1;
  A[15][5] = -4.69762141536116384314449447206;
  A[15][6] = 7.68342119606259904184240953878;
  A[15][7] = 4.06898981839711007970213554331;
  A[15][8] = 3.56727187455281109270669543021e-1;
  A[15][12] = -1.39902416515901462129418009734e-3;
  A[15][13] = 2.9475147891527723389556272149;
  A[15][14] = -9.15095847217987001081870187138;
  return A;
}();

inline constexpr std::array<double, 12> dop853_b = [] {
  std::array<double, 12> b{};
  for (int i = 0; i < 12; ++i) b[i] = dop853_a[12][i];
  return b;
}();

// e3 = b − b̂₃, the third-order weights bhh₁, bhh₉, bhh₁₂ of dop853.f.
inline constexpr std::array<double, 12> dop853_e3 = [] {
  std::array<double, 12> e = dop853_b;
  e[0] -= 0.244094488188976377952755905512;
  e[8] -= 0.733846688281611857341361741547;
  e[11] -= 0.220588235294117647058823529412e-1;
  return e;
}();

// The rows d₄ … d₇ of dop853.f's dense output (r₄ … r₇ above).
inline constexpr std::array<std::array<double, 16>, 4> dop853_d = [] {
  std::array<std::array<double, 16>, 4> D{};
  D[0][0] = -0.84289382761090128651353491142e1;
  D[0][5] = 0.56671495351937776962531783590;
  D[0][6] = -0.30689499459498916912797304727e1;
  D[0][7] = 0.23846676565120698287728149680e1;
  D[0][8] = 0.21170345824450282767155149946e1;
  D[0][9] = -0.87139158377797299206789907490;
  D[0][10] = 0.22404374302607882758541771650e1;
  D[0][11] = 0.63157877876946881815570249290;
  D[0][12] = -0.88990336451333310820698117400e-1;
  D[0][13] = 0.18148505520854727256656404962e2;
  D[0][14] = -0.91946323924783554000451984436e1;
  D[0][15] = -0.44360363875948939664310572000e1;
  D[1][0] = 0.10427508642579134603413151009e2;
  D[1][5] = 0.24228349177525818288430175319e3;
  D[1][6] = 0.16520045171727028198505394887e3;
  D[1][7] = -0.37454675472269020279518312152e3;
  D[1][8] = -0.22113666853125306036270938578e2;
  D[1][9] = 0.77334326684722638389603898808e1;
  D[1][10] = -0.30674084731089398182061213626e2;
  D[1][11] = -0.93321305264302278729567221706e1;
  D[1][12] = 0.15697238121770843886131091075e2;
  D[1][13] = -0.31139403219565177677282850411e2;
  D[1][14] = -0.93529243588444783865713862664e1;
  D[1][15] = 0.35816841486394083752465898540e2;
  D[2][0] = 0.19985053242002433820987653617e2;
  D[2][5] = -0.38703730874935176555105901742e3;
  D[2][6] = -0.18917813819516756882830838328e3;
  D[2][7] = 0.52780815920542364900561016686e3;
  D[2][8] = -0.11573902539959630126141871134e2;
  D[2][9] = 0.68812326946963000169666922661e1;
  D[2][10] = -0.10006050966910838403183860980e1;
  D[2][11] = 0.77771377980534432092869265740;
  D[2][12] = -0.27782057523535084065932004339e1;
  D[2][13] = -0.60196695231264120758267380846e2;
  D[2][14] = 0.84320405506677161018159903784e2;
  D[2][15] = 0.11992291136182789328035130030e2;
  D[3][0] = -0.25693933462703749003312586129e2;
  D[3][5] = -0.15418974869023643374053993627e3;
  D[3][6] = -0.23152937917604549567536039109e3;
  D[3][7] = 0.35763911791061412378285349910e3;
  D[3][8] = 0.93405324183624310003907691704e2;
  D[3][9] = -0.37458323136451633156875139351e2;
  D[3][10] = 0.10409964950896230045147246184e3;
  D[3][11] = 0.29840293426660503123344363579e2;
  D[3][12] = -0.43533456590011143754432175058e2;
  D[3][13] = 0.96324553959188282948394950600e2;
  D[3][14] = -0.39177261675615439165231486172e2;
  D[3][15] = -0.14972683625798562581422125276e3;
  return D;
}();
}  // namespace detail

// DOP853: the explicit order-8 method of Dormand & Prince with Hairer's error estimator of orders 5 and 3
// and an order-7 continuous extension. Prince & Dormand, J. Comput. Appl. Math. 7 (1981) 67–75 (the
// RK8(7)13M family); the 8(5,3) version and its dense output: Hairer, Nørsett, Wanner, Solving ODEs I,
// 2nd ed. (1993), §II.5 and §II.6, code dop853.f (section numbers from memory; table and equation numbers
// not confirmed — the book was not available to us, and dop853.f's header cites only the book). Error
// estimate of dop853.f: err = ‖δ₅‖² / √(‖δ₅‖² + 0.01 ‖δ₃‖²) (RMS norms of the scaled
// components), which behaves like h⁸: control_order 8. Checked by the order conditions (order 8 for b,
// 5 for b − e, 3 for b − e3, 7 for the dense weights) in tests/test_rkmk_family.cpp.
inline constexpr EmbeddedTableau<12, 16> dop853{
    .name = "rkmk_dp8",
    .title = "Runge-Kutta-Munthe-Kaas, DOP853 8(5,3) with dense output (adaptive with rtol/atol)",
    .order = 8,
    .embedded_order = 5,
    .dense_order = 7,
    .control_order = 8,
    .a = detail::dop853_a,
    .b = detail::dop853_b,
    .c = {0.0, 0.526001519587677318785587544488e-01, 0.789002279381515978178381316732e-01,
          0.118350341907227396726757197510, 0.281649658092772603273242802490, 0.333333333333333333333333333333,
          0.25, 0.307692307692307692307692307692, 0.651282051282051282051282051282, 0.6,
          0.857142857142857142857142857142, 1.0, 1.0, 0.1, 0.2, 0.777777777777777777777777777778},
    .e = {0.1312004499419488073250102996e-1, 0.0, 0.0, 0.0, 0.0, -0.1225156446376204440720569753e1,
          -0.4957589496572501915214079952, 0.1664377182454986536961530415e1, -0.3503288487499736816886487290,
          0.3341791187130174790297318841, 0.8192320648511571246570742613e-1, -0.2235530786388629525884427845e-1},
    .e3 = detail::dop853_e3,
    .fsal = 12,
    .dense = tableaus::detail::hermite_dense<12, 16, 4>(detail::dop853_b, 12, detail::dop853_d),
    .reference = "Prince-Dormand, J. Comput. Appl. Math. 7 (1981) 67; Hairer-Norsett-Wanner I, sec. II.5-II.6 (dop853); "
                 "Munthe-Kaas, BIT 38 (1998) 92",
};

}  // namespace tableaus
}  // namespace lgi
