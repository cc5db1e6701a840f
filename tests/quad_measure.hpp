// Measuring orders in quad precision (binary128): the scalar, an independent reference and the order fit of
// tests/integrators/test_quad_order.cpp. Only that test includes this header: it needs GCC's __float128, Boost's
// boost::multiprecision::float128 (header-only) and libquadmath, none of which lgi's own headers use.
//
// Why: in double and long double the errors of the order-9 methods meet the round-off floor (≈ 1e-16 with
// double coefficients) within two or three decades, before the leading h⁹ term of some of them dominates
// (tests/integrators/test_rkmk_family.cpp). In binary128, with coefficients parsed to binary128 from the source's decimal
// text (integrators/butcher_tableaus.hpp, tableaus::verner9_in<C>, dop853_in<C>), errors can be followed down
// to ≈ 1e-29.
#pragma once

#include "rk_order_conditions.hpp"
#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/core/so3.hpp>
#include <lgi/integrators/butcher_tableaus.hpp>

#include <boost/multiprecision/cpp_bin_float.hpp>
#include <boost/multiprecision/eigen.hpp>
#include <boost/multiprecision/float128.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace lgi::test::quad {

using Q = boost::multiprecision::float128;

// ---- beyond binary128 ------------------------------------------------------------------------------------
//
// Where the h⁹ term takes over only below the errors binary128 can resolve (Verner 9(8) in Cayley coordinates
// on the free body: tests/integrators/test_quad_order.cpp), the runs go to 50 decimal digits (Boost's cpp_bin_float, ≈ 5×
// the cost of binary128), with coefficients that keep all 40 of Verner's digits: DoubleQuad, an unevaluated
// sum hi + lo of two binary128 numbers (≈ 2 × 113 bits), parsed at compile time from the tableau's text
// (tableaus::detail::coefficient calls C::from_decimal).
using Wide = boost::multiprecision::number<boost::multiprecision::cpp_bin_float<50>, boost::multiprecision::et_off>;

struct DoubleQuad {
  __float128 hi = 0, lo = 0;

  // Error-free transformations in binary128 (Dekker; Knuth): a + b = s + e, a·b = p + e exactly.
  static constexpr DoubleQuad fast_two_sum(__float128 a, __float128 b) {  // |a| ≥ |b|
    const __float128 s = a + b;
    return {s, b - (s - a)};
  }
  static constexpr DoubleQuad two_sum(__float128 a, __float128 b) {
    const __float128 s = a + b, bb = s - a;
    return {s, (a - (s - bb)) + (b - bb)};
  }
  static constexpr DoubleQuad two_product(__float128 a, __float128 b) {
    constexpr __float128 splitter = __float128(1ULL << 57) + 1;  // 2^⌈113/2⌉ + 1
    const __float128 ca = splitter * a, a_hi = ca - (ca - a), a_lo = a - a_hi;
    const __float128 cb = splitter * b, b_hi = cb - (cb - b), b_lo = b - b_hi;
    const __float128 p = a * b;
    return {p, ((a_hi * b_hi - p) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo};
  }
  // x·b, x + b, x/b for a binary128 b, to ≈ 2⁻²²⁰ relative (the QD library's sloppy algorithms).
  static constexpr DoubleQuad times(const DoubleQuad& x, __float128 b) {
    const DoubleQuad p = two_product(x.hi, b);
    return fast_two_sum(p.hi, p.lo + x.lo * b);
  }
  static constexpr DoubleQuad plus(const DoubleQuad& x, __float128 b) {
    const DoubleQuad s = two_sum(x.hi, b);
    return fast_two_sum(s.hi, s.lo + x.lo);
  }
  static constexpr DoubleQuad divided(const DoubleQuad& x, __float128 b) {
    const __float128 q1 = x.hi / b;
    const DoubleQuad p = two_product(q1, b);
    const DoubleQuad r = two_sum(x.hi, -p.hi);
    const __float128 q2 = (r.hi + (r.lo - p.lo + x.lo)) / b;
    return fast_two_sum(q1, q2);
  }
  static constexpr __float128 power_of_ten(int k) {  // exact for k ≤ 48
    __float128 p = 1;
    for (int i = 0; i < k; ++i) p *= 10;
    return p;
  }

  // The decimal text, all its digits (up to 57 significant ones, in chunks of 19 that are exact integers).
  static constexpr DoubleQuad from_decimal(const char* s) {
    const tableaus::detail::DecimalDigits d = tableaus::detail::scan_decimal(s);
    const int exponent = d.exponent;
    if (exponent < -48 || exponent > 48) throw "DoubleQuad::from_decimal: exponent out of range";
    DoubleQuad m{static_cast<__float128>(d.chunk[0]), 0};
    for (int i = 1; i < 3; ++i)
      if (d.length[i] > 0) m = plus(times(m, power_of_ten(d.length[i])), static_cast<__float128>(d.chunk[i]));
    m = exponent < 0 ? divided(m, power_of_ten(-exponent)) : times(m, power_of_ten(exponent));
    return d.negative ? DoubleQuad{-m.hi, -m.lo} : m;
  }

  friend constexpr bool operator==(const DoubleQuad& a, int b) { return a.hi == b && a.lo == 0; }

  // hi + lo in a Boost number S (each part converts exactly, the sum rounds once).
  template <class S>
    requires boost::multiprecision::is_number<S>::value
  explicit operator S() const {
    return exactly<S>(hi) + exactly<S>(lo);
  }

  // A binary128 number in S with ≥ 113 bits, exactly: x = M·2^(e − 113) with the integer M < 2^113 in two parts.
  template <class S>
  static S exactly(__float128 x) {
    if (x == 0) return S(0);
    int e = 0;
    const Q m = frexp(Q(x), &e);  // |m| ∈ [0.5, 1)
    const Q M = ldexp(abs(m), 113);
    const Q M_hi = floor(ldexp(M, -64));
    const Q M_lo = M - ldexp(M_hi, 64);
    const S r = ldexp(ldexp(S(static_cast<unsigned long long>(M_hi)), 64) + S(static_cast<unsigned long long>(M_lo)),
                      e - 113);
    return m < 0 ? S(-r) : r;
  }
};

// |log(R_aᵀ R_b)| + |Ω_a − Ω_b| (the distance of tests/order_measure.hpp), computed in T.
template <class T>
double distance(const State<T>& a, const State<T>& b) {
  return static_cast<double>(so3::log(Mat3<T>(a.R.transpose() * b.R)).norm() + (a.Omega - b.Omega).norm());
}

// ---- the reference: Gragg–Bulirsch–Stoer extrapolation on the embedding ---------------------------------
//
// The rigid body in R^{3×3} × R³ (all nine entries of R and Ω, R' = R hat(Ω), JΩ' = (JΩ) × Ω + M(t, R, Ω): the
// equations of tests/order_measure.hpp's long-double RK4 reference), integrated by Gragg's explicit midpoint
// rule with Aitken–Neville extrapolation in h² (Hairer, Nørsett, Wanner, Solving ODEs I, 2nd ed., §II.9):
// macro steps H = T/M; in each, the midpoint rule with n_j substeps, n = 2, 4, 6, 8, 12, 16, 24, 32, 48, 64,
// 96, 128 (Bulirsch's sequence), for j = 1 … k, and the extrapolated value T_kk of order 2k. Bulirsch's
// sequence rather than the harmonic 2, 4, 6, …: the sum of the absolute extrapolation weights, by which the
// rounding of the n_j-runs is amplified, is 9.3 for k = 12 against 2.6e3 for the harmonic sequence — with the
// latter two runs in binary128 differed by 2e-30 to 3e-29 on the skew top, with it by 1e-32.
// Only rational coefficients ((n_j/n_m)² − 1 from integers): nothing shared with the methods measured but the
// problem data and binary128 arithmetic.
//
// gbs_extrapolate is the scheme on any y' = f(t, y) (V an Eigen vector of T); gbs_embedding applies it to the rigid
// body, tests/integrators/test_quad_order.cpp to the gyrostat's (R, m, h).
template <class T, class V, class F>
V gbs_extrapolate(const F& f, V y, double t_end, int macro_steps, int k) {
  static constexpr int sequence[] = {2, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256};
  EXPECT_LE(k, 14);
  const T H = T(t_end) / macro_steps;
  std::vector<V> table(static_cast<std::size_t>(k));  // table[m]: the column-(j − m) value of row j
  for (int s = 0; s < macro_steps; ++s) {
    const T t0 = H * s;
    const V f0 = f(t0, y);
    for (int j = 0; j < k; ++j) {
      const int n = sequence[j];
      const T h = H / n;
      V z0 = y, z1 = y + h * f0;
      for (int i = 1; i < n; ++i) {
        const V z2 = z0 + (T(2) * h) * f(t0 + h * i, z1);
        z0 = z1;
        z1 = z2;
      }
      table[static_cast<std::size_t>(j)] = z1;
      for (int m = j - 1; m >= 0; --m) {  // Aitken–Neville: T_{j,l+1} = T_{j,l} + (T_{j,l} − T_{j−1,l})/((n_j/n_{j−l})² − 1)
        const auto u = static_cast<std::size_t>(m);
        const int nj = sequence[j], nm = sequence[m];
        const T ratio = T(nj * nj - nm * nm) / T(nm * nm);
        table[u] = table[u + 1] + (table[u + 1] - table[u]) / ratio;
      }
    }
    y = table[0];
  }
  return y;
}

template <class T, RigidBodyProblem P>
State<T> gbs_embedding(const P& problem, const State<double>& x0, double t_end, int macro_steps, int k) {
  const auto p = problem.template cast<T>();
  const Mat3<T> J = p.inertia;
  const Mat3<T> J_inv = J.inverse();
  using V = Eigen::Matrix<T, 12, 1>;
  const auto f = [&](const T& t, const V& y) {
    const Mat3<T> R = Eigen::Map<const Mat3<T>>(y.data());
    const Vec3<T> W = y.template tail<3>();
    V d;
    Eigen::Map<Mat3<T>>(d.data()) = R * so3::hat(W);
    d.template tail<3>() = J_inv * Vec3<T>((J * W).cross(W) + body_torque(p, t, R, W));
    return d;
  };
  V y;
  Eigen::Map<Mat3<T>>(y.data()) = x0.R.cast<T>();
  y.template tail<3>() = x0.Omega.cast<T>();
  y = gbs_extrapolate<T>(f, y, t_end, macro_steps, k);
  State<T> x;
  x.R = Eigen::Map<const Mat3<T>>(y.data());
  x.Omega = y.template tail<3>();
  return x;
}

template <class T>
struct Reference {
  State<T> x;
  double error;  // distance to the second run
};

// Two extrapolations that share neither macro step nor depth: (H, k = 12, order 24) and (H/2, k = 10, order
// 20). Their distance bounds the reference's error (truncation and rounding of both); it is printed and every
// fitted error stays above 100× it.
template <class T, RigidBodyProblem P>
Reference<T> make_reference(const P& problem, const State<double>& x0, double t_end, int macro_steps) {
  const State<T> a = gbs_embedding<T>(problem, x0, t_end, macro_steps, 12);
  const State<T> b = gbs_embedding<T>(problem, x0, t_end, 2 * macro_steps, 10);
  const Reference<T> r{a, distance(a, b)};
  std::printf("reference over T = %g: GBS (M = %d, k = 12) against (M = %d, k = 10): %.2e\n", t_end, macro_steps,
              2 * macro_steps, r.error);
  return r;
}

// ---- fixed-step runs and the fit -----------------------------------------------------------------------

// The error of Method<P in T> after n steps of T_end/n from x0.
template <template <class> class Method, class T, RigidBodyProblem P>
double error_after(const P& problem, const State<double>& x0, double t_end, int n, const State<T>& reference) {
  using PT = rebind_problem_t<P, T>;
  Method<PT> stepper(problem.template cast<T>());
  State<T> x = x0.cast<T>();
  EXPECT_EQ(integrate_to(stepper, x, T(0), T(t_end) / n, T(t_end)).status, RunStatus::completed);
  return distance(x, reference);
}

struct Fit {
  std::vector<int> n;
  std::vector<double> h, error;
  double order = 0;
};

inline void print(const Fit& fit, int declared, const char* what) {
  for (std::size_t i = 0; i < fit.h.size(); ++i) {
    std::printf("  %-34s n = %5d  h = %.5f  error %.3e  e/h^%d = %.4e", what, fit.n[i], fit.h[i], fit.error[i], declared,
                fit.error[i] / std::pow(fit.h[i], declared));
    if (i > 0) std::printf("  local slope %.3f", std::log(fit.error[i] / fit.error[i - 1]) / std::log(fit.h[i] / fit.h[i - 1]));
    std::printf("\n");
  }
}

// The observed order in the style of tests/order_measure.hpp: step counts n = n_first·1.25^i (rounded, repeats
// skipped; n_first = 2 there, larger here only to skip runs far outside the window); points from the first error ≤ e_start, stopping after the first below e_stop or at max_points;
// the least-squares slope of log error against log h. Every point must be > 100× the reference's error.
template <template <class> class Method, class T, RigidBodyProblem P>
Fit observed_order(const P& problem, const State<double>& x0, double t_end, const Reference<T>& ref, double e_start,
                   double e_stop, int max_points, int declared, const char* what, double n_first = 2) {
  Fit fit;
  int last = 0;
  for (double n_real = n_first; n_real < 1e5 && static_cast<int>(fit.h.size()) < max_points; n_real *= 1.25) {
    const int n = static_cast<int>(std::lround(n_real));
    if (n == last) continue;
    last = n;
    const double e = error_after<Method>(problem, x0, t_end, n, ref.x);
    if (e > e_start) continue;
    fit.n.push_back(n);
    fit.h.push_back(t_end / n);
    fit.error.push_back(e);
    EXPECT_GT(e, 100 * ref.error) << what << ": error at n = " << n << " too close to the reference's";
    if (e < e_stop) break;
  }
  EXPECT_GE(fit.h.size(), 6u) << what << ": too few points";
  fit.order = fitted_order(fit.h, fit.error);
  print(fit, declared, what);
  std::printf("%-36s observed order %.3f (declared %d) over h = %.4g … %.4g, errors %.2e … %.2e, reference error "
              "%.1e\n",
              what, fit.order, declared, fit.h.front(), fit.h.back(), fit.error.front(), fit.error.back(), ref.error);
  return fit;
}

// The same runs at given step counts (for a control on the same steps).
template <template <class> class Method, class T, RigidBodyProblem P>
Fit errors_at(const P& problem, const State<double>& x0, double t_end, const Reference<T>& ref, const std::vector<int>& ns,
              int declared, const char* what) {
  Fit fit;
  for (const int n : ns) {
    fit.n.push_back(n);
    fit.h.push_back(t_end / n);
    fit.error.push_back(error_after<Method>(problem, x0, t_end, n, ref.x));
  }
  fit.order = fitted_order(fit.h, fit.error);
  print(fit, declared, what);
  std::printf("%-36s fitted slope %.3f over h = %.4g … %.4g, errors %.2e … %.2e\n", what, fit.order, fit.h.front(),
              fit.h.back(), fit.error.front(), fit.error.back());
  return fit;
}

// ---- order conditions in binary128 ----------------------------------------------------------------------

// The largest |Σ_i b_i Φ_i(τ) − 1/γ(τ)| over the rooted trees of each order 1 … max_order (index order − 1),
// evaluated in T (binary128, or 50 digits) on the first `stages` stages of the tableau (rk_order_conditions.hpp's
// trees).
template <class T = Q, class Tab>
std::vector<double> order_residuals(const Tab& tab, int stages, int max_order) {
  const std::vector<RootedTree> trees = rooted_trees(max_order);
  const auto s = static_cast<std::size_t>(stages);
  std::vector<std::vector<T>> phi(trees.size(), std::vector<T>(s, T(1)));
  std::vector<double> worst(static_cast<std::size_t>(max_order), 0.0);
  for (std::size_t t = 0; t < trees.size(); ++t) {
    for (const int c : trees[t].children)
      for (std::size_t i = 0; i < s; ++i) {
        T sum = 0;
        for (std::size_t j = 0; j < i; ++j) sum += T(tab.a[i][j]) * phi[static_cast<std::size_t>(c)][j];
        phi[t][i] *= sum;
      }
    T sum = 0;
    for (std::size_t i = 0; i < s; ++i) sum += T(tab.b[i]) * phi[t][i];
    const double r = static_cast<double>(abs(sum - T(1) / T(static_cast<double>(trees[t].gamma))));
    double& w = worst[static_cast<std::size_t>(trees[t].order - 1)];
    w = std::max(w, r);
  }
  return worst;
}

// A tableau's coefficients in another type: the double tableaus in binary128 for the control (the
// coefficients then carry the double rounding of the literals, ≈ 1e-17 relative).
template <class C, int S, int SE, int D>
constexpr EmbeddedTableau<S, SE, D, C> with_coefficients(const EmbeddedTableau<S, SE, D>& t) {
  EmbeddedTableau<S, SE, D, C> r{.name = t.name,
                                 .title = t.title,
                                 .order = t.order,
                                 .embedded_order = t.embedded_order,
                                 .dense_order = t.dense_order,
                                 .control_order = t.control_order,
                                 .a = {},
                                 .b = {},
                                 .c = {},
                                 .e = {},
                                 .e3 = {},
                                 .fsal = t.fsal,
                                 .dense = {},
                                 .reference = t.reference};
  for (int i = 0; i < SE; ++i) {
    r.c[i] = C(t.c[i]);
    for (int j = 0; j < SE; ++j) r.a[i][j] = C(t.a[i][j]);
    for (int m = 0; m < D; ++m) r.dense[i][m] = C(t.dense[i][m]);
  }
  for (int i = 0; i < S; ++i) {
    r.b[i] = C(t.b[i]);
    r.e[i] = C(t.e[i]);
    r.e3[i] = C(t.e3[i]);
  }
  return r;
}

}  // namespace lgi::test::quad
