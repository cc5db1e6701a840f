/// \file
/// lgi/problems/euler_angle_top.hpp — the seed paper's second formulation: the Lagrange top in Euler angles.
///
/// Source: A. A. Deriglazov, "Has the problem of the motion of a heavy symmetric top been solved in
/// quadratures?" (the seed paper, shared/seed/), Sect. II–III. Symmetric body I1 = I2, centre of mass on
/// the symmetry axis (z0 = e3), gravity k = (0, k2, k3) in the laboratory frame of the principal axes at
/// t = 0 (the paper's Fig. 1(b)). Equation numbers are the paper's LaTeX labels.
///
/// ~~~{.unparsed}
///   attitude (6.3):   R = Rz(φ) Rx(θ) Rz(ψ)   (the matrix printed as (6.3), checked entry by entry)
///   Lagrangian (s7):  L = ½ I2 (θ'² + φ'² sin²θ) + ½ I3 (ψ' + φ' cosθ)² − b U(θ, φ),
///                     U = k3 cosθ − k2 sinθ cosφ   (s10)  — U = k·(R e3): the cosine of the angle
///                     between the symmetry axis and k, the textbook's cos θ in another frame.
///   equations (s6.1)–(s6.3), solved for the accelerations (s = sinθ, c = cosθ):
///       m_ψ = I3 (ψ' + φ' c) = const                                   (s6.1)
///       φ'' = (−b k2 sinφ − 2 I2 φ' θ' c + m_ψ θ') / (I2 s)              (s6.2)
///       θ'' = φ'² s c − (m_ψ/I2) s φ' + (b/I2)(k3 s + k2 c cosφ)          (s6.3)
///   state y = (φ, θ, ψ, φ', θ', m_ψ, Φ, Ψ): ψ' = m_ψ/I3 − φ' c by (s6.1) and m_ψ' = 0, so that any
///   Runge–Kutta method keeps m_ψ exactly (it is a component with zero derivative). Φ and Ψ hold the
///   whole turns taken out of φ and ψ (multiples of 2π, zero derivative): `normalize` keeps φ, ψ in
///   [−π, π] after every step, because a growing angle rounds at its own ulp every step and raises the
///   error floor of a long run (docs/seed_paper.md, section 1); the continuous angles are φ + Φ and ψ + Ψ.
///   body angular velocity of (6.3): Ω = φ'(s sinψ, s cosψ, c) + θ'(cosψ, −sinψ, 0) + ψ'(0, 0, 1).
///
///   momenta (s8):     p_θ = I2 θ',   p_φ = I2 φ' s² + m_ψ c
///   Hamiltonian (s9): H = (p_θ² + p̃_φ²)/(2 I2) + b U,  integrals E (s12) and m_φ (s13):
///                     m_φ = k2 p_θ sinφ − U'_θ p̃_φ + m_ψ U,   U'_θ = −k3 s − k2 c cosφ.
///   (s12)'s E is the energy of the reduced theory (s7.2): the total energy is E + m_ψ²/(2 I3).
/// ~~~
///
/// Correction (measured, see docs/seed_paper.md): (s10) prints p̃_φ = (p_φ − m_ψ c)/(I2 s). With it (s9)
/// is not the Legendre transform of (s7.2), and E (s12) and m_φ (s13) are not conserved unless I2 = 1.
/// The consistent definition, the one (s15) is the solution for, is p̃_φ = (p_φ − m_ψ c)/s = I2 φ' s;
/// with it m_φ (s13) equals the footnote's (k, R I Ω) to round-off. Both are provided below.
///
/// Coordinate singularity: sin θ = 0 (symmetry axis along ±e3 of the paper's frame; R(0) = 1, the paper's
/// "universal initial condition", is on it). φ'' carries 1/sin θ, φ' grows like 1/sin²θ near it, and
/// fixed-step methods lose accuracy there. `admissible(y)` is false once sin θ < min_sin_theta; the
/// drivers of integrators/euclidean_rk.hpp then stop and report the time (docs/seed_paper.md).
#pragma once

#include "../core/attitude.hpp"
#include "../core/scalar.hpp"
#include "../core/state.hpp"
#include "heavy_top.hpp"

#include <array>
#include <cmath>
#include <string_view>

namespace lgi {

// rotation_from_euler_angles and body_rate_from_euler_rates, eq. (6.3): core/attitude.hpp.

/// (φ, θ, ψ) of a rotation, inverting (6.3): θ ∈ [0, π], φ, ψ ∈ (−π, π] (core/attitude.hpp's euler_from_rotation;
/// at sin θ = 0, where only φ ± ψ is defined, ψ = 0).
template <class T>
Vec3<T> euler_angles_from_rotation(const Mat3<T>& R) {
  return euler_from_rotation(EulerConvention::zxz, R);
}

/// Wraps x into (−π, π].
inline double wrap_angle(double x) {
  constexpr double two_pi = 6.283185307179586476925286766559;
  return x - two_pi * std::ceil((x - 3.141592653589793238462643383279) / two_pi);
}

/// The seed paper's Lagrange top in Euler angles (this header): an ODE on R⁸ for the Euclidean steppers of
/// integrators/euclidean_rk.hpp, with its conversions to SO(3) × R³ and the paper's quantities (a CoordinateProblem,
/// core/problem.hpp). Not a RigidBodyProblem. The data are not checked here (I2, I3 > 0, b ≥ 0, k2² + k3² = 1).
template <class T = double>
struct EulerAngleTop {
  using Scalar = T;                                                      ///< the scalar type
  static constexpr std::string_view name = "lagrange_top_euler_angles";  ///< the scene's problem.type
  static constexpr int dimension = 8;                                    ///< the size of the state vector
  using Vector = Eigen::Matrix<T, 8, 1>;  ///< (φ, θ, ψ, φ', θ', m_ψ, Φ, Ψ)

  T I2 = T(1);  ///< I1 = I2, about the fixed point
  T I3 = T(1);  ///< the moment about the symmetry axis
  T b = T(0);   ///< gravity × distance to the centre of mass × mass
  T k2 = T(0);  ///< k = (0, k2, k3), unit
  T k3 = T(1);  ///< see k2
  double min_sin_theta = 0.05;  ///< admissible(y): sin θ ≥ this (see the header)

  // --- the equations of motion (s6.1)–(s6.3) ---------------------------------------------------------
  /// y' of (s6.1)–(s6.3) (the header's state y; autonomous: t unused). Divides by sin θ: not finite at θ = 0, π.
  Vector derivative(const T&, const Vector& y) const {
    using std::cos;
    using std::sin;
    const T s = sin(y[1]), c = cos(y[1]), sf = sin(y[0]), cf = cos(y[0]);
    const T &dphi = y[3], &dtheta = y[4], &m_psi = y[5];
    Vector d;
    d[0] = dphi;
    d[1] = dtheta;
    d[2] = m_psi / I3 - dphi * c;
    d[3] = (-b * k2 * sf - T(2) * I2 * dphi * dtheta * c + m_psi * dtheta) / (I2 * s);
    d[4] = dphi * dphi * s * c - (m_psi / I2) * s * dphi + (b / I2) * (k3 * s + k2 * c * cf);
    d[5] = T(0);
    d[6] = T(0);
    d[7] = T(0);
    return d;
  }

  /// Moves whole turns of φ and ψ into Φ and Ψ, keeping |φ|, |ψ| ≤ π (the decision on the value part).
  void normalize(Vector& y) const {
    constexpr double two_pi = 6.283185307179586476925286766559;
    for (const int i : {0, 2}) {
      const double turns = std::round(static_cast<double>(value_of(y[i])) / two_pi);
      if (turns != 0) {
        y[i] -= T(two_pi * turns);
        y[i == 0 ? 6 : 7] += T(two_pi * turns);
      }
    }
  }

  /// False once the coordinates come too close to their singularity sin θ = 0 (or cross it).
  bool admissible(const Vector& y) const {
    using std::sin;
    return static_cast<double>(value_of(sin(y[1]))) >= min_sin_theta;
  }

  // --- conversions to and from SO(3) × R³ ------------------------------------------------------------
  /// The state on SO(3) × R³: R by (6.3), Ω from the angle rates (Ω3 = m_ψ/I3 exactly).
  State<T> to_state(const Vector& y) const {
    using std::cos;
    const T dpsi = y[5] / I3 - y[3] * cos(y[1]);
    State<T> x;
    x.R = rotation_from_euler_angles(y[0], y[1], y[2]);
    x.Omega = body_rate_from_euler_rates(y[1], y[2], y[3], y[4], dpsi);
    x.Omega.z() = y[5] / I3;
    return x;
  }
  /// The angles of x.R (φ, ψ ∈ (−π, π]) and their rates. Requires sin θ > 0.
  Vector from_state(const State<T>& x) const {
    using std::cos;
    using std::sin;
    const Vec3<T> a = euler_angles_from_rotation(x.R);
    const T sp = sin(a[2]), cp = cos(a[2]);
    Vector y;
    y << a[0], a[1], a[2], (x.Omega.x() * sp + x.Omega.y() * cp) / sin(a[1]), x.Omega.x() * cp - x.Omega.y() * sp,
        I3 * x.Omega.z(), T(0), T(0);
    return y;
  }
  /// The same top on SO(3) × R³ (problems/heavy_top.hpp): J = diag(I2, I2, I3), k = (0, k2, k3), z0 = e3.
  HeavyTop<T> heavy_top() const {
    HeavyTop<T> top;
    top.inertia = Vec3<T>(I2, I2, I3).asDiagonal();
    top.b = b;
    top.k = Vec3<T>(T(0), k2, k3);
    top.z0 = Vec3<T>::UnitZ();
    return top;
  }

  // --- the paper's quantities (s8)–(s13) --------------------------------------------------------------
  /// U(θ, φ) = k3 cos θ − k2 sin θ cos φ (s10), = k·(R e3).
  T U(const T& theta, const T& phi) const {
    using std::cos;
    using std::sin;
    return k3 * cos(theta) - k2 * sin(theta) * cos(phi);
  }
  /// ∂U/∂θ = −k3 sin θ − k2 cos θ cos φ.
  T dU_dtheta(const T& theta, const T& phi) const {
    using std::cos;
    using std::sin;
    return -k3 * sin(theta) - k2 * cos(theta) * cos(phi);
  }
  /// p_θ = I2 θ' (s8).
  T p_theta(const Vector& y) const { return I2 * y[4]; }
  /// p_φ = I2 φ' sin²θ + m_ψ cos θ (s8).
  T p_phi(const Vector& y) const {
    using std::cos;
    using std::sin;
    const T s = sin(y[1]);
    return I2 * y[3] * s * s + y[5] * cos(y[1]);
  }
  /// p̃_φ = (p_φ − m_ψ cosθ)/sinθ = I2 φ' sinθ: the definition consistent with (s9), (s13), (s15).
  T p_tilde_phi(const Vector& y) const {
    using std::cos;
    using std::sin;
    return (p_phi(y) - y[5] * cos(y[1])) / sin(y[1]);
  }
  /// p̃_φ as printed in (s10): (p_φ − m_ψ cosθ)/(I2 sinθ).
  T p_tilde_phi_as_printed(const Vector& y) const { return p_tilde_phi(y) / I2; }

  /// E of (s12) (the reduced theory's energy, without the spin term m_ψ²/(2 I3)), with p̃_φ given.
  T energy_s12(const Vector& y, const T& p_tilde) const {
    const T pt = p_theta(y);
    return (pt * pt + p_tilde * p_tilde) / (T(2) * I2) + b * U(y[1], y[0]);
  }
  /// E of (s12) with the consistent p̃_φ (p_tilde_phi): conserved.
  T energy_s12(const Vector& y) const { return energy_s12(y, p_tilde_phi(y)); }
  /// The total energy ½ Ω·IΩ + b k·(R e3) = E (s12) + m_ψ²/(2 I3).
  T energy(const Vector& y) const { return energy_s12(y) + y[5] * y[5] / (T(2) * I3); }

  /// m_φ of (s13), with p̃_φ given.
  T m_phi(const Vector& y, const T& p_tilde) const {
    using std::sin;
    return k2 * p_theta(y) * sin(y[0]) - dU_dtheta(y[1], y[0]) * p_tilde + y[5] * U(y[1], y[0]);
  }
  /// m_φ of (s13) with the consistent p̃_φ: conserved, equal to m·k = k·(R J Ω) to round-off.
  T m_phi(const Vector& y) const { return m_phi(y, p_tilde_phi(y)); }

  /// Extra CSV columns after the standard ones: the integrals m_φ (= m·k, named as the heavy top's column)
  /// and m_ψ, the distance sin θ to the singularity, and the angles themselves (φ + Φ, ψ + Ψ: continuous).
  /// The first integral_count invariants are integrals of the motion; sin_theta, phi, theta, psi are coordinates.
  static constexpr std::size_t integral_count = 2;
  /// The column names, in the order of invariants().
  static constexpr std::array<std::string_view, 6> invariant_names{"momentum_k", "momentum_psi", "sin_theta",
                                                                   "phi",        "theta",        "psi"};
  /// {m_φ, m_ψ, sin θ, φ + Φ, θ, ψ + Ψ} of y.
  std::array<T, 6> invariants(const Vector& y) const {
    using std::sin;
    return {m_phi(y), y[5], sin(y[1]), y[0] + y[6], y[1], y[2] + y[7]};
  }

  /// The same top in scalar S (e.g. double → ceres::Jet).
  template <class S>
  EulerAngleTop<S> cast() const {
    return {S(I2), S(I3), S(b), S(k2), S(k3), min_sin_theta};
  }
};

}  // namespace lgi
