// Shared test data and an independent reference integrator.
//
// The reference integrates the rigid body in the embedding R^{3×3} × R³ (all nine entries of R and Ω)
// with the classical RK4 in long double — a different method, coordinates and precision from every lgi
// integrator, so that an error measured against it belongs to the method under test.
#pragma once

#include <lgi/core/problem.hpp>
#include <lgi/core/so3.hpp>
#include <lgi/core/state.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string_view>
#include <vector>

namespace lgi::test {

// exp(w) for the tests' initial attitudes (0.1 ≤ |w| ≤ π), as fixed data: Rodrigues' formula with A = sin θ/θ and
// B = 2 (sin(θ/2)/θ)² from core/trig.hpp's polynomial sin, whatever so3::exp's own evaluation of its coefficients
// is. Several tests measure round-off-sized quantities (orthogonality after 5e5 steps, energy rises of a few ulps,
// a reference's cross-check at 1e-16) whose values depend on the fixture's last bits; a change to exp should not
// move their inputs.
inline Mat3<double> fixture_rotation(const Vec3<double>& w) {
  const double theta = w.norm();
  if (!(theta >= 0.1 && theta <= trig::max_argument))
    throw std::invalid_argument("fixture_rotation: |w| outside [0.1, pi]");
  const double s = trig::sin_0_pi(theta / 2) / theta;
  return so3::rodrigues(w, trig::sin_0_pi(theta) / theta, 2 * s * s);
}

// A heavy top with nothing aligned: non-diagonal inertia (principal moments 0.9, 1.3, 1.7 rotated by
// Q = exp(0.3, −0.5, 0.7)), z0 and k off the principal axes, a tilted initial attitude.
inline HeavyTop<double> skew_heavy_top() {
  HeavyTop<double> p;
  const Mat3<double> Q = fixture_rotation(Vec3<double>(0.3, -0.5, 0.7));
  p.inertia = Q * Vec3<double>(0.9, 1.3, 1.7).asDiagonal() * Q.transpose();
  p.inertia = 0.5 * (p.inertia + p.inertia.transpose()).eval();
  p.b = 1.3;
  p.k = Vec3<double>(0.1, 0.6, 0.8).normalized();
  p.z0 = Vec3<double>(0.3, -0.4, 0.87).normalized();
  return p;
}

inline State<double> skew_initial_state() {
  return {fixture_rotation(Vec3<double>(0.4, 0.2, -0.3)), Vec3<double>(0.7, -0.4, 1.1)};
}

// The Hairer–Vilmart initial state: m0 = JΩ0 = (1.8, 0.4, −0.9), R0 = I (NUMERICS.md).
// A torque that reads Ω and t (core/problem.hpp, StateTorqueProblem): a heavy top with linear damping and a periodic body-frame drive:
//   M(t, R, Ω) = b (Rᵀk) × z0 − C Ω + a sin(w t),
// C symmetric positive semi-definite. Energy E = ½ Ω·JΩ + b k·(R z0); dE/dt = Ω·(a sin(w t) − C Ω).
template <class T = double>
struct DrivenDampedTop {
  using Scalar = T;
  static constexpr std::string_view name = "driven_damped_top";
  static constexpr bool has_torque = true;

  HeavyTop<T> top;
  Mat3<T> inertia = top.inertia;
  Mat3<T> C = Mat3<T>::Zero();
  Vec3<T> a = Vec3<T>::Zero();
  T w = T(0);

  T potential(const Mat3<T>& R) const { return top.potential(R); }
  Vec3<T> torque(const T& t, const Mat3<T>& R, const Vec3<T>& Omega) const {
    using std::sin;
    return top.torque(R) - C * Omega + a * sin(w * t);
  }
  /// Ω·M_nc, the power of the non-conservative part.
  T power(const T& t, const Vec3<T>& Omega) const {
    using std::sin;
    return Omega.dot(Vec3<T>(a * sin(w * t) - C * Omega));
  }
  static constexpr std::array<std::string_view, 0> invariant_names{};
  std::array<T, 0> invariants(const State<T>&) const { return {}; }
  template <class S>
  DrivenDampedTop<S> cast() const {
    return {top.template cast<S>(), inertia.template cast<S>(), C.template cast<S>(), a.template cast<S>(), S(w)};
  }
};

inline DrivenDampedTop<double> driven_damped_skew_top() {
  DrivenDampedTop<double> p;
  p.top = skew_heavy_top();
  p.inertia = p.top.inertia;
  p.C << 0.30, 0.05, 0.00,  //
      0.05, 0.20, 0.02,     //
      0.00, 0.02, 0.10;
  p.a = Vec3<double>(0.4, -0.3, 0.2);
  p.w = 3.0;
  return p;
}

template <class P>
State<double> hairer_vilmart_state(const P& p) {
  return {Mat3<double>::Identity(), p.inertia.inverse() * Vec3<double>(1.8, 0.4, -0.9)};
}

// Classical RK4 on (R, Ω) ∈ R^{3×3} × R³ in long double, n steps over [0, T].
template <RigidBodyProblem P>
State<double> reference_solution(const P& problem, const State<double>& x0, double T, int n) {
  using L = long double;
  const auto p = problem.template cast<L>();
  const Mat3<L> J = p.inertia;
  const Mat3<L> J_inv = J.inverse();
  struct Y {
    Mat3<L> R;
    Vec3<L> W;
  };
  const auto f = [&](const Y& y) {
    Vec3<L> rhs = (J * y.W).cross(y.W) + body_torque(p, L(0), y.R, y.W);
    return Y{y.R * so3::hat(y.W), J_inv * rhs};
  };
  const auto axpy = [](const Y& y, L a, const Y& k) { return Y{y.R + a * k.R, y.W + a * k.W}; };
  Y y{x0.R.cast<L>(), x0.Omega.cast<L>()};
  const L h = L(T) / n;
  for (int i = 0; i < n; ++i) {
    const Y k1 = f(y), k2 = f(axpy(y, h / 2, k1)), k3 = f(axpy(y, h / 2, k2)), k4 = f(axpy(y, h, k3));
    y.R += (h / 6) * (k1.R + 2 * k2.R + 2 * k3.R + k4.R);
    y.W += (h / 6) * (k1.W + 2 * k2.W + 2 * k3.W + k4.W);
  }
  return {y.R.template cast<double>(), y.W.template cast<double>()};
}

// Distance between states: |log(R_aᵀ R_b)| + |Ω_a − Ω_b|.
inline double state_distance(const State<double>& a, const State<double>& b) {
  return so3::log(Mat3<double>(a.R.transpose() * b.R)).norm() + (a.Omega - b.Omega).norm();
}

// Least-squares slope of log(err) against log(h).
inline double fitted_order(const std::vector<double>& h, const std::vector<double>& err) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(h.size());
  for (std::size_t i = 0; i < h.size(); ++i) {
    const double x = std::log(h[i]), y = std::log(err[i]);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// ∫ f over [0, n h] from f at the n + 1 points k h (n a multiple of 8) by the composite 9-point closed Newton–Cotes
// rule: weights 4h/14175 · (989, 5888, −928, 10496, −4540, …), exact for polynomials of degree ≤ 9, error O(h¹⁰) on
// smooth data (the energy-balance tests integrate a method's power with it).
template <class S>
S newton_cotes9(const std::vector<S>& f, const S& h) {
  static constexpr double w[9] = {989, 5888, -928, 10496, -4540, 10496, -928, 5888, 989};
  const std::size_t n = f.size() - 1;
  if (f.empty() || n % 8 != 0) throw std::invalid_argument("newton_cotes9: the number of intervals must be a multiple of 8");
  S sum = S(0);
  for (std::size_t panel = 0; panel + 8 <= n; panel += 8)
    for (std::size_t k = 0; k <= 8; ++k) sum += S(w[k]) * f[panel + k];
  return sum * S(4) * h / S(14175);
}

}  // namespace lgi::test
