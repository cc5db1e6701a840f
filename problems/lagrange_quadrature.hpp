/// \file
/// lgi/problems/lagrange_quadrature.hpp — the Lagrange top in closed form: the seed paper's quadratures
/// (s15)–(s21), evaluated with Jacobi elliptic functions and elliptic integrals (Boost.Math).
///
/// Source: A. A. Deriglazov, seed paper (shared/seed/), Sect. III; equation numbers are its LaTeX labels.
/// The top: I1 = I2, I3, z0 = e3 (centre of mass on the symmetry axis), b > 0, any unit k (the paper's
/// k = (0, k2, k3), or the textbook's k = e3). n = R e3 is the symmetry axis and U = k·n (s10).
///
/// Integrals: m_ψ = I3 Ω3 (s6.1); m_φ = k·(R I Ω) (s13, footnote); E = E_total − m_ψ²/(2 I3) (s12, with
/// the corrected p̃_φ of problems/euler_angle_top.hpp), E_total = ½ Ω·IΩ + b U.
///
/// U(t). The radicand of (s15) and (s18) is the cubic
/// ~~~{.unparsed}
///     D(U) = 2 I2 (1 − U²)(E − b U) − (m_φ − m_ψ U)² = 2 I2 b (U − u1)(U − u2)(U − u3),
/// ~~~
/// with −1 ≤ u1 ≤ U ≤ u2 ≤ 1 ≤ u3 (D(±1) = −(m_φ ∓ m_ψ)² ≤ 0). (s18) with c1 = −t + ∂Φ/∂E (s17) is
/// t − t0 = I2 ∫ dU/(ε √D), ε = sign(U') (so I2² U'² = D(U)). Inverting it:
/// ~~~{.unparsed}
///     U(t) = u1 + (u2 − u1) sn²(τ, k),  τ = τ0 + λ t,  λ = √(b (u3 − u1)/(2 I2)),  k² = (u2 − u1)/(u3 − u1),
/// ~~~
/// and the time between consecutive turning points u1 ↔ u2 (nutation half-period) is K(k)/λ.
///
/// Angles. The paper's (s19) + (s21) (c2 = ∂Φ/∂m_φ) split into a total differential and an ε-term: along
/// any path, d(∂Φ/∂m_φ) = dχ − ε (m_φ − m_ψ U) dU / ((1 − U²) √D), where χ is the azimuth of the symmetry
/// axis about k (the non-ε terms of (s21) and of ∂p_θ/∂m_φ add up to (k2 sinφ dθ − sinθ U'_θ dφ)/(1 − U²)
/// = dχ; verified by measurement, docs/seed_paper.md). c2 = const is therefore the textbook precession law
/// ~~~{.unparsed}
///     χ' = (m_φ − m_ψ U) / (I2 (1 − U²)),
/// ~~~
/// and the spin about the axis follows from (s6.1) written in the frame of k (the paper gives no
/// quadrature for ψ): ψ_k' = m_ψ/I3 − χ' U. With 1 − U = (1 − u1)(1 − n1 sn²τ), n1 = (u2 − u1)/(1 − u1),
/// and 1 + U = (1 + u1)(1 − n2 sn²τ), n2 = −(u2 − u1)/(1 + u1), and ∫ dτ/(1 − n sn²τ) = Π(n; am τ | k):
/// ~~~{.unparsed}
///     J1(t) = ∫₀ᵗ dt/(1 − U) = [Π(n1; am τ) − Π(n1; am τ0)] / (λ (1 − u1)),   J2 likewise with n2, 1 + u1,
///     χ(t)   = χ0 + [(m_φ − m_ψ) J1 + (m_φ + m_ψ) J2] / (2 I2),
///     ψ_k(t) = ψ_k0 + m_ψ (1/I3 − 1/I2) t − [(m_φ − m_ψ) J1 − (m_φ + m_ψ) J2] / (2 I2).
/// ~~~
/// The attitude is R(t) = Qᵀ Rz(χ) Rx(θ_k) Rz(ψ_k) with cos θ_k = U, Q the constant rotation taking k to
/// e3 (the textbook's laboratory frame); the paper's Euler angles are those of R(t) by (6.3).
///
/// Conventions: Boost's Π(n; φ | k) = ∫₀^φ dϑ / ((1 − n sin²ϑ) √(1 − k² sin²ϑ)) (NUMERICS.md: GSL's n has
/// the other sign); jacobi_elliptic(k, u, …) and ellint_*(k, …) take the modulus k, not k².
/// Scope: b > 0 and |U| < 1 throughout (u1 > −1, u2 < 1: the symmetry axis never along ±k; the sleeping
/// and "awakened" tops excluded); the constructor throws std::domain_error otherwise. Evaluated in long
/// double; double interface. Not templated on the scalar (Boost's special functions take no Jets).
#pragma once

#include "../core/scalar.hpp"
#include "../core/state.hpp"
#include "euler_angle_top.hpp"

#include <Eigen/Geometry>
#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/ellint_3.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace lgi {

/// The exact motion of a Lagrange top by the quadratures of this header, for one initial state. Immutable after
/// construction: the const members may be called from several threads at once. Each evaluation at a time t costs
/// a few elliptic functions and integrals (Boost.Math) in long double.
class LagrangeTopQuadrature {
 public:
  using L = long double;  ///< the working precision

  /// The top (I1 = I2, I3, b > 0, unit k, z0 = e3) and its state at t = 0. std::domain_error when b ≤ 0, when D
  /// has no band in [−1, 1] where it is positive, or when the axis reaches ±k (|U| = 1).
  LagrangeTopQuadrature(double I2, double I3, double b, const Vec3<double>& k, const State<double>& x0)
      : I2_(I2), I3_(I3), b_(b) {
    if (!(b > 0)) throw std::domain_error("LagrangeTopQuadrature: needs b > 0");
    const Vec3<L> kk = k.cast<L>().normalized();
    // Q: rows (a, c, k), right-handed, so that Q k = e3. For k = (0, k2, k3): Q = Rx(atan2(k2, k3)).
    Vec3<L> a = Vec3<L>::UnitX() - kk.x() * kk;
    if (a.norm() < 0.5L) a = Vec3<L>::UnitY() - kk.y() * kk;
    a.normalize();
    Q_.row(0) = a.transpose();
    Q_.row(1) = kk.cross(a).transpose();
    Q_.row(2) = kk.transpose();

    const Mat3<L> R0 = x0.R.cast<L>();
    const Vec3<L> W0 = x0.Omega.cast<L>();
    const Vec3<L> IW(I2_ * W0.x(), I2_ * W0.y(), I3_ * W0.z());
    U0_ = kk.dot(R0.col(2));
    m_psi_ = I3_ * W0.z();
    m_phi_ = kk.dot(R0 * IW);
    E_total_ = L(0.5) * W0.dot(IW) + b_ * U0_;
    E_ = E_total_ - m_psi_ * m_psi_ / (2 * I3_);

    // D(U) = c3 U³ + c2 U² + c1 U + c0.
    c3_ = 2 * I2_ * b_;
    c2_ = -(2 * I2_ * E_ + m_psi_ * m_psi_);
    c1_ = 2 * m_phi_ * m_psi_ - 2 * I2_ * b_;
    c0_ = 2 * I2_ * E_ - m_phi_ * m_phi_;
    // D's local maximum (the smaller critical point) separates u1 from u2; D > 0 between them.
    const L disc = c2_ * c2_ - 3 * c3_ * c1_;
    const L u_max = disc > 0 ? (-c2_ - std::sqrt(disc)) / (3 * c3_) : U0_;
    const L u_top = std::clamp(u_max, L(-1), L(1));
    if (!(D(u_top) > 0)) throw std::domain_error("LagrangeTopQuadrature: no nutation band (D <= 0 in [-1, 1])");
    u1_ = root(L(-1), u_top);
    u2_ = root(u_top, L(1));
    u3_ = -c2_ / c3_ - u1_ - u2_;  // the sum of the roots
    u3_ = polish(u3_);
    if (!(u1_ > -1 + 1e-12L && u2_ < 1 - 1e-12L))
      throw std::domain_error("LagrangeTopQuadrature: the symmetry axis reaches +-k (|U| = 1), excluded");

    lambda_ = std::sqrt(b_ * (u3_ - u1_) / (2 * I2_));
    modulus_ = std::sqrt((u2_ - u1_) / (u3_ - u1_));
    K_ = boost::math::ellint_1(modulus_);
    n1_ = (u2_ - u1_) / (1 - u1_);
    n2_ = -(u2_ - u1_) / (1 + u1_);
    Pi1_ = boost::math::ellint_3(modulus_, n1_);
    Pi2_ = boost::math::ellint_3(modulus_, n2_);

    // τ0: sn²τ0 = (U0 − u1)/(u2 − u1), on the branch where dU/dτ = 2(u2 − u1) sn cn dn has the sign of U'(0)
    // = k·R0 (Ω × e3).
    const L s2 = std::clamp((U0_ - u1_) / (u2_ - u1_), L(0), L(1));
    const L F = boost::math::ellint_1(modulus_, std::asin(std::sqrt(s2)));
    const L dU0 = kk.dot(R0 * Vec3<L>(W0.y(), -W0.x(), L(0)));
    tau0_ = dU0 >= 0 ? F : -F;
    Pi1_0_ = pi_of_tau(n1_, Pi1_, tau0_);
    Pi2_0_ = pi_of_tau(n2_, Pi2_, tau0_);

    // Initial azimuth and spin: the Euler angles (6.3) of the attitude in the frame where k = e3.
    const Vec3<L> a0 = euler_angles_from_rotation(Mat3<L>(Q_ * R0));
    chi0_ = a0[0];
    psi_k0_ = a0[2];
  }

  // --- the integrals and the cubic ------------------------------------------------------------------
  /// The total energy ½ Ω·JΩ + b k·(R e3) of the initial state.
  double energy_total() const { return static_cast<double>(E_total_); }
  /// E of (s12), the reduced theory's energy: energy_total() − m_ψ²/(2 I3).
  double energy_s12() const { return static_cast<double>(E_); }
  /// m_φ = m·k = k·(R J Ω).
  double m_phi() const { return static_cast<double>(m_phi_); }
  /// m_ψ = I3 Ω3.
  double m_psi() const { return static_cast<double>(m_psi_); }
  /// The radicand of (s15)/(s18): D(U) = 2 I2 (1 − U²)(E − bU) − (m_φ − m_ψ U)².
  L D(L U) const { return ((c3_ * U + c2_) * U + c1_) * U + c0_; }
  /// The same written as (s18) prints it (not expanded), and its derivative, in any floating type F that
  /// long double converts to exactly (a check on the expansion, and extended-precision quadrature).
  template <class F>
  F D_as_printed(const F& U) const {
    const F I2(I2_), b(b_), E(E_), mf(m_phi_), mp(m_psi_), one(1);
    return 2 * I2 * (one - U * U) * (E - b * U) - (mf - mp * U) * (mf - mp * U);
  }
  /// dD/dU of D_as_printed, in F.
  template <class F>
  F dD_as_printed(const F& U) const {
    const F I2(I2_), b(b_), E(E_), mf(m_phi_), mp(m_psi_), one(1);
    return 2 * I2 * (-2 * U * (E - b * U) - b * (one - U * U)) + 2 * mp * (mf - mp * U);
  }
  /// The roots of D: −1 < u1 ≤ U(t) ≤ u2 < 1 ≤ u3 (U = cos of the axis' angle to k oscillates in [u1, u2]).
  double u1() const { return static_cast<double>(u1_); }
  /// See u1().
  double u2() const { return static_cast<double>(u2_); }
  /// See u1().
  double u3() const { return static_cast<double>(u3_); }
  /// (u1, u2, u3) in full (long double) precision.
  std::array<L, 3> roots() const { return {u1_, u2_, u3_}; }
  /// λ = √(b (u3 − u1)/(2 I2)): U(t) = u1 + (u2 − u1) sn²(τ0 + λt, κ), in 1/time.
  double lambda() const { return static_cast<double>(lambda_); }
  /// κ = √((u2 − u1)/(u3 − u1)), the modulus of the elliptic functions.
  double modulus() const { return static_cast<double>(modulus_); }
  /// Time between consecutive turning points of U (u1 ↔ u2): (s18) between the roots, K(k)/λ.
  double nutation_half_period() const { return static_cast<double>(K_ / lambda_); }
  /// Q, the rotation of the laboratory frame with Q k = e3 in which the angles are taken.
  const Mat3<L>& frame_of_k() const { return Q_; }

  // --- the solution -----------------------------------------------------------------------------------
  /// U(t) = k·(R(t) e3), the cosine of the symmetry axis' angle to k.
  double U(double t) const {
    const Jacobi j = jacobi(tau(t));
    return static_cast<double>(u1_ + (u2_ - u1_) * j.sn * j.sn);
  }
  /// dU/dt at t.
  double dU(double t) const {
    const Jacobi j = jacobi(tau(t));
    return static_cast<double>(2 * lambda_ * (u2_ - u1_) * j.sn * j.cn * j.dn);
  }
  /// Azimuth of the symmetry axis about k (continuous in t) and the spin angle about the axis.
  double chi(double t) const { return static_cast<double>(angles(t).chi); }
  /// The spin angle ψ about the symmetry axis at t, in the frame of k (frame_of_k).
  double psi_k(double t) const { return static_cast<double>(angles(t).psi); }

  /// R(t) and Ω(t) in the laboratory frame of the constructor's k.
  State<double> state(double t) const {
    const Angles a = angles(t);
    const Jacobi j = jacobi(tau(t));
    const L U = u1_ + (u2_ - u1_) * j.sn * j.sn;
    const L dU = 2 * lambda_ * (u2_ - u1_) * j.sn * j.cn * j.dn;
    const L s = std::sqrt((1 - U) * (1 + U));
    const L theta = std::atan2(s, U);
    const L dchi = (m_phi_ - m_psi_ * U) / (I2_ * s * s);
    const L dtheta = -dU / s;
    const L dpsi = m_psi_ / I3_ - dchi * U;
    State<double> x;
    x.R = (Q_.transpose() * rotation_from_euler_angles(a.chi, theta, a.psi)).cast<double>();
    Vec3<L> W = body_rate_from_euler_rates(theta, a.psi, dchi, dtheta, dpsi);
    W.z() = m_psi_ / I3_;
    x.Omega = W.cast<double>();
    return x;
  }

 private:
  struct Jacobi {
    L sn, cn, dn, am;
  };
  struct Angles {
    L chi, psi;
  };

  L tau(double t) const { return tau0_ + lambda_ * L(t); }

  /// sn, cn, dn and am(τ), with τ reduced to [−K, K] first (sn² has period 2K; am(τ + 2K) = am(τ) + π).
  Jacobi jacobi(L tau) const {
    const L j = std::round(tau / (2 * K_));
    const L r = tau - 2 * K_ * j;
    L cn, dn;
    const L sn = boost::math::jacobi_elliptic(modulus_, r, &cn, &dn);
    return {sn, cn, dn, std::atan2(sn, cn) + j * std::numbers::pi_v<L>};
  }
  /// Π(n; am τ | k), continued past ±K by Π(n; φ + jπ) = Π(n; φ) + 2j Π(n).
  L pi_of_tau(L n, L Pi_complete, L tau) const {
    const L j = std::round(tau / (2 * K_));
    const Jacobi r = jacobi(tau - 2 * K_ * j);
    return boost::math::ellint_3(modulus_, n, r.am) + 2 * j * Pi_complete;
  }
  Angles angles(double t) const {
    const L T = tau(t);
    const L J1 = (pi_of_tau(n1_, Pi1_, T) - Pi1_0_) / (lambda_ * (1 - u1_));
    const L J2 = (pi_of_tau(n2_, Pi2_, T) - Pi2_0_) / (lambda_ * (1 + u1_));
    const L a = (m_phi_ - m_psi_) * J1, c = (m_phi_ + m_psi_) * J2;
    return {chi0_ + (a + c) / (2 * I2_), psi_k0_ + m_psi_ * (1 / I3_ - 1 / I2_) * L(t) - (a - c) / (2 * I2_)};
  }

  /// The root of D in [lo, hi] (D changes sign there): bisection, then Newton to round-off.
  L root(L lo, L hi) const {
    const bool rising = D(hi) > D(lo);
    for (int i = 0; i < 80; ++i) {
      const L mid = (lo + hi) / 2;
      if ((D(mid) > 0) == rising)
        hi = mid;
      else
        lo = mid;
    }
    return polish((lo + hi) / 2);
  }
  /// Newton steps, each accepted only when it is a small correction (a near-double root u1 ≈ u2 has
  /// D' ≈ 0 there, where bisection's answer is already the best available).
  L polish(L u) const {
    for (int i = 0; i < 3; ++i) {
      const L d = (3 * c3_ * u + 2 * c2_) * u + c1_;
      if (d == 0) break;
      const L step = D(u) / d;
      if (!(std::abs(step) < 1e-9L * (1 + std::abs(u)))) break;
      u -= step;
    }
    return u;
  }

  L I2_, I3_, b_;
  Mat3<L> Q_;
  L U0_, m_psi_, m_phi_, E_total_, E_;
  L c3_, c2_, c1_, c0_;
  L u1_, u2_, u3_;
  L lambda_, modulus_, K_, n1_, n2_, Pi1_, Pi2_;
  L tau0_, Pi1_0_, Pi2_0_, chi0_, psi_k0_;
};

}  // namespace lgi
