// benchmarks/wp_reference.cpp — references for the work-precision benchmark (see Reference in wp_common.hpp).
//
// The integration is independent of every method under test: another state space (the 12 entries of R and
// Ω, no quaternion, no group), another precision (long double, ε = 1.1e-19), another algorithm (Fehlberg's
// 7(8) pair used as a fixed-step order-8 method, Boost.Odeint's coefficients as exact rationals in long
// double). Its error bar is the distance between the N- and 2N-step results (an over-estimate of the 2N
// result's truncation error by about 2⁸, which also contains the difference of two roundings). The exact
// free-body solution is lgi's own (problems/free_body_exact.hpp, tested against a 113-bit integration to
// ≤ 2.6e-16 over t ≤ 100): on free bodies it is the reference and the integration its cross-check.
#include "wp_common.hpp"

#include <lgi/problems/free_body_exact.hpp>

#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>

#include <Eigen/SVD>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

namespace wp {
namespace {

using L = long double;
using Y12 = std::array<L, 12>;  // R row-major, then Ω
using Mat3L = Eigen::Matrix<L, 3, 3>;
using Vec3L = Eigen::Matrix<L, 3, 1>;

struct Rhs12 {
  Mat3L J, Ji;
  L b;
  Vec3L k, z0;
  explicit Rhs12(const Body& body)
      : J(body.J.cast<L>()), Ji(body.J.cast<L>().inverse()), b(body.b), k(body.k.cast<L>()), z0(body.z0.cast<L>()) {}
  void operator()(const Y12& y, Y12& d, L /*t*/) const {
    const Eigen::Map<const Eigen::Matrix<L, 3, 3, Eigen::RowMajor>> R(y.data());
    const Vec3L W(y[9], y[10], y[11]);
    Mat3L What;
    What << 0, -W.z(), W.y(), W.z(), 0, -W.x(), -W.y(), W.x(), 0;
    Eigen::Map<Eigen::Matrix<L, 3, 3, Eigen::RowMajor>> dR(d.data());
    dR = R * What;
    Vec3L rhs = (J * W).cross(W);
    if (b != 0) rhs += b * Vec3L(R.transpose() * k).cross(z0);
    const Vec3L dW = Ji * rhs;
    d[9] = dW.x(), d[10] = dW.y(), d[11] = dW.z();
  }
};

Y12 to_y(const State& x) {
  Y12 y{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) y[static_cast<std::size_t>(3 * i + j)] = x.R(i, j);
  for (int i = 0; i < 3; ++i) y[static_cast<std::size_t>(9 + i)] = x.Omega(i);
  return y;
}

// Rounded to double; R replaced by its polar factor (the nearest rotation: the 12-entry integration leaves
// SO(3) by its own truncation and rounding, ~1e-17 here).
State to_state(const Y12& y) {
  Mat3 R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = static_cast<double>(y[static_cast<std::size_t>(3 * i + j)]);
  const Eigen::JacobiSVD<Mat3> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
  State x;
  x.R = svd.matrixU() * svd.matrixV().transpose();
  x.Omega = Vec3(static_cast<double>(y[9]), static_cast<double>(y[10]), static_cast<double>(y[11]));
  return x;
}

// n fixed steps over [0, t_end] (n a multiple of `marks`), the state at each of the `marks` equally spaced
// times j·t_end/marks, j = 1 … marks.
std::vector<State> integrate12(const Body& body, const State& x0, double t_end, std::int64_t n, int marks) {
  const Rhs12 f(body);
  boost::numeric::odeint::runge_kutta_fehlberg78<Y12, L> stepper;
  Y12 y = to_y(x0);
  const L h = L(t_end) / L(n);
  const std::int64_t per_mark = n / marks;
  std::vector<State> out;
  for (std::int64_t i = 0; i < n; ++i) {
    stepper.do_step(f, y, h * L(i), h);
    if ((i + 1) % per_mark == 0) out.push_back(to_state(y));
  }
  return out;
}

}  // namespace

Reference compute_reference(const Case& c, bool reduced) {
  constexpr int marks = 20;
  Reference ref;
  // ω: a bound on |Ω| over the run (|Ω0| plus what the potential, of range 2b, can add to the kinetic energy).
  const double I_min = Eigen::SelfAdjointEigenSolver<Mat3>(c.body.J).eigenvalues().minCoeff();
  const double omega = c.x0.Omega.norm() + std::sqrt(4 * c.body.b / I_min);
  std::int64_t n = marks * static_cast<std::int64_t>(std::ceil(c.t_end * omega / (marks * 0.005)));
  if (reduced) n = std::max<std::int64_t>(marks, marks * (n / (8 * marks)));
  ref.steps_coarse = n;
  ref.steps_fine = 2 * n;
  ref.method = "Boost.Odeint runge_kutta_fehlberg78 (order 8, fixed steps) in long double on the 12 entries of (R, Omega); " +
               std::to_string(n) + " and " + std::to_string(2 * n) + " steps";
  const std::vector<State> coarse = integrate12(c.body, c.x0, c.t_end, n, marks);
  const std::vector<State> fine = integrate12(c.body, c.x0, c.t_end, 2 * n, marks);
  State x1 = c.x0;
  x1.Omega *= 1 + ref.perturbation;
  const std::vector<State> perturbed = integrate12(c.body, x1, c.t_end, 2 * n, marks);
  const double delta = ref.perturbation * c.x0.Omega.norm();

  int last = marks - 1;  // the last mark up to which the amplification stays below max_amplification
  for (int j = 0; j < marks; ++j) {
    ref.guard_times.push_back(c.t_end * (j + 1) / marks);
    ref.divergence.push_back(state_error(fine[static_cast<std::size_t>(j)], perturbed[static_cast<std::size_t>(j)]));
  }
  for (int j = 0; j < marks; ++j)
    if (!(ref.divergence[static_cast<std::size_t>(j)] <= ref.max_amplification * delta)) {
      last = j - 1;
      break;
    }
  ref.amplification = ref.divergence.back() / delta;
  if (last < 0) last = 0;  // not even the first mark: evaluate there anyway (the JSON says so)
  ref.t_eval = ref.guard_times[static_cast<std::size_t>(last)];
  const State& x_int = fine[static_cast<std::size_t>(last)];
  const double bar_int = state_error(coarse[static_cast<std::size_t>(last)], x_int);

  if (c.kind == Kind::free_body) {
    const lgi::FreeBodyExact<double, long double> exact(c.body.J);
    ref.kind = "exact";
    ref.x = exact.solve(c.x0).state(ref.t_eval);
    ref.error_bar = 1e-15;  // tests/problems/test_free_body_exact.cpp: ≤ 2.6e-16 for t ≤ 100; stated as 1e-15
    ref.cross_check = state_error(ref.x, x_int);
    char bar[32];
    std::snprintf(bar, sizeof bar, "%.1e", bar_int);
    ref.method = "exact solution (problems/free_body_exact.hpp, long double); cross-checked against " + ref.method +
                 " (its own step-halving bar " + bar + ")";
  } else {
    ref.kind = "integration";
    ref.x = x_int;
    // At least the rounding of the result to double (the two integrations may round to the same doubles).
    ref.error_bar = std::max(bar_int, std::numeric_limits<double>::epsilon() * (3.2 + x_int.Omega.norm()));
  }
  return ref;
}

}  // namespace wp
