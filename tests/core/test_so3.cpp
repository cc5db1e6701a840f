// core/so3.hpp, measured: hat/vee, exp and log round trips, orthogonality, the Jacobians against
// finite differences, the truncated dexp⁻¹ series, the Cayley map, and the scalar helpers; typed over
// double and ceres::Jet, with the Jet's derivative parts checked against finite differences.
//
// Inputs sit on every branch point of so3.hpp: θ = 0, 1e-8, the Taylor threshold θ² = 1e-2 (below, at,
// above), log's switch at π/2 and its own threshold sin²θ = 1e-2, and π; along axis-aligned and oblique
// axes. Tolerances are in units of ε = 2.2e-16 unless the quantity is ill-conditioned (stated where so).
#include "fp_traps.hpp"

#include <lgi/core/so3.hpp>

#include <Eigen/Geometry>
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace lgi {
namespace {

using Jet3 = ceres::Jet<double, 3>;
using Vec3d = Vec3<double>;
using Mat3d = Mat3<double>;

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kPi = std::numbers::pi;

const std::vector<Vec3d>& axes() {
  static const std::vector<Vec3d> a = {Vec3d::UnitX(),         Vec3d::UnitY(),
                                       Vec3d::UnitZ(),         Vec3d(1, 1, 1).normalized(),
                                       Vec3d(0.36, -0.48, 0.8), Vec3d(-2, 3, 6) / 7};
  return a;
}

const std::vector<double>& angles() {
  static const std::vector<double> t = {0,   1e-8, 1e-4, std::sqrt(0.99e-2), 0.1, std::sqrt(1.01e-2),
                                        1,   2,    kPi / 2 - 1e-7,          kPi / 2, kPi / 2 + 1e-7,
                                        3,   kPi - 1e-6};
  return t;
}

// Calls f(θ, ω = θ n) for every angle and axis, with the sample named in any failure.
template <class F>
void for_each_sample(const F& f) {
  for (double theta : angles())
    for (const Vec3d& n : axes()) {
      SCOPED_TRACE(::testing::Message() << "theta = " << theta << ", axis = " << n.transpose());
      f(theta, Vec3d(theta * n));
    }
}

// ω as a T. A Jet's derivative parts are seeded with the identity: every result carries d/dω.
template <class T>
Vec3<T> lift(const Vec3d& w) {
  if constexpr (is_dual_v<T>) {
    return Vec3<T>(T(w.x(), 0), T(w.y(), 1), T(w.z(), 2));
  } else {
    return w;
  }
}

template <class Derived>
Eigen::Matrix<double, Derived::RowsAtCompileTime, Derived::ColsAtCompileTime> values(
    const Eigen::MatrixBase<Derived>& m) {
  return m.unaryExpr([](const typename Derived::Scalar& x) { return static_cast<double>(value_of(x)); });
}

// The k-th derivative part of a Jet matrix.
template <class Derived>
Eigen::Matrix<double, Derived::RowsAtCompileTime, Derived::ColsAtCompileTime> derivative(
    const Eigen::MatrixBase<Derived>& m, int k) {
  return m.unaryExpr([k](const Jet3& x) { return x.v[k]; });
}

template <class Derived>
double max_abs(const Eigen::MatrixBase<Derived>& m) {
  return m.cwiseAbs().maxCoeff();
}

// df/ds at s = 0, Richardson-extrapolated central differences (4 D(h/2) − D(h))/3 with
// D(h) = (f(h) − f(−h))/2h: truncation O(h⁴) ≲ 1e-13 for the O(1) derivatives here at h = 1e-3,
// round-off ≈ 3ε|f|/h ≈ 1e-12. Hence 1e-11 for derivative checks (measured ≤ 1.3e-12).
constexpr double kFdTolerance = 1e-11;
template <class F>
auto central_difference(const F& f, double h = 1e-3) {
  using M = decltype(f(0.0));
  const auto d = [&](double s) -> M { return (f(s) - f(-s)) / (2 * s); };
  return M((4 * d(h / 2) - d(h)) / 3);
}

template <class T>
class So3Test : public ::testing::Test {};
using Scalars = ::testing::Types<double, Jet3>;
TYPED_TEST_SUITE(So3Test, Scalars);

// vee∘hat is exact (vee halves w − (−w)); hat(a)b = a × b up to the summation order (≤ 2 ulps).
TYPED_TEST(So3Test, HatVeeAreInverseAndHatIsTheCrossProduct) {
  using T = TypeParam;
  const Vec3d b(0.3, -1.7, 2.9);
  for_each_sample([&](double, const Vec3d& w) {
    const Mat3<T> W = so3::hat(lift<T>(w));
    EXPECT_EQ(values(Mat3<T>(W + W.transpose())), Mat3d::Zero());
    EXPECT_EQ(values(so3::vee(W)), w);
    const Vec3d Wb = values(Vec3<T>(W * b.cast<T>()));
    EXPECT_LE((Wb - w.cross(b)).norm(), 2 * kEps * w.norm() * b.norm());
  });
  Mat3d M;  // vee reads the antisymmetric part only
  M << 1, 2, 3, 4, 5, 6, 7, 8, 10;
  EXPECT_EQ(so3::vee(M), so3::vee(Mat3d((M - M.transpose()) / 2)));
}

// exp is a rotation to round-off: ≲ 2 ulps in each of 9 entries gives ‖RᵀR − I‖_F, |det R − 1| < 16ε
// (measured ≤ 10ε, near θ = 3). It agrees with Eigen's AngleAxis to the same accuracy, and a Jet's
// derivative parts are finite everywhere, θ = 0 included.
TYPED_TEST(So3Test, ExpIsARotationAndMatchesAngleAxis) {
  using T = TypeParam;
  for_each_sample([&](double theta, const Vec3d& w) {
    const Mat3<T> R = so3::exp(lift<T>(w));
    EXPECT_TRUE(all_finite(R));
    const Mat3d Rd = values(R);
    EXPECT_LE(so3::orthogonality_error(Rd), 16 * kEps);
    EXPECT_LE(std::abs(Rd.determinant() - 1), 16 * kEps);
    const Vec3d n = theta > 0 ? Vec3d(w / theta) : Vec3d::UnitX();
    EXPECT_LE(max_abs(Rd - Eigen::AngleAxisd(theta, n).toRotationMatrix()), 8 * kEps);
  });
}

// log∘exp = id for θ < π. The angle is atan2 of (sin θ, cos θ), both carried by R to ~ε, the axis comes
// from the antisymmetric (θ ≤ π/2) or symmetric (θ > π/2) part: well conditioned up to π, so the error
// is a few ulps of θ (measured ≤ 1.7εθ). log of Eigen's AngleAxis matrix gives θn just as well.
TYPED_TEST(So3Test, LogInvertsExp) {
  using T = TypeParam;
  for_each_sample([&](double theta, const Vec3d& w) {
    const Vec3<T> l = so3::log(so3::exp(lift<T>(w)));
    EXPECT_TRUE(all_finite(l));
    EXPECT_LE((values(l) - w).norm(), 4 * kEps * theta);
    if (theta > 0) {
      const Mat3d R = Eigen::AngleAxisd(theta, w / theta).toRotationMatrix();
      EXPECT_LE((values(so3::log(R.cast<T>().eval())) - w).norm(), 8 * kEps * theta);
    }
  });
}

// exp∘log = id on rotations built from quaternions (θ from 0 to π, generic axes), and log(R) is the
// quaternion's angle-axis 2 atan2(|q_v|, q_w) q_v/|q_v|. Errors are a few ulps (measured ≤ 2ε).
TYPED_TEST(So3Test, ExpInvertsLogOnQuaternionRotations) {
  using T = TypeParam;
  const std::vector<Eigen::Quaterniond> qs = {
      {1, 0, 0, 0},        {1, 1e-9, -2e-9, 3e-9}, {1, 0.05, 0.02, -0.01}, {0.9, 0.3, -0.2, 0.1},
      {0.5, 0.5, 0.5, 0.5}, {0.1, -0.7, 0.6, 0.2},  {1e-7, 0.6, 0.0, -0.8},  {0, 0.36, -0.48, 0.8}};
  for (const Eigen::Quaterniond& q0 : qs) {
    const Eigen::Quaterniond q = q0.normalized();
    SCOPED_TRACE(::testing::Message() << "q = " << q.coeffs().transpose());
    const Mat3d R = q.toRotationMatrix();
    const Vec3d l = values(so3::log(R.cast<T>().eval()));
    EXPECT_LE(max_abs(so3::exp(l) - R), 16 * kEps);
    const double s = q.vec().norm();
    const Vec3d expected = s > 0 ? Vec3d(2 * std::atan2(s, q.w()) / s * q.vec()) : Vec3d::Zero();
    if (q.w() == 0) {  // θ = π exactly: ±π n are both correct
      EXPECT_LE(std::min((l - expected).norm(), (l + expected).norm()), 8 * kEps * kPi);
    } else {
      EXPECT_LE((l - expected).norm(), 8 * kEps * std::max(expected.norm(), kEps));
    }
  }
}

// log near π: for π − θ ≥ 1e-14 the sign of sin θ (≥ 1e-14 ≫ its ~ε round-off) fixes ω; at π in
// double (sin θ = 1.2e-16, below round-off) either of ±ω is correct. Exact half-turns 2nnᵀ − I too.
TYPED_TEST(So3Test, LogIsRobustNearPi) {
  using T = TypeParam;
  for (double gap : {1e-6, 1e-8, 1e-10, 1e-14, 0.0}) {
    for (const Vec3d& n : axes()) {
      SCOPED_TRACE(::testing::Message() << "pi - theta = " << gap << ", axis = " << n.transpose());
      const Vec3d w = (kPi - gap) * n;
      const Vec3<T> l = so3::log(so3::exp(lift<T>(w)));
      EXPECT_TRUE(all_finite(l));  // Jet derivatives too, even at θ = π
      const Vec3d ld = values(l);
      const double err = gap >= 1e-14 ? (ld - w).norm() : std::min((ld - w).norm(), (ld + w).norm());
      EXPECT_LE(err, 4 * kEps * kPi);
      const Mat3d half_turn = 2 * n * n.transpose() - Mat3d::Identity();
      const Vec3d lh = values(so3::log(half_turn.cast<T>().eval()));
      EXPECT_LE(std::min((lh - kPi * n).norm(), (lh + kPi * n).norm()), 4 * kEps * kPi);
    }
  }
}

// J_r, J_l, J_r⁻¹ against central differences of their definitions:
//   exp(ω + s e_i) = exp(ω) exp(s J_r e_i) = exp(s J_l e_i) exp(ω),  log(exp(ω) exp(s e_i)) = ω + s J_r⁻¹ e_i.
// The J_r⁻¹ stencil must not carry log across θ = π, so it stops at θ = 3.
TYPED_TEST(So3Test, JacobiansMatchFiniteDifferences) {
  using T = TypeParam;
  for_each_sample([&](double theta, const Vec3d& w) {
    const Mat3d R = so3::exp(w);
    const Mat3d Jr = values(so3::right_jacobian(lift<T>(w)));
    const Mat3d Jl = values(so3::left_jacobian(lift<T>(w)));
    const Mat3d Jri = values(so3::right_jacobian_inverse(lift<T>(w)));
    for (int i = 0; i < 3; ++i) {
      const Vec3d e = Vec3d::Unit(i);
      const Mat3d Rt = R.transpose();
      const auto exp_at = [&](double s) -> Mat3d { return so3::exp(Vec3d(w + s * e)); };
      const Vec3d jr = central_difference([&](double s) -> Vec3d { return so3::log(Mat3d(Rt * exp_at(s))); });
      const Vec3d jl = central_difference([&](double s) -> Vec3d { return so3::log(Mat3d(exp_at(s) * Rt)); });
      EXPECT_LE((Jr.col(i) - jr).norm(), kFdTolerance);
      EXPECT_LE((Jl.col(i) - jl).norm(), kFdTolerance);
      if (theta > 3) continue;
      const Vec3d jri =
          central_difference([&](double s) -> Vec3d { return so3::log(Mat3d(R * so3::exp(Vec3d(s * e)))); });
      EXPECT_LE((Jri.col(i) - jri).norm(), kFdTolerance);
    }
  });
}

// What is true of J_l (both are polynomials in hat(ω), which commutes with exp(ω)):
// J_l(ω) = J_r(ω)ᵀ = exp(ω) J_r(ω) = J_r(ω) exp(ω). Products of O(1) matrices: ≤ 8ε (measured ≤ 2.3ε); the transpose
// is exact up to one rounding of the shared W² term. (so3.hpp computes J_l as J_r(−ω); what checks it independently
// is JacobiansMatchFiniteDifferences, against central differences of exp from the left.)
TYPED_TEST(So3Test, LeftJacobianIdentities) {
  using T = TypeParam;
  for_each_sample([&](double, const Vec3d& w) {
    const Mat3d Jl = values(so3::left_jacobian(lift<T>(w)));
    const Mat3d Jr = values(so3::right_jacobian(lift<T>(w)));
    const Mat3d R = so3::exp(w);
    EXPECT_LE(max_abs(Jl - Jr.transpose()), 2 * kEps);
    EXPECT_LE(max_abs(Jl - R * Jr), 8 * kEps);
    EXPECT_LE(max_abs(Jl - Jr * R), 8 * kEps);
  });
}

// J_r J_r⁻¹ = J_r⁻¹ J_r = I for θ < 2π. Both factors are O(ε)-accurate, so the product error is a few
// ε × ‖J_r‖ ‖J_r⁻¹‖, which grows like 1/(2π − θ) (θ = 4, 5, 6 added beyond π; measured ≤ 3ε up to π).
TYPED_TEST(So3Test, RightJacobianTimesItsInverseIsIdentity) {
  using T = TypeParam;
  const auto check = [](const Vec3d& w) {
    const Mat3d Jr = values(so3::right_jacobian(lift<T>(w)));
    const Mat3d Jri = values(so3::right_jacobian_inverse(lift<T>(w)));
    const double tol = 4 * kEps * Jr.norm() * Jri.norm();
    EXPECT_LE(max_abs(Jr * Jri - Mat3d::Identity()), tol);
    EXPECT_LE(max_abs(Jri * Jr - Mat3d::Identity()), tol);
  };
  for_each_sample([&](double, const Vec3d& w) { check(w); });
  for (double theta : {4.0, 5.0, 6.0}) {
    SCOPED_TRACE(::testing::Message() << "theta = " << theta);
    check(theta * Vec3d(0.36, -0.48, 0.8));
  }
}

// The dexp⁻¹ series truncated after ad_u^K differs from J_r⁻¹(u) v by its first omitted term,
// |B_m/m!| |u|^m |v| (m the next even index): for K ≥ 1 the tail is along u×(u×v), its terms of one
// sign and ratio ≤ θ²/(2π)², so within a factor 1 + θ²/39 of the first one. At K = 8, |u| = 0.1
// that is 2e-18: what is left is the closed form's round-off, ≤ 4ε|v|.
TYPED_TEST(So3Test, InverseJacobianSeriesConverges) {
  using T = TypeParam;
  const Vec3d v(0.7, -0.2, 1.1);
  for (double r : {0.4, 0.2, 0.1, 0.05}) {
    const Vec3d u = r * Vec3d(-2, 3, 6) / 7;
    SCOPED_TRACE(::testing::Message() << "|u| = " << r);
    const Vec3d exact = so3::right_jacobian_inverse(u) * v;
    const auto error = [&](auto series) { return (values(series) - exact).norm(); };
    const Vec3<T> uT = lift<T>(u), vT = v.cast<T>();
    const double bound = (1 + r * r / 39) * v.norm();
    const double roundoff = 4 * kEps * v.norm();
    // K = 0 leaves ½ u×v and the orthogonal u×(u×v) terms: |·| ≤ (r/2 + D(r²) r²)|v|, D < 1/11.
    EXPECT_LE(error(so3::right_jacobian_inverse_series<0>(uT, vT)), (r / 2 + r * r / 11) * v.norm() + roundoff);
    EXPECT_LE(error(so3::right_jacobian_inverse_series<1>(uT, vT)), bound * std::pow(r, 2) / 12 + roundoff);
    EXPECT_LE(error(so3::right_jacobian_inverse_series<2>(uT, vT)), bound * std::pow(r, 4) / 720 + roundoff);
    EXPECT_EQ(values(so3::right_jacobian_inverse_series<3>(uT, vT)),
              values(so3::right_jacobian_inverse_series<2>(uT, vT)));  // B_3 = 0
    EXPECT_LE(error(so3::right_jacobian_inverse_series<4>(uT, vT)), bound * std::pow(r, 6) / 30240 + roundoff);
    EXPECT_LE(error(so3::right_jacobian_inverse_series<6>(uT, vT)), bound * std::pow(r, 8) / 1209600 + roundoff);
    EXPECT_LE(error(so3::right_jacobian_inverse_series<8>(uT, vT)), bound * std::pow(r, 10) / 47900160 + roundoff);
  }
}

// Cayley: a rotation to round-off, inverted by cayley_inverse (1 + tr R = 16/(4 + θ²) ≥ 1.1 here, so a
// few ulps of θ), and cay(ω) − exp(ω) = −(θ²/12) hat(ω) + O(θ⁴): ‖·‖_F = √2 θ³/12 (1 + O(θ²)), the O(θ²)
// measured as −0.15 θ².
TYPED_TEST(So3Test, CayleyIsARotationInvertedByCayleyInverse) {
  using T = TypeParam;
  for_each_sample([&](double theta, const Vec3d& w) {
    const Mat3<T> C = so3::cayley(lift<T>(w));
    EXPECT_TRUE(all_finite(C));
    const Mat3d Cd = values(C);
    EXPECT_LE(so3::orthogonality_error(Cd), 16 * kEps);
    EXPECT_LE(std::abs(Cd.determinant() - 1), 16 * kEps);
    EXPECT_LE((values(so3::cayley_inverse(C)) - w).norm(), 8 * kEps * theta);
  });
  for (double theta : {1e-2, 0.1, 0.3}) {
    const Vec3d w = theta * Vec3d(0.36, -0.48, 0.8);
    const double gap = (values(so3::cayley(lift<T>(w))) - so3::exp(w)).norm();
    EXPECT_NEAR(gap / (std::sqrt(2.0) * std::pow(theta, 3) / 12), 1.0, theta * theta / 5);
  }
}

// ‖RᵀR − I‖_F of known perturbations of a rotation Q: a scaling sQ gives √3|s² − 1|; Q·diag(1 + d)
// gives ‖(1 + d)² − 1‖; a shear Q(I + δ e1e2ᵀ) gives δ√(2 + δ²). Round-off ~ε against values ≥ 1e-8.
TYPED_TEST(So3Test, OrthogonalityErrorOfPerturbedRotations) {
  using T = TypeParam;
  const Mat3d Q = so3::exp(Vec3d(0.3, -1.2, 0.8));
  const auto err = [](const Mat3d& M) { return value_of(so3::orthogonality_error(M.cast<T>().eval())); };
  EXPECT_LE(err(Q), 16 * kEps);
  for (double s : {1 + 1e-6, 1 - 1e-8, 1.5}) {
    EXPECT_NEAR(err(s * Q), std::sqrt(3.0) * std::abs(s * s - 1), 1e-8 * std::abs(s * s - 1));
  }
  const Vec3d d(1e-6, -2e-7, 3e-8);
  const Vec3d dd = ((Vec3d::Ones() + d).array().square() - 1).matrix();
  EXPECT_NEAR(err(Q * (Vec3d::Ones() + d).asDiagonal()), dd.norm(), 1e-8 * dd.norm());
  for (double delta : {1e-7, 1e-3}) {
    Mat3d S = Mat3d::Identity();
    S(0, 1) = delta;
    EXPECT_NEAR(err(Q * S), delta * std::sqrt(2 + delta * delta), 1e-8 * delta);
  }
}

// A Jet's value part follows the same operations as the double computation except that Ceres divides
// as a·(1/b), two roundings: a few ulps apart at most (measured ≤ 4ε on O(1) entries).
TYPED_TEST(So3Test, JetValuesMatchDoubleValues) {
  using T = TypeParam;
  for_each_sample([&](double theta, const Vec3d& w) {
    const Vec3<T> wT = lift<T>(w);
    EXPECT_LE(max_abs(values(so3::exp(wT)) - so3::exp(w)), 8 * kEps);
    EXPECT_LE(max_abs(values(so3::log(so3::exp(wT))) - so3::log(so3::exp(w))), 8 * kEps * theta);
    EXPECT_LE(max_abs(values(so3::right_jacobian(wT)) - so3::right_jacobian(w)), 8 * kEps);
    EXPECT_LE(max_abs(values(so3::right_jacobian_inverse(wT)) - so3::right_jacobian_inverse(w)), 8 * kEps);
    EXPECT_LE(max_abs(values(so3::cayley(wT)) - so3::cayley(w)), 8 * kEps);
  });
}

// Across each switch to a Taylor polynomial the two formulas agree: ω just below and just above
// θ² = 1e-2 (a few ulps apart), and R just either side of log's switch sin²θ = 1e-2. The inputs move
// by ~ε, so values agree to 4ε (measured ≤ 2ε) and Jet derivatives to 1e-14 (measured 1e-15; the
// closed forms' cancellation in 1 − (θ/2)cot(θ/2) and θ − sin θ is amplified in d/dθ², ×θ³ after).
TYPED_TEST(So3Test, TaylorBranchesAreContinuous) {
  using T = TypeParam;
  const auto compare = [](const auto& below, const auto& above, double scale) {
    EXPECT_LE(max_abs(values(below) - values(above)), 4 * kEps * scale);
    if constexpr (is_dual_v<T>) {
      for (int k = 0; k < 3; ++k) EXPECT_LE(max_abs(derivative(below, k) - derivative(above, k)), 1e-14);
    }
  };
  for (const Vec3d& n : axes()) {
    SCOPED_TRACE(::testing::Message() << "axis = " << n.transpose());
    Vec3d lo = 0.1 * n, hi = 0.1 * n;
    while (lo.squaredNorm() >= so3::small_angle_theta2) lo *= 1 - kEps;
    while (hi.squaredNorm() < so3::small_angle_theta2) hi *= 1 + kEps;
    const Vec3<T> a = lift<T>(lo), b = lift<T>(hi);
    compare(so3::exp(a), so3::exp(b), 1);
    compare(so3::right_jacobian(a), so3::right_jacobian(b), 1);
    compare(so3::right_jacobian_inverse(a), so3::right_jacobian_inverse(b), 1);
    compare(so3::log(so3::exp(a)), so3::log(so3::exp(b)), 0.1);
    // log's own switch, sin²θ = |vee(R)|² = 1e-2 (θ ≈ 0.1002), straddled the same way.
    Vec3d llo = std::asin(0.1) * n, lhi = llo;
    while (so3::vee(so3::exp(llo)).squaredNorm() >= so3::small_angle_theta2) llo *= 1 - kEps;
    while (so3::vee(so3::exp(lhi)).squaredNorm() < so3::small_angle_theta2) lhi *= 1 + kEps;
    compare(so3::log(so3::exp(lift<T>(llo))), so3::log(so3::exp(lift<T>(lhi))), 0.1);
  }
  // The coefficient D itself: just above the threshold, 1 − (θ/2)cot(θ/2) ≈ θ²/12 cancels about
  // 12/θ² ≈ 1200 × ε relative (measured 1e-14 here, ≤ 6e-14 up to θ² = 2e-2); below it the polynomial
  // is exact to round-off. (In J_r⁻¹ the error is multiplied by θ² and invisible.)
  const double below = so3::jacobian_inverse_coefficient(std::nextafter(so3::small_angle_theta2, 0.0));
  const double above = so3::jacobian_inverse_coefficient(std::nextafter(so3::small_angle_theta2, 1.0));
  EXPECT_NEAR(above / below, 1.0, 12 / so3::small_angle_theta2 * kEps);
}

// core/trig.hpp's polynomial sin/cos and exp's coefficients from them, against long double over dense samples of
// their whole ranges: the error in units of the last place of the correctly rounded value. libm's formulas for
// the same coefficients (the branch exp_coefficients used before) are measured alongside for comparison.
// The bounds are the measured maxima (g++ 12, x86-64, glibc's long double sin and cos as the truth) rounded up to
// the next 0.1 ulp.
double ulp_error(double approx, long double truth) {
  const double t = static_cast<double>(truth);
  const double ulp = std::nextafter(std::abs(t), std::numeric_limits<double>::infinity()) - std::abs(t);
  return static_cast<double>(std::fabs(static_cast<long double>(approx) - truth) / ulp);
}

TEST(TrigPolynomial, SinAndCosWithinAnUlpOnZeroToPi) {
  const int n = 1000000;
  double sin_max = 0, cos_max = 0, sin_at = 0, cos_at = 0, sin_libm = 0, cos_libm = 0;
  for (int i = 0; i <= n; ++i) {
    const double x = trig::max_argument * i / n;
    const double s = trig::sin_0_pi(x), c = trig::cos_0_pi(x);
    const long double xl = x, S = std::sin(xl), C = std::cos(xl);
    if (i > 0 && ulp_error(s, S) > sin_max) sin_max = ulp_error(s, S), sin_at = x;
    if (ulp_error(c, C) > cos_max) cos_max = ulp_error(c, C), cos_at = x;
    if (i > 0) sin_libm = std::max(sin_libm, ulp_error(std::sin(x), S));
    cos_libm = std::max(cos_libm, ulp_error(std::cos(x), C));
  }
  std::printf("polynomial sin on [0, pi]: max %.3f ulp (at %.6f); cos: max %.3f ulp (at %.6f); libm: sin %.3f ulp, "
              "cos %.3f ulp\n",
              sin_max, sin_at, cos_max, cos_at, sin_libm, cos_libm);
  EXPECT_LE(sin_max, 0.8);  // measured 0.775 (libm 0.515)
  EXPECT_LE(cos_max, 0.9);  // measured 0.815 (libm 0.515)
}

TEST(TrigPolynomial, ExpCoefficientsWithinUlpsOnTenthToPi) {
  const int n = 1000000;
  double a_max = 0, b_max = 0, a_libm = 0, b_libm = 0, a_at = 0, b_at = 0;
  const double lo = 0.1, hi = trig::max_argument;
  for (int i = 0; i <= n; ++i) {
    const double theta = i == n ? hi : lo + (hi - lo) * i / n;
    const long double tl = theta;
    const long double A = std::sin(tl) / tl, s2 = std::sin(tl / 2) / tl, B = 2 * s2 * s2;
    const so3::Coefficients<double> k = so3::exp_coefficients(Vec3d(theta, 0, 0));
    if (ulp_error(k.A, A) > a_max) a_max = ulp_error(k.A, A), a_at = theta;
    if (ulp_error(k.B, B) > b_max) b_max = ulp_error(k.B, B), b_at = theta;
    const double s = std::sin(theta / 2) / theta;  // the libm formulas
    a_libm = std::max(a_libm, ulp_error(std::sin(theta) / theta, A));
    b_libm = std::max(b_libm, ulp_error(2 * s * s, B));
  }
  std::printf("exp coefficients on [0.1, pi], polynomial: A = sin(t)/t max %.3f ulp (at %.6f), B = (1 - cos t)/t^2 "
              "max %.3f ulp (at %.6f); libm formulas: A %.3f ulp, B %.3f ulp\n",
              a_max, a_at, b_max, b_at, a_libm, b_libm);
  EXPECT_LE(a_max, 1.5);  // measured 1.485 (libm's sin: 1.467)
  EXPECT_LE(b_max, 3.4);  // measured 3.366 (libm's sin: 3.366): the formula squares, and so doubles, s's error
}

// exp of Jets at angles below and above a switch of exp_coefficients' branches, along every test axis: equal values
// to 8ε and derivatives to 1e-13.
void expect_exp_continuous_across(double below, double above) {
  for (const Vec3d& n : axes()) {
    const Vec3<Jet3> wb = lift<Jet3>(Vec3d(below * n)), wa = lift<Jet3>(Vec3d(above * n));
    const Mat3<Jet3> Rb = so3::exp(wb), Ra = so3::exp(wa);
    EXPECT_LE(max_abs(values(Rb) - values(Ra)), 8 * kEps);
    for (int k = 0; k < 3; ++k) EXPECT_LE(max_abs(derivative(Rb, k) - derivative(Ra, k)), 1e-13);
  }
}

// Below θ² = 2 the coefficients come from B's series, with A = √(B (2 − θ² B)): each within about an ulp and a half,
// and Rodrigues' orthogonality factor 2B − A² − θ²B² (evaluated in long double from the rounded A and B, to ≈ 1e-19) is
// the rounding of A alone, unbiased: its mean over the samples is far below its spread (≈ 1e-16) — a biased A (its
// own series: ≈ −1e-17 θ² a call) would drift an attitude away from SO(3) linearly in the number of steps.
TEST(TrigPolynomial, ExpCoefficientsBelowSqrtTwoWithinAnUlpAndAHalf) {
  const int n = 1000000;
  double a_max = 0, b_max = 0, a_at = 0, b_at = 0;
  long double defect_sum = 0, defect_abs = 0;
  const double lo = 0.1, hi = std::sqrt(trig::exp_series_theta2);
  for (int i = 0; i < n; ++i) {
    const double theta = lo + (hi - lo) * i / n;
    if (theta * theta >= trig::exp_series_theta2) break;
    const long double tl = theta;
    const long double A = std::sin(tl) / tl, s2 = std::sin(tl / 2) / tl, B = 2 * s2 * s2;
    const so3::Coefficients<double> k = so3::exp_coefficients(Vec3d(theta, 0, 0));
    if (ulp_error(k.A, A) > a_max) a_max = ulp_error(k.A, A), a_at = theta;
    if (ulp_error(k.B, B) > b_max) b_max = ulp_error(k.B, B), b_at = theta;
    const long double a = k.A, b = k.B, t2 = k.theta2;
    const long double defect = 2 * b - a * a - t2 * b * b;
    defect_sum += defect;
    defect_abs += std::fabs(defect);
  }
  const double mean = static_cast<double>(defect_sum / n), mean_abs = static_cast<double>(defect_abs / n);
  std::printf("exp coefficients on [0.1, sqrt 2), series: A max %.3f ulp (at %.6f), B max %.3f ulp (at %.6f); "
              "orthogonality factor 2B - A^2 - t^2 B^2: mean %.2e, mean |.| %.2e\n",
              a_max, a_at, b_max, b_at, mean, mean_abs);
  EXPECT_LE(a_max, 1.5);  // B's error (< 0.9 ulp) halved by the square root, plus its own rounding
  EXPECT_LE(b_max, 0.9);
  EXPECT_LE(std::fabs(mean), 0.01 * mean_abs);
}

// At θ² = 2 the coefficients switch from B's series to the polynomial sin: the two agree to round-off there, in value
// and (Jets) in derivative, and exp stays continuous.
TEST(TrigPolynomial, SwitchFromTheSeriesAtSqrtTwoIsContinuous) {
  const double above = std::sqrt(trig::exp_series_theta2);  // θ² rounds to ≥ 2: the sine's side
  double below = above;
  while (below * below >= trig::exp_series_theta2) below = std::nextafter(below, 0.0);
  const so3::Coefficients<double> kb = so3::exp_coefficients(Vec3d(below, 0, 0));
  const so3::Coefficients<double> ka = so3::exp_coefficients(Vec3d(above, 0, 0));
  ASSERT_LT(kb.theta2, trig::exp_series_theta2);
  ASSERT_GE(ka.theta2, trig::exp_series_theta2);
  EXPECT_NEAR(kb.A, ka.A, 4 * kEps * kb.A);
  EXPECT_NEAR(kb.B, ka.B, 6 * kEps * kb.B);
  expect_exp_continuous_across(below, above);
}

// The polynomial's coefficients are doubles: long double (the tests' references) keeps libm's sinl, to its own
// precision (the polynomial would be off by ~1e-16 here).
TEST(TrigPolynomial, LongDoubleKeepsItsOwnPrecision) {
  using L = long double;
  L worst = 0;
  for (int i = 0; i <= 1000; ++i) {
    const L theta = 0.1L + (3.1L - 0.1L) * i / 1000;
    const so3::Coefficients<L> k = so3::exp_coefficients(Vec3<L>(theta, 0, 0));
    const L s = std::sin(theta / 2) / theta;
    worst = std::max({worst, std::fabs(k.A / (std::sin(theta) / theta) - 1), std::fabs(k.B / (2 * s * s) - 1)});
  }
  EXPECT_LE(worst, 8 * std::numeric_limits<L>::epsilon());
}

// At θ = π the coefficients switch from the polynomials to libm: the two agree to round-off there, in value and
// (Jets) in derivative, and exp stays continuous.
TEST(TrigPolynomial, SwitchToLibmAtPiIsContinuous) {
  const double below = trig::max_argument, above = std::nextafter(below, 4.0);
  const so3::Coefficients<double> kb = so3::exp_coefficients(Vec3d(below, 0, 0));
  const so3::Coefficients<double> ka = so3::exp_coefficients(Vec3d(above, 0, 0));
  EXPECT_NEAR(kb.A, ka.A, 4 * kEps * kb.B);  // A ≈ 4e-17 there: compare on the scale of B ≈ 0.2
  EXPECT_NEAR(kb.B, ka.B, 4 * kEps * kb.B);
  expect_exp_continuous_across(below, above);
}

// Jet derivative parts against finite differences in double, and exactly right at θ = 0.
// d exp(ω)/dω_k, d J_r/dω_k, d J_r⁻¹/dω_k, d cay/dω_k.
TEST(So3JetTest, MapDerivativesMatchFiniteDifferences) {
  for_each_sample([&](double, const Vec3d& w) {
    const Vec3<Jet3> wj = lift<Jet3>(w);
    const Mat3<Jet3> R = so3::exp(wj), Jr = so3::right_jacobian(wj), Jri = so3::right_jacobian_inverse(wj),
                     C = so3::cayley(wj);
    ASSERT_TRUE(all_finite(R) && all_finite(Jr) && all_finite(Jri) && all_finite(C));
    for (int k = 0; k < 3; ++k) {
      const auto at = [&](double s) { return Vec3d(w + s * Vec3d::Unit(k)); };
      const auto fd = [&](auto map) { return central_difference([&](double s) -> Mat3d { return map(at(s)); }); };
      EXPECT_LE(max_abs(derivative(R, k) - fd([](const Vec3d& x) { return so3::exp(x); })), kFdTolerance);
      EXPECT_LE(max_abs(derivative(Jr, k) - fd([](const Vec3d& x) { return so3::right_jacobian(x); })), kFdTolerance);
      EXPECT_LE(max_abs(derivative(Jri, k) - fd([](const Vec3d& x) { return so3::right_jacobian_inverse(x); })),
                kFdTolerance);
      EXPECT_LE(max_abs(derivative(C, k) - fd([](const Vec3d& x) { return so3::cayley(x); })), kFdTolerance);
    }
  });
}

// d log(exp(ω))/dω = I through the chain rule, up to π − 1e-6 (the symmetric-part branch is
// differentiable there; measured ≤ 5ε). d/dδ log(exp(ω) exp(δ)) at δ = 0 is J_r⁻¹(ω) by the closed
// form, and by finite differences for θ ≤ 3 (the stencil must stay below π).
TEST(So3JetTest, LogDerivatives) {
  for_each_sample([&](double theta, const Vec3d& w) {
    const Mat3d R = so3::exp(w);
    const Vec3<Jet3> l = so3::log(so3::exp(lift<Jet3>(w)));
    const Vec3<Jet3> l_delta = so3::log(Mat3<Jet3>(R.cast<Jet3>() * so3::exp(lift<Jet3>(Vec3d::Zero()))));
    ASSERT_TRUE(all_finite(l) && all_finite(l_delta));
    const Mat3d Jri = so3::right_jacobian_inverse(w);
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE((derivative(l, k) - Vec3d::Unit(k)).norm(), 16 * kEps);
      EXPECT_LE((derivative(l_delta, k) - Jri.col(k)).norm(), 16 * kEps);
      if (theta > 3) continue;
      const Vec3d fd = central_difference(
          [&](double s) -> Vec3d { return so3::log(Mat3d(R * so3::exp(Vec3d(s * Vec3d::Unit(k))))); });
      EXPECT_LE((derivative(l_delta, k) - fd).norm(), kFdTolerance);
    }
  });
}

// With R = cay(c), d/dδ cayley_inverse(R exp(δ)) at δ = 0 is I + ½hat(c) + ¼ccᵀ (the right-trivialised
// dcay⁻¹, from dcay⁻¹_C(H) = (I − C/2) H (I + C/2), Hairer–Lubich–Wanner §IV.8.3). cayley_inverse
// divides by 1 + tr R, which vanishes at θ = π: relative accuracy ~ε·4/(1 + tr R) (≈ 200ε at θ = 3, the
// last angle checked). Finite differences too where that factor is ≤ 4 (θ ≤ 2).
TEST(So3JetTest, CayleyInverseDerivative) {
  for_each_sample([&](double theta, const Vec3d& w) {
    if (theta > 3) return;
    const Mat3d R = so3::exp(w);
    const Vec3<Jet3> c = so3::cayley_inverse(Mat3<Jet3>(R.cast<Jet3>() * so3::exp(lift<Jet3>(Vec3d::Zero()))));
    ASSERT_TRUE(all_finite(c));
    const Vec3d cd = values(c);
    const Mat3d expected = Mat3d::Identity() + 0.5 * so3::hat(cd) + 0.25 * cd * cd.transpose();
    const double condition = 4 / (1 + R.trace());
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE((derivative(c, k) - expected.col(k)).norm(), 16 * kEps * condition * expected.norm());
      if (theta > 2) continue;
      const Vec3d fd = central_difference(
          [&](double s) -> Vec3d { return so3::cayley_inverse(Mat3d(R * so3::exp(Vec3d(s * Vec3d::Unit(k))))); });
      EXPECT_LE((derivative(c, k) - fd).norm(), kFdTolerance);
    }
  });
}

// At θ = 0 every derivative is finite and exact: d exp = d cay = hat(e_k), d J_r = −½hat(e_k),
// d J_r⁻¹ = d J_l = ½hat(e_k); through log and cayley_inverse at I, any perturbation M (not even
// antisymmetric) gives vee(M).
TEST(So3JetTest, DerivativesAtZeroAreExact) {
  const Vec3<Jet3> zero = lift<Jet3>(Vec3d::Zero());
  Mat3<Jet3> R = Mat3d::Identity().cast<Jet3>();
  Mat3d M[3];
  M[0] << 0.3, -1.0, 2.0, 0.5, 0.1, -0.7, 1.5, 0.9, -0.2;
  M[1] = so3::hat(Vec3d(0.2, -0.4, 0.6));
  M[2] << 1, 0, 0, 0, 1, 0, 0, 0, 1;  // pure scaling: no rotation, zero derivative
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 9; ++i) R(i).v[k] = M[k](i);
  const Vec3<Jet3> l = so3::log(R), c = so3::cayley_inverse(R);
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE(::testing::Message() << "k = " << k);
    const Mat3d E = so3::hat(Vec3d(Vec3d::Unit(k)));
    EXPECT_EQ(derivative(so3::exp(zero), k), E);
    EXPECT_EQ(derivative(so3::cayley(zero), k), E);
    EXPECT_EQ(derivative(so3::right_jacobian(zero), k), -0.5 * E);
    EXPECT_EQ(derivative(so3::right_jacobian_inverse(zero), k), 0.5 * E);
    EXPECT_EQ(derivative(so3::left_jacobian(zero), k), 0.5 * E);
    EXPECT_LE((derivative(l, k) - so3::vee(M[k])).norm(), kEps);
    EXPECT_LE((derivative(c, k) - so3::vee(M[k])).norm(), kEps);
  }
  EXPECT_EQ(values(l), Vec3d::Zero());
}

// value_of reads the value part, through nested Jets too; all_finite, unlike ceres::isfinite, also
// looks at the derivative parts, alone and inside matrices.
TEST(ScalarHelpers, ValueOfAndAllFinite) {
  const test::FpTrapsOff traps_off;  // NaN and ∞ made on purpose: all_finite must see them
  using Nested = ceres::Jet<ceres::Jet<double, 2>, 1>;
  EXPECT_EQ(value_of(2.5), 2.5);
  EXPECT_EQ(value_of(Jet3(1.5, 2)), 1.5);
  EXPECT_EQ(value_of(Nested(ceres::Jet<double, 2>(-3.0, 1))), -3.0);
  Jet3 bad(1.0);
  bad.v[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(ceres::isfinite(bad));
  EXPECT_FALSE(all_finite(bad));
  EXPECT_TRUE(all_finite(Jet3(1.0, 0)));
  Mat3<Jet3> m = Mat3d::Identity().cast<Jet3>();
  EXPECT_TRUE(all_finite(m));
  m(2, 1) = bad;
  EXPECT_FALSE(all_finite(m));
  EXPECT_FALSE(all_finite(Vec3d(0, std::numeric_limits<double>::infinity(), 0)));
  EXPECT_TRUE(all_finite(Vec3d(0, 1, 2)));
}

}  // namespace
}  // namespace lgi
