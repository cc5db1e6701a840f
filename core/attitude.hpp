/// \file
/// lgi/core/attitude.hpp — attitudes in the forms people have them: unit quaternions, axis and angle, Euler angles
/// in the z-x-z and z-y-x conventions, and the body angular velocity of Euler-angle rates.
///
/// Every rotation R here maps body coordinates to laboratory coordinates (x_lab = R x_body), as the state's R
/// (core/state.hpp). Rotations about the coordinate axes: Rx(a) = exp(a ê1), Ry(a) = exp(a ê2), Rz(a) = exp(a ê3).
/// ~~~{.unparsed}
///   quaternion q = (w, x, y, z), scalar first (Hamilton's convention):
///       R(q) = I + 2w hat(v) + 2 hat(v)²  for |q| = 1, v = (x, y, z); q and −q give the same R.
///   axis and angle (â, θ):  R = exp(θ hat(â))  (right-handed: positive θ turns counter-clockwise about â).
///   z-x-z Euler angles (φ, θ, ψ), the seed paper's eq. (6.3):  R = Rz(φ) Rx(θ) Rz(ψ)
///       (intrinsic: about z, then the new x, then the new z; equivalently extrinsic z, x, z by ψ, θ, φ);
///       Ω = φ'(sinθ sinψ, sinθ cosψ, cosθ) + θ'(cosψ, −sinψ, 0) + ψ'(0, 0, 1).
///   z-y-x Euler angles (ψ, θ, φ) = (yaw, pitch, roll), the aerospace convention:  R = Rz(ψ) Ry(θ) Rx(φ)
///       (intrinsic: yaw about z, pitch about the new y, roll about the newest x);
///       Ω = (φ' − ψ' sinθ, θ' cosφ + ψ' sinφ cosθ, −θ' sinφ + ψ' cosφ cosθ).
/// ~~~
/// The body rates follow from Ω = Rᵀ R' (for R = A(α) B(β) C(γ): Ω = γ' c + β' Cᵀ b + α' Cᵀ Bᵀ a, with a, b, c
/// the three rotation axes). Reference: M. D. Shuster, "A survey of attitude representations", J. Astronaut.
/// Sci. 41 (1993) 439, §§4–5 (his matrices are the transposes, laboratory → body).
///
/// Every function takes any scalar of core/scalar.hpp (double, long double, ceres::Jet).
#pragma once

#include "scalar.hpp"
#include "so3.hpp"

#include <cmath>
#include <cstdint>
#include <string_view>

namespace lgi {

/// R = Rz(φ) Rx(θ) Rz(ψ), the seed paper's eq. (6.3) (this header).
template <class T>
Mat3<T> rotation_from_euler_angles(const T& phi, const T& theta, const T& psi) {
  using std::cos;
  using std::sin;
  const T cf = cos(phi), sf = sin(phi), ct = cos(theta), st = sin(theta), cp = cos(psi), sp = sin(psi);
  Mat3<T> R;
  R << cp * cf - sp * ct * sf, -sp * cf - cp * ct * sf, st * sf,  //
      cp * sf + sp * ct * cf, -sp * sf + cp * ct * cf, -st * cf,   //
      sp * st, cp * st, ct;
  return R;
}

/// Ω (body frame) of (6.3) for the angle rates (φ', θ', ψ').
template <class T>
Vec3<T> body_rate_from_euler_rates(const T& theta, const T& psi, const T& dphi, const T& dtheta, const T& dpsi) {
  using std::cos;
  using std::sin;
  const T st = sin(theta), ct = cos(theta), sp = sin(psi), cp = cos(psi);
  return Vec3<T>(dphi * st * sp + dtheta * cp, dphi * st * cp - dtheta * sp, dphi * ct + dpsi);
}

/// The Euler-angle conventions of this header.
enum class EulerConvention : std::uint8_t {
  zxz,  ///< (φ, θ, ψ): R = Rz(φ) Rx(θ) Rz(ψ), the seed paper's
  zyx,  ///< (ψ, θ, φ) = (yaw, pitch, roll): R = Rz(ψ) Ry(θ) Rx(φ)
};

/// "zxz" or "zyx".
constexpr std::string_view to_string(EulerConvention c) { return c == EulerConvention::zxz ? "zxz" : "zyx"; }

/// R of the Euler angles `a` (in the convention's order, radians).
template <class T>
Mat3<T> rotation_from_euler(EulerConvention convention, const Vec3<T>& a) {
  if (convention == EulerConvention::zxz) return rotation_from_euler_angles(a(0), a(1), a(2));
  using std::cos;
  using std::sin;
  const T cy = cos(a(0)), sy = sin(a(0)), cp = cos(a(1)), sp = sin(a(1)), cr = cos(a(2)), sr = sin(a(2));
  Mat3<T> R;
  R << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr,  //
      sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,   //
      -sp, cp * sr, cp * cr;
  return R;
}

/// The body angular velocity Ω of Euler angles `a` changing at the rates `da` (the convention's order).
template <class T>
Vec3<T> body_rate_from_euler(EulerConvention convention, const Vec3<T>& a, const Vec3<T>& da) {
  if (convention == EulerConvention::zxz) return body_rate_from_euler_rates(a(1), a(2), da(0), da(1), da(2));
  using std::cos;
  using std::sin;
  const T cp = cos(a(1)), sp = sin(a(1)), cr = cos(a(2)), sr = sin(a(2));
  return Vec3<T>(da(2) - da(0) * sp, da(1) * cr + da(0) * sr * cp, -da(1) * sr + da(0) * cr * cp);
}

/// The Euler angles of a rotation R in the convention's order: z-x-z θ ∈ [0, π], φ, ψ ∈ (−π, π]; z-y-x pitch ∈
/// [−π/2, π/2], yaw, roll ∈ (−π, π]. At the convention's singularity (z-x-z sin θ = 0, z-y-x cos(pitch) = 0, exactly)
/// only a sum or difference of the outer angles is defined: the last angle is then 0, so that
/// rotation_from_euler(convention, euler_from_rotation(convention, R)) = R there too.
template <class T>
Vec3<T> euler_from_rotation(EulerConvention convention, const Mat3<T>& R) {
  using std::atan2;
  using std::sqrt;
  if (convention == EulerConvention::zxz) {  // R13 = sθ sφ, R23 = −sθ cφ, R33 = cθ, R31 = sψ sθ, R32 = cψ sθ
    const T s = sqrt(R(0, 2) * R(0, 2) + R(1, 2) * R(1, 2));
    if (s == T(0)) return Vec3<T>(atan2(R(1, 0), R(0, 0)), atan2(T(0), R(2, 2)), T(0));
    return Vec3<T>(atan2(R(0, 2), -R(1, 2)), atan2(s, R(2, 2)), atan2(R(2, 0), R(2, 1)));
  }
  // R31 = −sθ, R11 = cψ cθ, R21 = sψ cθ, R32 = cθ sφ, R33 = cθ cφ
  const T c = sqrt(R(0, 0) * R(0, 0) + R(1, 0) * R(1, 0));
  if (c == T(0)) return Vec3<T>(atan2(-R(0, 1), R(1, 1)), atan2(-R(2, 0), T(0)), T(0));
  return Vec3<T>(atan2(R(1, 0), R(0, 0)), atan2(-R(2, 0), c), atan2(R(2, 1), R(2, 2)));
}

/// R(q) of the quaternion q = (w, x, y, z) / |q| (this header's convention); q ≠ 0 (not checked).
template <class T>
Mat3<T> rotation_from_quaternion(const T& w, const T& x, const T& y, const T& z) {
  using std::sqrt;
  const T n = sqrt(w * w + x * x + y * y + z * z);
  const T qw = w / n, qx = x / n, qy = y / n, qz = z / n;
  Mat3<T> R;
  R << T(1) - T(2) * (qy * qy + qz * qz), T(2) * (qx * qy - qw * qz), T(2) * (qx * qz + qw * qy),  //
      T(2) * (qx * qy + qw * qz), T(1) - T(2) * (qx * qx + qz * qz), T(2) * (qy * qz - qw * qx),   //
      T(2) * (qx * qz - qw * qy), T(2) * (qy * qz + qw * qx), T(1) - T(2) * (qx * qx + qy * qy);
  return R;
}

/// R = exp(θ hat(axis/|axis|)); axis ≠ 0 (not checked).
template <class T>
Mat3<T> rotation_from_axis_angle(const Vec3<T>& axis, const T& angle) {
  return so3::exp(Vec3<T>(axis / axis.norm() * angle));
}

}  // namespace lgi
