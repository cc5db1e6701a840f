/// \file
/// lgi/core/inertia.hpp — the inertia tensor: J, its inverse, and the checks a physical one passes.
///
/// J is symmetric positive definite, in the body frame, about the fixed point (heavy tops) or the centre
/// of mass (free bodies); it need not be diagonal (seed paper, eqs. (s2), (s0.02)). Its principal moments
/// obey the triangle inequalities I_i ≤ I_j + I_k (equality: a plane lamina). `Inertia` precomputes J⁻¹
/// once and notes whether J is diagonal, so that the step loop multiplies by 3 numbers instead of 9 where
/// it can.
#pragma once

#include "scalar.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <type_traits>

namespace lgi {

/// J with its inverse, computed once, and whether it is diagonal (the step loops' multiplications by J and J⁻¹).
template <class T>
struct Inertia {
  Mat3<T> J;      ///< the inertia tensor, body frame
  Mat3<T> J_inv;  ///< J⁻¹
  bool diagonal;  ///< J is structurally diagonal (is_diagonal): apply and solve multiply by 3 numbers

  /// J_ symmetric positive definite (inertia_defect checks a double one); a singular J_ gives a non-finite J_inv,
  /// which is not detected here.
  explicit Inertia(const Mat3<T>& J_) : J(J_), J_inv(J_.inverse()), diagonal(is_diagonal(J_)) {}

  /// J v
  Vec3<T> apply(const Vec3<T>& v) const {
    if (diagonal) return J.diagonal().cwiseProduct(v);
    return J * v;
  }
  /// J⁻¹ v
  Vec3<T> solve(const Vec3<T>& v) const {
    if (diagonal) return J_inv.diagonal().cwiseProduct(v);
    return J_inv * v;
  }

  /// Off-diagonal entries exactly zero — derivative parts too: a Jet that carries ∂/∂J01 must take the
  /// full-matrix path even when J01's value is 0, or that derivative would be dropped.
  static bool is_diagonal(const Mat3<T>& M) {
    return is_exact_zero(M(0, 1)) && is_exact_zero(M(0, 2)) && is_exact_zero(M(1, 2)) && is_exact_zero(M(1, 0)) &&
           is_exact_zero(M(2, 0)) && is_exact_zero(M(2, 1));
  }
};

namespace detail {
inline std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", x);
  return buf;
}
}  // namespace detail

/// Why M is not a physical inertia tensor, or nothing when it is. Checks, in this order: finite entries,
/// symmetry (|M_ij − M_ji| ≤ 1e-12 max|M|), positive definiteness (smallest eigenvalue > 1e-14 max|M|),
/// the triangle inequalities of the principal moments (to a relative 1e-12), and a scale whose inverse
/// is representable (principal moments in [1e-150, 1e150]). `where` receives the
/// (row, column) of the offending entry for the first two checks, (−1, −1) otherwise.
inline std::optional<std::string> inertia_defect(const Mat3<double>& M, int* row = nullptr, int* col = nullptr) {
  auto at = [&](int r, int c) {
    if (row) *row = r;
    if (col) *col = c;
  };
  at(-1, -1);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(M(r, c))) {
        at(r, c);
        return "entry is not a finite number";
      }
  const double scale = M.cwiseAbs().maxCoeff();
  if (scale == 0) return "inertia tensor is zero";
  for (int r = 0; r < 3; ++r)
    for (int c = r + 1; c < 3; ++c)
      if (std::abs(M(r, c) - M(c, r)) > 1e-12 * scale) {
        at(r, c);
        return "inertia tensor is not symmetric: I" + std::to_string(r + 1) + std::to_string(c + 1) + " = " +
               detail::number(M(r, c)) + " but I" + std::to_string(c + 1) + std::to_string(r + 1) + " = " +
               detail::number(M(c, r));
      }
  if (!(scale < 1e150))  // the eigenvalues (or the inverse) of such a tensor are not representable
    return "inertia tensor's scale (largest entry " + detail::number(scale) +
           ") is outside [1e-150, 1e150]: its inverse is not representable; change the units";
  // The eigenvalues of M/scale (entries in [-1, 1]: no overflow in the solver), scaled back.
  const Mat3<double> S = 0.5 * (M / scale + M.transpose() / scale);
  const Eigen::SelfAdjointEigenSolver<Mat3<double>> eig(S, Eigen::EigenvaluesOnly);
  const Vec3<double> l = scale * eig.eigenvalues();  // ascending
  if (!(l(0) > 1e-14 * scale) || !std::isfinite(l(0)))
    return "inertia tensor is not positive definite (principal moments " + detail::number(l(0)) + ", " +
           detail::number(l(1)) + ", " + detail::number(l(2)) + ")";
  if (l(2) > (l(0) + l(1)) * (1 + 1e-12))
    return "principal moments " + detail::number(l(0)) + ", " + detail::number(l(1)) + ", " +
           detail::number(l(2)) + " violate the triangle inequality I3 <= I1 + I2 (no rigid body has them)";
  if (!M.inverse().allFinite() || !(1e-150 < l(0) && l(2) < 1e150))
    return "inertia tensor's scale (principal moments " + detail::number(l(0)) + " .. " + detail::number(l(2)) +
           ") is outside [1e-150, 1e150]: its inverse is not representable; change the units";
  return std::nullopt;
}

/// Principal axes of a symmetric positive-definite J: J = Q diag(I) Qᵀ, det Q = +1. For a structurally
/// diagonal J (is_diagonal: zero off-diagonal entries, derivative parts included) Q = 1 and I = diag(J)
/// in the given order, so the principal axes are the body axes. Otherwise the moments are ascending.
template <class T>
struct PrincipalAxes {
  Mat3<T> Q = Mat3<T>::Identity();  ///< the principal axes as columns, in body coordinates; a rotation
  Vec3<T> I = Vec3<T>::Ones();      ///< the principal moments, in the order of Q's columns
  bool identity = true;             ///< Q = 1 exactly (J was structurally diagonal): the conversions copy

  /// Q = 1, I = (1, 1, 1).
  PrincipalAxes() = default;
  /// The principal axes of J (symmetric positive definite, not checked; J's value part is decomposed with Eigen's
  /// SelfAdjointEigenSolver). For a Jet J the derivative parts of I and Q are the first-order perturbation
  /// ∂λ_i = q_iᵀ ∂J q_i, ∂q_i = Σ_j q_j (q_jᵀ ∂J q_i)/(λ_i − λ_j), with the terms of moments closer than 1e-12
  /// relative dropped (equal moments: any axes of the plane are principal).
  explicit PrincipalAxes(const Mat3<T>& J) {
    if (Inertia<T>::is_diagonal(J)) {
      I = J.diagonal();
      return;
    }
    identity = false;
    using V = value_type_t<T>;
    Mat3<V> J0;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) J0(r, c) = static_cast<V>(value_of(J(r, c)));
    const Eigen::SelfAdjointEigenSolver<Mat3<V>> eig(J0);
    Mat3<V> Q0 = eig.eigenvectors();
    if (Q0.determinant() < 0) Q0.col(2) = -Q0.col(2);
    const Vec3<V> l0 = eig.eigenvalues();
    if constexpr (std::is_arithmetic_v<T>) {
      Q = Q0;
      I = l0;
    } else {
      // First-order perturbation: M = Q0ᵀ J Q0 has diagonal values, derivative parts anywhere.
      const Mat3<T> Q0t = Q0.template cast<T>();
      const Mat3<T> M = Q0t.transpose() * J * Q0t;
      Mat3<T> K = Mat3<T>::Zero();
      for (int i = 0; i < 3; ++i) {
        I(i) = T(l0(i)) + (M(i, i) - T(value_of(M(i, i))));
        for (int j = 0; j < 3; ++j) {
          const V gap = l0(j) - l0(i);
          if (i == j || !(std::abs(gap) > 1e-12 * std::abs(l0(2)))) continue;
          K(i, j) = (M(i, j) - T(value_of(M(i, j)))) / T(gap);
        }
      }
      Q = Q0t + Q0t * K;
    }
  }

  /// Qᵀ v: body-frame components of v in principal axes.
  Vec3<T> to_principal(const Vec3<T>& v) const { return identity ? v : Vec3<T>(Q.transpose() * v); }
  /// Q v: principal-axis components of v back in the body frame.
  Vec3<T> to_body(const Vec3<T>& v) const { return identity ? v : Vec3<T>(Q * v); }
};

}  // namespace lgi
