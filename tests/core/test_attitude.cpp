// core/attitude.hpp against independent constructions: the Euler-angle matrices against products of axis
// rotations exp(a ê_i), their body rates against Rᵀ R' by central differences, quaternions against exp of the
// same axis and angle, the sign of q, and Jets through every map against central differences.
#include "figures.hpp"
#include "jet_check.hpp"

#include <lgi/core/attitude.hpp>
#include <lgi/core/so3.hpp>

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

namespace lgi {
namespace {

Mat3<double> about(int axis, double angle) { return so3::exp(Vec3<double>(angle * Vec3<double>::Unit(axis))); }

// The rotation of Euler angles `a` built as the product of three axis rotations (the convention's definition).
Mat3<double> by_products(EulerConvention c, const Vec3<double>& a) {
  return c == EulerConvention::zxz ? Mat3<double>(about(2, a(0)) * about(0, a(1)) * about(2, a(2)))
                                   : Mat3<double>(about(2, a(0)) * about(1, a(1)) * about(0, a(2)));
}

std::vector<Vec3<double>> random_angles(int n) {
  std::mt19937_64 gen(20261126);
  std::uniform_real_distribution<double> u(-3.1, 3.1);
  std::vector<Vec3<double>> out;
  for (int i = 0; i < n; ++i) out.emplace_back(u(gen), u(gen), u(gen));
  return out;
}

TEST(Attitude, EulerAnglesAreTheProductsOfTheirAxisRotations) {
  double worst = 0;
  for (const EulerConvention c : {EulerConvention::zxz, EulerConvention::zyx})
    for (const Vec3<double>& a : random_angles(200)) {
      const Mat3<double> R = rotation_from_euler(c, a);
      worst = std::max(worst, (R - by_products(c, a)).cwiseAbs().maxCoeff());
      EXPECT_LT(so3::orthogonality_error(R), 1e-15);
    }
  test::expect_figure("Euler angles vs products of axis rotations, 400 random angle triples", worst, 1.5e-15);
  // The aerospace reading of z-y-x: yaw turns the body's x axis (the nose) from the laboratory's x towards y, pitch
  // raises it out of the x-y plane towards −z, roll turns the body's y axis (the wing) towards its z.
  const double d = 0.3;
  EXPECT_NEAR((rotation_from_euler(EulerConvention::zyx, Vec3<double>(d, 0, 0)) * Vec3<double>::UnitX())(1),
              std::sin(d), 1e-16);
  EXPECT_NEAR((rotation_from_euler(EulerConvention::zyx, Vec3<double>(0, d, 0)) * Vec3<double>::UnitX())(2),
              -std::sin(d), 1e-16);
  EXPECT_NEAR((rotation_from_euler(EulerConvention::zyx, Vec3<double>(0, 0, d)) * Vec3<double>::UnitY())(2),
              std::sin(d), 1e-16);
}

// Ω = vee(Rᵀ R') along a(t) = a0 + t da, R' by central differences of order 4 (h = 1e-3, |da| up to 5: their
// truncation, ≈ h⁴|da|⁵/30, is the 1e-10 measured).
TEST(Attitude, BodyRatesAreRTransposeRDot) {
  const auto angles = random_angles(100);
  const auto rates = random_angles(101);
  double worst = 0;
  for (const EulerConvention c : {EulerConvention::zxz, EulerConvention::zyx})
    for (std::size_t i = 0; i < angles.size(); ++i) {
      const Vec3<double>& a = angles[i];
      const Vec3<double>& da = rates[i + 1];
      const double h = 1e-3;
      const auto R = [&](double t) { return by_products(c, Vec3<double>(a + t * da)); };
      const Mat3<double> dR = (R(-2 * h) - 8 * R(-h) + 8 * R(h) - R(2 * h)) / (12 * h);
      const Vec3<double> expected = so3::vee(Mat3<double>(R(0).transpose() * dR));
      worst = std::max(worst, (body_rate_from_euler(c, a, da) - expected).norm() / da.norm());
    }
  test::expect_figure("Euler-angle body rates vs R^T R' (finite differences)", worst, 4e-10);
}

// Angles from a rotation give it back, also at and near the conventions' singularities (where only a sum or
// difference of the outer angles is defined: each carries an error ≈ ε/sin θ there, R a few ulps more than elsewhere,
// 5.3e-15 measured).
TEST(Attitude, EulerAnglesOfARotationGiveItBack) {
  double worst = 0;
  std::vector<Mat3<double>> rotations;
  for (const Vec3<double>& a : random_angles(200)) rotations.push_back(so3::exp(a));
  for (const double d : {0.0, 1e-12, 1e-6})
    for (const double phi : {0.3, -2.9}) {
      rotations.push_back(rotation_from_euler(EulerConvention::zxz, Vec3<double>(phi, d, 1.1)));
      rotations.push_back(rotation_from_euler(EulerConvention::zxz, Vec3<double>(phi, 3.14159265358979323846 - d, 1.1)));
      rotations.push_back(rotation_from_euler(EulerConvention::zyx, Vec3<double>(phi, 1.5707963267948966 - d, 1.1)));
      rotations.push_back(rotation_from_euler(EulerConvention::zyx, Vec3<double>(phi, -1.5707963267948966 + d, 1.1)));
    }
  rotations.push_back(Mat3<double>::Identity());
  for (const EulerConvention c : {EulerConvention::zxz, EulerConvention::zyx})
    for (const Mat3<double>& R : rotations)
      worst = std::max(worst, (rotation_from_euler(c, euler_from_rotation(c, R)) - R).cwiseAbs().maxCoeff());
  test::expect_figure("rotation -> Euler angles -> rotation, random and (near-)singular", worst, 2e-14);
}

TEST(Attitude, QuaternionsAreRotationsAboutTheirAxis) {
  const auto axes = random_angles(200);
  double worst = 0, sign = 0;
  for (const Vec3<double>& v : axes) {
    const Vec3<double> axis = v.normalized();
    const double angle = v(0) + v(1);  // in (−6.2, 6.2)
    const double w = std::cos(angle / 2), s = std::sin(angle / 2);
    const Mat3<double> R = rotation_from_quaternion(w, s * axis(0), s * axis(1), s * axis(2));
    worst = std::max(worst, (R - so3::exp(Vec3<double>(angle * axis))).cwiseAbs().maxCoeff());
    worst = std::max(worst, (rotation_from_axis_angle(Vec3<double>(3 * axis), angle) -
                             so3::exp(Vec3<double>(angle * axis))).cwiseAbs().maxCoeff());
    sign = std::max(sign, (rotation_from_quaternion(-w, -s * axis(0), -s * axis(1), -s * axis(2)) - R)
                              .cwiseAbs()
                              .maxCoeff());
    // Not normalised: the same rotation.
    const Mat3<double> scaled = rotation_from_quaternion(1.01 * w, 1.01 * s * axis(0), 1.01 * s * axis(1),
                                                         1.01 * s * axis(2));
    worst = std::max(worst, (scaled - R).cwiseAbs().maxCoeff());
  }
  test::expect_figure("quaternion and axis-angle rotations vs exp, 200 random axes and angles", worst, 2e-15);
  EXPECT_EQ(sign, 0.0);  // −q: the same products with both signs flipped
}

// Jets through every map: derivatives with respect to the three angles (rates, quaternion components) against
// central differences.
TEST(Attitude, JetsThroughEveryMap) {
  using J = ceres::Jet<double, 3>;
  const Vec3<double> a0(0.4, -1.1, 2.3), r0(0.7, -0.2, 1.5);
  const auto seeded = [](const Vec3<double>& v) {
    Vec3<J> out;
    for (int i = 0; i < 3; ++i) out(i) = J(v(i), i);
    return out;
  };
  double worst = 0;
  const double eps = 1e-6;
  for (const EulerConvention c : {EulerConvention::zxz, EulerConvention::zyx}) {
    const Mat3<J> R = rotation_from_euler(c, seeded(a0));
    const Vec3<J> W = body_rate_from_euler(c, a0.cast<J>().eval(), seeded(r0));
    for (int k = 0; k < 3; ++k) {
      const Vec3<double> e = eps * Vec3<double>::Unit(k);
      const Mat3<double> dR = (rotation_from_euler(c, Vec3<double>(a0 + e)) - rotation_from_euler(c, Vec3<double>(a0 - e))) / (2 * eps);
      const Vec3<double> dW = (body_rate_from_euler(c, a0, Vec3<double>(r0 + e)) - body_rate_from_euler(c, a0, Vec3<double>(r0 - e))) / (2 * eps);
      for (int i = 0; i < 3; ++i) {
        worst = std::max(worst, std::abs(W(i).v[k] - dW(i)));
        for (int j = 0; j < 3; ++j) worst = std::max(worst, std::abs(R(i, j).v[k] - dR(i, j)));
      }
    }
  }
  const Mat3<J> Rq = rotation_from_quaternion(J(0.8), J(0.1, 0), J(-0.5, 1), J(0.3, 2));
  for (int k = 0; k < 3; ++k) {
    double q[4] = {0.8, 0.1, -0.5, 0.3}, p[4] = {0.8, 0.1, -0.5, 0.3};
    q[k + 1] += eps;
    p[k + 1] -= eps;
    const Mat3<double> dR = (rotation_from_quaternion(q[0], q[1], q[2], q[3]) -
                             rotation_from_quaternion(p[0], p[1], p[2], p[3])) / (2 * eps);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) worst = std::max(worst, std::abs(Rq(i, j).v[k] - dR(i, j)));
  }
  test::expect_figure("Jets through the attitude maps vs central differences", worst, 5e-10);
}

}  // namespace
}  // namespace lgi
