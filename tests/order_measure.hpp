// Measuring helpers shared by the RKMK-family, adaptive, projection and baseline tests: an independent
// long-double reference, the test cases, and the observed order over a step sequence.
#pragma once

#include "test_problems.hpp"

#include <lgi/core/driver.hpp>
#include <lgi/integrators/embedding.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace lgi::test {

// The reference: classical RK4 in long double on the 12-dimensional embedding (all nine entries of R and
// Ω; the algorithm of test_problems.hpp, kept in long double to the end), a different method, coordinates
// and precision from every method measured here, with 320000 steps. Its own error is estimated twice:
//   truncation  from the run with half the steps (16× the truncation error): |fine − coarse|/15;
//   everything  (truncation and the rounding of 320000 long-double steps, which Richardson cannot see)
//               from the same RK4, with its coefficients exact in long double, on another embedding: the
//               unit quaternion and Ω (R(q/|q|) for the torque), whose truncation and rounding errors are
//               different; the distance between the two runs.
// The reference's error is the larger of the two, printed and required below 1e-16; every error fitted
// stays above 100× it (so the reference moves no fitted error by more than 1 %).
// (Not a cross-check: lgi's own long-double DOP853 — its coefficients are doubles, so its order conditions
// hold only to ~1e-16 and it carries an error floor of that size per unit time: measured 3.3e-16 over T = 2
// on the skew top and 1.1e-15 over T = 10 on the GNI body against this reference. The order-8 fits below stop
// at errors ≥ 1e-14, above that floor.)
using L = long double;

struct Reference {
  State<L> x;
  double error;              // max(truncation, cross_check)
  double truncation = 0;     // |fine − coarse|/15
  double cross_check = 0;    // distance to the DOP853 quaternion run
};

// States at t = T·m/M, m = 1 … M (M divides n), from n RK4 steps of T/n.
template <class P>
std::vector<State<L>> rk4_embedding_long_double_track(const P& problem, const State<double>& x0, double T, int n,
                                                      int M) {
  const auto p = problem.template cast<L>();
  const Mat3<L> J = p.inertia;
  const Mat3<L> J_inv = J.inverse();
  struct Y {
    Mat3<L> R;
    Vec3<L> W;
  };
  const auto f = [&](const L& t, const Y& y) {
    const Vec3<L> rhs = (J * y.W).cross(y.W) + body_torque(p, t, y.R, y.W);
    return Y{y.R * so3::hat(y.W), J_inv * rhs};
  };
  const auto axpy = [](const Y& y, L a, const Y& k) { return Y{y.R + a * k.R, y.W + a * k.W}; };
  Y y{x0.R.cast<L>(), x0.Omega.cast<L>()};
  const L h = L(T) / n;
  std::vector<State<L>> out;
  for (int i = 0; i < n; ++i) {
    const L t = L(T) * i / n;
    const Y k1 = f(t, y), k2 = f(t + h / 2, axpy(y, h / 2, k1)), k3 = f(t + h / 2, axpy(y, h / 2, k2)),
            k4 = f(t + h, axpy(y, h, k3));
    y.R += (h / 6) * (k1.R + 2 * k2.R + 2 * k3.R + k4.R);
    y.W += (h / 6) * (k1.W + 2 * k2.W + 2 * k3.W + k4.W);
    if ((i + 1) % (n / M) == 0) out.push_back({y.R, y.W});
  }
  return out;
}

template <class P>
State<L> rk4_embedding_long_double(const P& problem, const State<double>& x0, double T, int n) {
  return rk4_embedding_long_double_track(problem, x0, T, n, 1).back();
}

// The same classical RK4 in long double on (q, Ω) ∈ R⁴ × R³: q' = ½ q ⊗ (0, Ω), the torque at R(q/|q|).
template <class P>
State<L> rk4_quaternion_long_double(const P& problem, const State<double>& x0, double T, int n) {
  const auto p = problem.template cast<L>();
  const Mat3<L> J = p.inertia;
  const Mat3<L> J_inv = J.inverse();
  using V7 = Eigen::Matrix<L, 7, 1>;
  const auto rotation = [](const V7& y) {
    const Eigen::Matrix<L, 4, 1> q = y.template head<4>() / y.template head<4>().norm();
    return embedding::rotation_of(q);
  };
  const auto f = [&](const L& t, const V7& y) {
    const Vec3<L> v = y.template segment<3>(1), W = y.template tail<3>();
    V7 d;
    d(0) = -v.dot(W) / 2;
    d.template segment<3>(1) = (y(0) * W + v.cross(W)) / 2;
    d.template tail<3>() = J_inv * Vec3<L>((J * W).cross(W) + body_torque(p, t, rotation(y), W));
    return d;
  };
  V7 y;
  y.template head<4>() = embedding::quaternion_of(Mat3<L>(x0.R.cast<L>()));
  y.template tail<3>() = x0.Omega.cast<L>();
  const L h = L(T) / n;
  for (int i = 0; i < n; ++i) {
    const L t = L(T) * i / n;
    const V7 k1 = f(t, y), k2 = f(t + h / 2, V7(y + (h / 2) * k1)), k3 = f(t + h / 2, V7(y + (h / 2) * k2)),
             k4 = f(t + h, V7(y + h * k3));
    y += (h / 6) * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return {rotation(y), y.template tail<3>()};
}

// |log(R_aᵀ R_b)| + |Ω_a − Ω_b| in long double.
inline double distance(const State<L>& a, const State<L>& b) {
  return static_cast<double>(so3::log(Mat3<L>(a.R.transpose() * b.R)).norm() + (a.Omega - b.Omega).norm());
}

template <class P>
Reference make_reference(const P& problem, const State<double>& x0, double T) {
  const State<L> fine = rk4_embedding_long_double(problem, x0, T, 320000);
  const State<L> coarse = rk4_embedding_long_double(problem, x0, T, 160000);
  Reference r{fine, 0, distance(fine, coarse) / 15.0, distance(fine, rk4_quaternion_long_double(problem, x0, T, 320000))};
  r.error = std::max(r.truncation, r.cross_check);
  std::printf("reference over T = %g: truncation %.1e (Richardson), distance to the quaternion RK4 run %.1e\n", T,
              r.truncation, r.cross_check);
  return r;
}

// The cases. Heavy top: the skew top of test_problems.hpp (non-diagonal J, z0 and k off the principal
// axes), T = 2. Free body: the GNI book's body J = diag(2, 1, 2/3), m0 = (cos 1.1, 0, sin 1.1) (NUMERICS.md),
// T = 10. (On the Hairer–Vilmart free body over T = 2, DOP853 shows ≈ 9 instead of 8 over most of the
// range of errors: see HairerVilmartFreeBodyDop853 below.)
inline const HeavyTop<double>& skew_top() {
  static const HeavyTop<double> p = test::skew_heavy_top();
  return p;
}
inline const FreeBody<double>& gni_body() {
  static const FreeBody<double> p{Vec3<double>(2.0, 1.0, 2.0 / 3).asDiagonal()};
  return p;
}
inline State<double> gni_state() {
  return {Mat3<double>::Identity(), gni_body().inertia.inverse() * Vec3<double>(std::cos(1.1), 0.0, std::sin(1.1))};
}
inline const Reference& skew_reference() {
  static const Reference r = make_reference(skew_top(), test::skew_initial_state(), 2.0);
  return r;
}
inline const Reference& gni_reference() {
  static const Reference r = make_reference(gni_body(), gni_state(), 10.0);
  return r;
}

// Step counts n over [0, T]: a geometric sequence n = 2 q^i (q = 2 up to order 4, 1.5 for order 5, 1.25
// for order 8) restricted to the asymptotic range h|Ω(0)| ≤ 0.4 and an error below 1e-3 (orders ≤ 2),
// 1e-5 (orders 3, 4) or 1e-6 (orders 5, 8); up to 8 points, stopping below 1e-12 (double) or 1e-14 (long
// double) or 2e3× the reference's error. Methods of order 8 run in long double (the problem cast to long double: everything in lgi is a
// template on the scalar): in double their errors cross the round-off-free window (1e-6 … 1e-12) within
// three or four points.
template <template <class> class Method, class P>
double observed_order(const P& problem, const State<double>& x0, double T, const Reference& ref, const char* label,
                      double max_h_omega = 0.4) {
  EXPECT_LT(ref.error, 1e-16) << "reference not converged";
  constexpr int order = Method<P>::traits.order;
  const bool extended = order >= 8;
  const double q = order <= 4 ? 2.0 : order == 5 ? 1.5 : 1.25;
  const double e_start = order <= 2 ? 1e-3 : order <= 4 ? 1e-5 : 1e-6;
  const double e_stop = std::max(extended ? 1e-14 : 1e-12, 2e3 * ref.error);
  std::vector<double> hs, errors;
  int last_n = 0;
  for (double n_real = 2; n_real < 1e6 && hs.size() < 8; n_real *= q) {
    const int n = static_cast<int>(std::lround(n_real));
    if (n == last_n || (T / n) * x0.Omega.norm() > max_h_omega) continue;
    last_n = n;
    double error = 0;
    if (extended) {
      using PL = rebind_problem_t<P, L>;
      Method<PL> stepper(problem.template cast<L>());
      State<L> x = x0.cast<L>();
      EXPECT_EQ(integrate_to(stepper, x, L(0), L(T) / n, L(T)).status, RunStatus::completed);
      error = distance(x, ref.x);
    } else {
      Method<P> stepper(problem);
      State<double> x = x0;
      EXPECT_EQ(integrate_to(stepper, x, 0.0, T / n, T).status, RunStatus::completed);
      error = distance(x.cast<L>(), ref.x);
    }
    if (error > e_start) continue;
    if (error < e_stop && hs.size() >= 4) break;
    hs.push_back(T / n);
    errors.push_back(error);
    EXPECT_GT(error, 100 * ref.error) << Method<P>::traits.name << ": error too close to the reference's";
  }
  EXPECT_GE(hs.size(), 4u) << Method<P>::traits.name << ": too few points in the asymptotic range";
  const double p = test::fitted_order(hs, errors);
  std::printf("%-10s %-10s observed order %.3f (declared %d, %s), h %.3g .. %.3g, errors %.3e .. %.3e, reference "
              "error %.1e\n",
              Method<P>::traits.name.data(), label, p, order, extended ? "long double" : "double", hs.front(),
              hs.back(), errors.front(), errors.back(), ref.error);
  return p;
}

}  // namespace lgi::test
