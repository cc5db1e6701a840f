/// \file
/// lgi/fit/manifolds.hpp — the attitude R0 ∈ SO(3) and the direction z0 ∈ S² as ceres::Manifold.
///
/// SO(3), stored as the 9 entries of R in Eigen's column-major order, tangent space R³ (the body frame),
/// right-multiplicative perturbation (the convention of core/so3.hpp: updates are R·Exp(δ)):
///
/// ~~~{.unparsed}
///   Plus(R, δ)      = R Exp(δ)                          (Solà et al., arXiv:1812.01537, the right-⊕)
///   Minus(S, R)     = Log(Rᵀ S)                         (the right-⊖; Plus(R, Minus(S, R)) = S)
///   PlusJacobian    = ∂ vec(R Exp(δ))/∂δ at δ = 0: column k is vec(R hat(e_k))              (9 × 3)
///   MinusJacobian   = ∂ Log(Rᵀ S)/∂ vec S at S = R: Log(I + E) = vee(E) + O(E²), so row k is
///                     ∂ vee(Rᵀ S)_k/∂ vec S                                                   (3 × 9)
/// ~~~
/// MinusJacobian · PlusJacobian = I (vee(hat(e_k)) = e_k), and PlusJacobianᵀ PlusJacobian = 2 I for an
/// orthogonal R (tr(hat(a)ᵀ hat(b)) = 2 a·b), the identity the fit uses to turn tangent-space derivatives into
/// ambient ones (fit/model.hpp). The ⊕/⊖ pair is that of Solà, Deray, Atchuthan, "A micro Lie theory for
/// state estimation in robotics", §II-E (the right-⊕ and right-⊖ operators; equation numbers not
/// re-confirmed here), and the Manifold contract is that of Ceres 2.1, include/ceres/manifold.h
/// (Plus, PlusJacobian, Minus, MinusJacobian; row-major Jacobians).
///
/// S², stored as a unit 3-vector z, tangent space R² in an orthonormal basis B(z) = [b1 b2] of z⊥ that is a
/// fixed function of z (b1 = normalise(e × z) with e the coordinate axis least aligned with z, b2 = z × b1):
///
/// ~~~{.unparsed}
///   Plus(z, δ)      = Exp(B δ) z = z cos θ + (n × z) sin θ,   θ = |δ|, n = Bδ/θ   (a rotation of z, so |z| = 1)
///   Minus(y, z)     = Bᵀ ω,   ω = atan2(|z × y|, z·y) (z × y)/|z × y|           (Exp(ω) z = y, ω ⊥ z)
///   PlusJacobian    = [b1 × z, b2 × z]  (orthonormal columns)                                 (3 × 2)
///   MinusJacobian   = Bᵀ hat(z)         (MinusJacobian · PlusJacobian = −Bᵀ hat(z)² B = Bᵀ(I − zzᵀ)B = I)
/// ~~~
#pragma once

#include <lgi/core/so3.hpp>

#include <ceres/manifold.h>

#include <Eigen/Core>

#include <cmath>

namespace lgi::fit {

///@{
/// The row-major Jacobian shapes of the Manifold interface (ambient × tangent and back).
using RowMajor93 = Eigen::Matrix<double, 9, 3, Eigen::RowMajor>;
using RowMajor39 = Eigen::Matrix<double, 3, 9, Eigen::RowMajor>;
using RowMajor32 = Eigen::Matrix<double, 3, 2, Eigen::RowMajor>;
using RowMajor23 = Eigen::Matrix<double, 2, 3, Eigen::RowMajor>;
///@}

/// R Exp(δ), written as R + R (Exp(δ) − I) so that δ = 0 returns R exactly (values and derivatives).
template <class T>
Mat3<T> so3_plus(const Mat3<T>& R, const Vec3<T>& delta) {
  return R + R * so3::exp_increment(delta);
}

/// ∂ vec(R Exp(δ))/∂δ at δ = 0 (vec: Eigen's column-major order).
inline RowMajor93 so3_plus_jacobian(const Mat3<double>& R) {
  RowMajor93 P;
  for (int k = 0; k < 3; ++k) {
    const Mat3<double> D = R * so3::hat(Vec3<double>(Vec3<double>::Unit(k)));
    for (int a = 0; a < 9; ++a) P(a, k) = D.data()[a];
  }
  return P;
}

/// SO(3) as a ceres::Manifold (the header's first table). Stateless: one object may serve every parameter block.
/// x must be a rotation (9 entries, column-major); every operation returns true.
class SO3Manifold final : public ceres::Manifold {
 public:
  ///@{
  /// ceres::Manifold's interface (Ceres 2.1), as the header's table defines it: ambient size 9, tangent size 3.
  int AmbientSize() const override { return 9; }
  int TangentSize() const override { return 3; }

  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    const Eigen::Map<const Mat3<double>> R(x);
    Eigen::Map<Mat3<double>>{x_plus_delta} = so3_plus(Mat3<double>(R), Vec3<double>(delta[0], delta[1], delta[2]));
    return true;
  }
  bool PlusJacobian(const double* x, double* jacobian) const override {
    Eigen::Map<RowMajor93>{jacobian} = so3_plus_jacobian(Mat3<double>(Eigen::Map<const Mat3<double>>(x)));
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    const Eigen::Map<const Mat3<double>> S(y), R(x);
    Eigen::Map<Vec3<double>>{y_minus_x} = so3::log(Mat3<double>(R.transpose() * S));
    return true;
  }
  bool MinusJacobian(const double* x, double* jacobian) const override {
    const Eigen::Map<const Mat3<double>> R(x);
    Eigen::Map<RowMajor39> M(jacobian);
    for (int a = 0; a < 9; ++a) {  // S = R + ε E_a, E_a the unit matrix of vec index a
      Mat3<double> E = Mat3<double>::Zero();
      E.data()[a] = 1;
      M.col(a) = so3::vee(Mat3<double>(R.transpose() * E));
    }
    return true;
  }
  ///@}
};

/// The orthonormal basis [b1 b2] of z⊥ (a fixed function of z; see the header).
template <class T>
Eigen::Matrix<T, 3, 2> s2_basis(const Vec3<T>& z) {
  using std::sqrt;
  int i = 0;
  for (int j = 1; j < 3; ++j)
    if (std::abs(static_cast<double>(value_of(z(j)))) < std::abs(static_cast<double>(value_of(z(i))))) i = j;
  Vec3<T> b1 = Vec3<T>(Vec3<T>::Unit(i)).cross(z);
  b1 /= sqrt(b1.squaredNorm());
  Eigen::Matrix<T, 3, 2> B;
  B.col(0) = b1;
  B.col(1) = z.cross(b1);
  return B;
}

/// Exp(B(z) δ) z, written as z + (Exp(Bδ) − I) z so that δ = 0 returns z exactly.
template <class T>
Vec3<T> s2_plus(const Vec3<T>& z, const Eigen::Matrix<T, 3, 2>& B, const Eigen::Matrix<T, 2, 1>& delta) {
  return z + so3::exp_increment(Vec3<T>(B * delta)) * z;
}

/// ∂ Exp(B(z) δ) z/∂δ at δ = 0: [b1 × z, b2 × z].
inline RowMajor32 s2_plus_jacobian(const Vec3<double>& z) {
  const Eigen::Matrix<double, 3, 2> B = s2_basis(z);
  RowMajor32 P;
  P.col(0) = B.col(0).cross(z);
  P.col(1) = B.col(1).cross(z);
  return P;
}

/// S² as a ceres::Manifold (the header's second table). Stateless; x must be a unit vector; every operation returns
/// true (Minus(y, z) is 0 where z × y = 0, antipodal points included).
class S2Manifold final : public ceres::Manifold {
 public:
  ///@{
  /// ceres::Manifold's interface (Ceres 2.1), as the header's table defines it: ambient size 3, tangent size 2.
  int AmbientSize() const override { return 3; }
  int TangentSize() const override { return 2; }

  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    const Vec3<double> z(x[0], x[1], x[2]);
    const Vec3<double> y = s2_plus(z, s2_basis(z), Eigen::Vector2d(delta[0], delta[1]));
    Eigen::Map<Vec3<double>>{x_plus_delta} = y / y.norm();  // |y| = 1 to round-off; keep it from drifting
    return true;
  }
  bool PlusJacobian(const double* x, double* jacobian) const override {
    Eigen::Map<RowMajor32>{jacobian} = s2_plus_jacobian(Vec3<double>(x[0], x[1], x[2]));
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    const Vec3<double> z(x[0], x[1], x[2]), w(y[0], y[1], y[2]);
    const Vec3<double> c = z.cross(w);
    const double s = c.norm();
    const Vec3<double> omega = s > 0 ? Vec3<double>(std::atan2(s, z.dot(w)) / s * c) : Vec3<double>::Zero();
    Eigen::Map<Eigen::Vector2d>{y_minus_x} = s2_basis(z).transpose() * omega;
    return true;
  }
  bool MinusJacobian(const double* x, double* jacobian) const override {
    const Vec3<double> z(x[0], x[1], x[2]);
    Eigen::Map<RowMajor23>{jacobian} = s2_basis(z).transpose() * so3::hat(z);
    return true;
  }
  ///@}
};

}  // namespace lgi::fit
