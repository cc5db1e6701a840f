/// \file
/// lgi/core/so3.hpp — the rotation group SO(3) and its Lie algebra so(3) ≅ R³.
///
/// Representation. A rotation is a plain 3×3 matrix R (`Mat3<T>`), body → laboratory: its columns are the
/// body axes in laboratory coordinates. Nothing here re-orthonormalises; every map below returns a matrix
/// orthogonal to round-off (‖RᵀR − I‖_F of a few ulps) when its input is. Integrators update an attitude
/// as R + R·(F − I), with the increment F − I formed without the 1 (rodrigues_increment, exp_increment):
/// the rounding of 1 − O(θ²) on F's diagonal repeats identically every step when θ is small and steady,
/// and would add up to a drift linear in the number of steps (docs/findings.md); without it the departure
/// from SO(3) is a random walk of round-off, ≈ √n·ε after n steps.
///
/// Conventions (right trivialisation: body velocities, updates R·Exp(u)):
/// ~~~{.unparsed}
///   hat(ω) v = ω × v,                               vee(hat(ω)) = ω
///   exp(ω)   = I + A hat(ω) + B hat(ω)²             A = sin θ/θ, B = (1 − cos θ)/θ², θ = |ω|   (Rodrigues)
///   log(R)   = ω with exp(ω) = R, θ ∈ [0, π]
///   exp(ω + δ) = exp(ω) exp(J_r(ω) δ + O(δ²))        right Jacobian
///   J_r(ω)   = I − B hat(ω) + C hat(ω)²              C = (θ − sin θ)/θ³
///   J_r⁻¹(ω) = I + ½ hat(ω) + D hat(ω)²              D = 1/θ² − (1 + cos θ)/(2θ sin θ)
///            = Σ_k B_k/k! (−ad_ω)^k (Bernoulli numbers B_k, B_1 = −½), singular at θ = 2π
///   J_l(ω)   = J_r(−ω) = exp(ω) J_r(ω)
///   cay(ω)   = (I − ½hat(ω))⁻¹(I + ½hat(ω)) = I + 4/(4 + θ²) (hat(ω) + ½ hat(ω)²)
/// ~~~
/// References: Solà, Deray, Atchuthan, "A micro Lie theory for state estimation in robotics",
/// arXiv:1812.01537, App. B: eq. (132) Exp (Rodrigues), (133) Log, (143)–(146) J_r, J_r⁻¹, J_l, J_l⁻¹;
/// Hairer, Lubich, Wanner, Geometric Numerical Integration, 2nd ed. (2006), Lemma III.4.2 (dexp⁻¹ as a
/// Bernoulli series), §IV.8.3 Lemma 8.7 (Cayley map).
///
/// exp's coefficients A = sin θ/θ, B = (1 − cos θ)/θ²: θ² < 1e-2, Taylor polynomials in θ²; for double and Jets
/// of double, 1e-2 ≤ θ² < 2, B by its Taylor polynomial to θ¹⁸ and A = √(B (2 − θ² B)), and θ² ≥ 2, θ ≤ π,
/// A = sin θ/θ, B = 2 (sin(θ/2)/θ)² with core/trig.hpp's polynomial sin (deterministic + − × and √, so that a
/// vector kernel computes the same bits: integrators/batch_rkmk.hpp); θ > π, and other scalars (long double
/// references, float), the sine formulas with libm's sin. A = √(B (2 − θ² B)) makes Rodrigues' orthogonality
/// factor 2B − A² − θ²B² (RᵀR = I + (2B − A² − θ²B²) hat(ω)²) the rounding of one square root, unbiased; A by its
/// own series would bias it (docs/findings.md). The Jacobians, log and tan below use libm.
///
/// Scalars. Every function is a template on T and correct for ceres::Jet: the coefficients A…D are
/// Taylor polynomials in θ² (never sqrt or division at θ = 0) below a threshold where the polynomial is
/// exact to round-off in value *and* first derivative; log takes the angle with atan2, switches to the
/// symmetric part of R for θ > π/2 (robust near π), and uses a series in sin²θ near the identity.
#pragma once

#include "scalar.hpp"
#include "trig.hpp"

/// SO(3) and so(3) ≅ R³: hat/vee, exp/log, the right and left Jacobians, the Cayley map (this header's equations).
namespace lgi::so3 {

/// The skew-symmetric matrix of w: hat(w) v = w × v for every v. Exact (no rounding), any scalar.
template <class T>
Mat3<T> hat(const Vec3<T>& w) {
  Mat3<T> W;
  W << T(0), -w.z(), w.y(),  //
      w.z(), T(0), -w.x(),   //
      -w.y(), w.x(), T(0);
  return W;
}

/// The axial vector of the antisymmetric part: vee(M) = vee(½(M − Mᵀ)); exact inverse of hat.
template <class T>
Vec3<T> vee(const Mat3<T>& M) {
  return Vec3<T>(M(2, 1) - M(1, 2), M(0, 2) - M(2, 0), M(1, 0) - M(0, 1)) * T(0.5);
}

/// θ² below which the coefficients are evaluated by their Taylor polynomials. At θ² = 1e-2 the
/// truncated series below are exact to < 1e-18 relative in value and < 1e-15 in d/dθ².
inline constexpr double small_angle_theta2 = 1e-2;

namespace detail {
// True for the scalars that take the small-angle series of this header (float, double, long double and Jets of them):
// its coefficients are doubles and its terms reach double's round-off. A wider real scalar (binary128, Boost's
// cpp_bin_float) takes the closed forms at every angle, to its own precision: the series' double coefficients would
// put an error of ≈ 1e-17 θ³ in every exponential (a global error O(h²) under an RKMK step), and their truncation one
// of ≈ θ¹².
template <class T>
inline constexpr bool small_angle_series_v = std::is_floating_point_v<decltype(value_of(std::declval<const T&>()))>;

// Horner evaluation of c0 + c1 x + c2 x² + … (coefficients as doubles, converted to T once each).
template <class T, std::size_t N>
T horner(const T& x, const double (&c)[N]) {
  T r = T(c[N - 1]);
  for (std::size_t i = N - 1; i-- > 0;) r = r * x + T(c[i]);
  return r;
}
}  // namespace detail

/// Coefficients of the Rodrigues formula and of the Jacobians, computed once and shared.
template <class T>
struct Coefficients {
  T theta2;  ///< θ² = ω·ω
  T A;       ///< sin θ / θ
  T B;       ///< (1 − cos θ)/θ²
};

namespace detail {
// exp_coefficients for θ² ≥ 1e-2, out of line: the branch is rare in small steps, and inlined into a flattened
// step it slows the common Taylor path (benchmarks/exp_count rkmk4_small measures it).
template <class T>
[[gnu::noinline]] Coefficients<T> exp_coefficients_trig(const T& theta2) {
  using std::sin;
  using std::sqrt;
  constexpr bool double_valued = std::is_same_v<std::remove_cvref_t<decltype(value_of(theta2))>, double>;
  // θ² ∈ [1e-2, 2): B's series, A from B (core/trig.hpp; double coefficients, so double-valued scalars only).
  if constexpr (double_valued) {
    if (value_of(theta2) < trig::exp_series_theta2) {
      const T B = horner(theta2, trig::exp_series_B);
      return {theta2, sqrt(B * (T(2) - theta2 * B)), B};
    }
  }
  const T theta = sqrt(theta2);
  // θ ∈ [√2, π]: core/trig.hpp's polynomial sin, for double and Jets of double (its coefficients are doubles:
  // long double and float keep their own libm sin).
  if constexpr (double_valued) {
    if (value_of(theta) <= trig::max_argument) {
      const T s = trig::sin_0_pi(theta / T(2)) / theta;  // no cancellation in 1 − cos θ = 2 sin²(θ/2)
      return {theta2, trig::sin_0_pi(theta) / theta, T(2) * s * s};
    }
  }
  // θ > π (or not finite): the same formulas with libm's sin, which no kernel vectorises bit-identically: the
  // batch kernels call this function for such lanes (integrators/batch_rkmk_kernel.hpp).
  const T s = sin(theta / T(2)) / theta;
  return {theta2, sin(theta) / theta, T(2) * s * s};
}
}  // namespace detail

/// A = sin θ/θ and B = (1 − cos θ)/θ² of w (θ = |w|), with θ² itself: Taylor polynomials in θ² below
/// small_angle_theta2; for double-valued scalars B's series with A = √(B (2 − θ² B)) below θ² = 2 and the
/// polynomial sin of core/trig.hpp up to θ = π; libm beyond (and for other scalars). Finite for every finite w,
/// accurate to a few ulps.
template <class T>
Coefficients<T> exp_coefficients(const Vec3<T>& w) {
  const T theta2 = w.squaredNorm();
  static_assert(trig::exp_taylor_theta2 == small_angle_theta2);
  if constexpr (detail::small_angle_series_v<T>) {
    if (value_of(theta2) < small_angle_theta2)
      return {theta2, detail::horner(theta2, trig::exp_taylor_A), detail::horner(theta2, trig::exp_taylor_B)};
  } else if (value_of(theta2) == 0) {
    return {theta2, T(1), T(1) / T(2)};
  }
  return detail::exp_coefficients_trig(theta2);
}

/// A hat(w) + B hat(w)², built entry by entry with hat(w)² = w wᵀ − |w|² I (no 3×3 product): the
/// increment F − I of F = I + A hat(w) + B hat(w)², without forming the 1 (see the header). exp
/// (A = sin θ/θ, B = (1 − cos θ)/θ²) and the Cayley map (A = 2B = 4/(4 + θ²)) are of this form.
template <class T>
Mat3<T> rodrigues_increment(const Vec3<T>& w, const T& A, const T& B) {
  const T bx = B * w.x(), by = B * w.y(), bz = B * w.z();
  const T bxx = bx * w.x(), byy = by * w.y(), bzz = bz * w.z();
  const T bxy = bx * w.y(), bxz = bx * w.z(), byz = by * w.z();
  const T ax = A * w.x(), ay = A * w.y(), az = A * w.z();
  Mat3<T> D;
  D << -(byy + bzz), bxy - az, bxz + ay,  //
      bxy + az, -(bxx + bzz), byz - ax,   //
      bxz - ay, byz + ax, -(bxx + byy);
  return D;
}

/// v + A w × v + B w × (w × v): the product (I + A hat(w) + B hat(w)²) v without forming the matrix.
/// exp(ω)ᵀ v = exp(−ω) v is rotate(ω, −A, B, v).
template <class T>
Vec3<T> rotate(const Vec3<T>& w, const T& A, const T& B, const Vec3<T>& v) {
  const Vec3<T> wv = w.cross(v);
  return v + A * wv + B * w.cross(wv);
}

/// I + A hat(w) + B hat(w)².
template <class T>
Mat3<T> rodrigues(const Vec3<T>& w, const T& A, const T& B) {
  Mat3<T> R = rodrigues_increment(w, A, B);
  R.diagonal().array() += T(1);
  return R;
}

/// exp: so(3) → SO(3), Rodrigues' formula. Any finite w (θ = |w| in radians, any size); the result is
/// orthogonal to round-off.
template <class T>
Mat3<T> exp(const Vec3<T>& w) {
  const Coefficients<T> k = exp_coefficients(w);
  return rodrigues(w, k.A, k.B);
}

/// exp(w) − I, for updates R + R·(exp(w) − I) (see the header).
template <class T>
Mat3<T> exp_increment(const Vec3<T>& w) {
  const Coefficients<T> k = exp_coefficients(w);
  return rodrigues_increment(w, k.A, k.B);
}

/// log: SO(3) → so(3), the principal logarithm (θ ∈ [0, π]). At θ = π exactly, either of ±π·n is returned.
/// R must be a rotation to round-off; for other matrices the result means nothing (it may be NaN) and no error is
/// reported.
template <class T>
Vec3<T> log(const Mat3<T>& R) {
  using std::atan2;
  using std::sqrt;
  const T c = (R.trace() - T(1)) / T(2);  // cos θ
  const Vec3<T> v = vee(R);               // sin θ · n
  if (value_of(c) >= 0) {                 // θ ≤ π/2: θ = asin(|v|)
    const T s2 = v.squaredNorm();
    if (detail::small_angle_series_v<T> ? value_of(s2) < small_angle_theta2 : value_of(s2) == 0) {
      // asin(s)/s = Σ (2n)! / (4ⁿ (n!)² (2n+1)) s^(2n); exact to < 1e-20 for s² < 1e-2.
      static constexpr double a[] = {1.0,          1.0 / 6,        3.0 / 40,        5.0 / 112,       35.0 / 1152,
                                     63.0 / 2816, 231.0 / 13312, 143.0 / 10240, 6435.0 / 557056};
      return detail::horner(s2, a) * v;
    }
    const T s = sqrt(s2);
    return (atan2(s, c) / s) * v;
  }
  // θ > π/2: the symmetric part (R + Rᵀ)/2 − cos θ I = (1 − cos θ) n nᵀ gives the axis without
  // dividing by sin θ; its largest diagonal entry is ≥ (1 − cos θ)/3 > 0.
  Mat3<T> S = (R + R.transpose()) / T(2);
  S.diagonal().array() -= c;
  int i = 0;
  if (value_of(S(1, 1)) > value_of(S(i, i))) i = 1;
  if (value_of(S(2, 2)) > value_of(S(i, i))) i = 2;
  const Vec3<T> n = S.col(i) / sqrt(S(i, i) * (T(1) - c));  // ±axis
  return atan2(n.dot(v), c) * n;  // either sign of n gives θ·axis: atan2(−s, c)(−n) = atan2(s, c) n
}

/// D(θ²) = 1/θ² − (1 + cos θ)/(2θ sin θ), the coefficient of hat(ω)² in J_r⁻¹. Just above the Taylor
/// threshold the closed form loses ~3 digits to cancellation (relative error ≤ 6e-14 near θ² = 2e-2);
/// J_r⁻¹ multiplies it by hat(ω)² = O(θ²), so J_r⁻¹ itself stays accurate to round-off.
template <class T>
T jacobian_inverse_coefficient(const T& theta2) {
  using std::sin;
  using std::sqrt;
  using std::tan;
  if (detail::small_angle_series_v<T> ? value_of(theta2) < small_angle_theta2 : value_of(theta2) == 0) {
    static constexpr double d[] = {1.0 / 12, 1.0 / 720, 1.0 / 30240, 1.0 / 1209600, 1.0 / 47900160};
    return detail::horner(theta2, d);
  }
  const T theta = sqrt(theta2);
  // (θ/2) cot(θ/2) = θ sin θ / (2 (1 − cos θ)); written with tan(θ/2) to avoid the cancellation in 1 − cos θ.
  return (T(1) - (theta / T(2)) / tan(theta / T(2))) / theta2;
}

/// Right Jacobian J_r(ω): exp(ω + δ) = exp(ω) exp(J_r(ω) δ) to first order in δ.
template <class T>
Mat3<T> right_jacobian(const Vec3<T>& w) {
  using std::sin;
  using std::sqrt;
  const T theta2 = w.squaredNorm();
  T B, C;  // (1 − cos θ)/θ², (θ − sin θ)/θ³
  if (detail::small_angle_series_v<T> ? value_of(theta2) < small_angle_theta2 : value_of(theta2) == 0) {
    static constexpr double b[] = {0.5, -1.0 / 24, 1.0 / 720, -1.0 / 40320, 1.0 / 3628800, -1.0 / 479001600};
    static constexpr double c[] = {1.0 / 6, -1.0 / 120, 1.0 / 5040, -1.0 / 362880, 1.0 / 39916800, -1.0 / 6227020800};
    B = detail::horner(theta2, b);
    C = detail::horner(theta2, c);
  } else {
    const T theta = sqrt(theta2);
    const T s = sin(theta / T(2)) / theta;
    B = T(2) * s * s;
    C = (theta - sin(theta)) / (theta2 * theta);
  }
  const Mat3<T> W = hat(w);
  Mat3<T> J = C * (W * W) - B * W;
  J.diagonal().array() += T(1);
  return J;
}

/// Inverse right Jacobian J_r⁻¹(ω) (closed form, valid for θ < 2π).
template <class T>
Mat3<T> right_jacobian_inverse(const Vec3<T>& w) {
  const Mat3<T> W = hat(w);
  Mat3<T> J = jacobian_inverse_coefficient(w.squaredNorm()) * (W * W) + T(0.5) * W;
  J.diagonal().array() += T(1);
  return J;
}

/// Left Jacobian J_l(ω) = J_r(−ω): exp(ω + δ) = exp(J_l(ω) δ) exp(ω) to first order.
template <class T>
Mat3<T> left_jacobian(const Vec3<T>& w) {
  return right_jacobian(Vec3<T>(-w));
}

/// J_r⁻¹(u) v truncated after the ad_u^K term: Σ_{k≤K} B_k/k! (−ad_u)^k v
/// ~~~{.unparsed}
///   = v + ½ u×v + (1/12) u×(u×v) − (1/720) ad_u⁴ v + (1/30240) ad_u⁶ v − (1/1209600) ad_u⁸ v.
/// ~~~
/// An RKMK method of order p needs K = p − 2 (Hairer–Lubich–Wanner, Theorem IV.8.5; Munthe-Kaas,
/// Appl. Numer. Math. 29 (1999) 115); integrators/rkmk.hpp keeps K = p for an embedded pair (its error estimate);
/// the truncated series is a polynomial: no trigonometric functions, exact for Jets. Since u · (u × v) = 0,
/// ad_u³ v = −θ² ad_u v and ad_u^(2j+2) v = (−θ²)^j ad_u² v (θ² = |u|²), so it is evaluated with two cross products
/// and a polynomial in θ² (Horner) instead of K chained cross products:
/// ~~~{.unparsed}
///   = v + ½ u×v + c(θ²) u×(u×v),   c(θ²) = 1/12 + θ²/720 + θ⁴/30240 + θ⁶/1209600   (terms up to k = K).
/// ~~~
/// Its coefficients are doubles for double-valued scalars (double, Jets of double) and B_k/k! formed in T
/// otherwise, so that a wider scalar (long double, binary128, cpp_bin_float) carries no double rounding in them.
template <int K, class T>
Vec3<T> right_jacobian_inverse_series(const Vec3<T>& u, const Vec3<T>& v) {
  static_assert(K >= 0 && K <= 8, "right_jacobian_inverse_series: K in [0, 8]");
  Vec3<T> r = v;
  if constexpr (K >= 1) {
    // B_k/k! = numerator[k] / denominator[k]
    static constexpr int numerator[] = {0, 1, 1, 0, -1, 0, 1, 0, -1};
    static constexpr int denominator[] = {1, 2, 12, 1, 720, 1, 30240, 1, 1209600};
    using Value = std::remove_cvref_t<decltype(value_of(std::declval<const T&>()))>;
    constexpr bool double_valued = std::is_same_v<Value, double>;
    const auto coeff = [](int k) {
      if constexpr (double_valued)
        return T(static_cast<double>(numerator[k]) / denominator[k]);
      else
        return T(T(numerator[k]) / T(denominator[k]));
    };
    const Vec3<T> w1 = u.cross(v);
    r += coeff(1) * w1;
    if constexpr (K >= 2) {
      constexpr int top = K % 2 == 1 ? K - 1 : K;  // the last non-zero term (B_k = 0 for odd k ≥ 3)
      const Vec3<T> w2 = u.cross(w1);
      T c = coeff(top);
      if constexpr (top >= 4) {
        const T minus_theta2 = -u.squaredNorm();
        for (int k = top - 2; k >= 2; k -= 2) c = c * minus_theta2 + coeff(k);
      }
      r += c * w2;
    }
  }
  return r;
}

/// Cayley map and its inverse (defined for θ < π).
/// cay(w) = I + 4/(4 + θ²) (hat(w) + ½ hat(w)²): a rotation by 2 atan(θ/2) < π about w, for every finite w,
/// orthogonal to round-off; rational, no trigonometric function.
template <class T>
Mat3<T> cayley(const Vec3<T>& w) {
  const T A = T(4) / (T(4) + w.squaredNorm());
  return rodrigues(w, A, T(0.5) * A);
}

/// cay⁻¹(R) = 4 vee(R)/(1 + tr R), for a rotation R by an angle below π (at π, 1 + tr R = 0: the result is not
/// finite). R must be a rotation to round-off.
template <class T>
Vec3<T> cayley_inverse(const Mat3<T>& R) {
  return (T(4) / (T(1) + R.trace())) * vee(R);  // 2 vee(R − Rᵀ)/(1 + tr R)
}

/// cay(w) − I, for updates R + R·(cay(w) − I) (see the header on the rounding of increments).
template <class T>
Mat3<T> cayley_increment(const Vec3<T>& w) {
  const T A = T(4) / (T(4) + w.squaredNorm());
  return rodrigues_increment(w, A, T(0.5) * A);
}

/// The right-trivialised inverse differential of the Cayley map: with R(t) = R₀ cay(u(t)) and the body
/// velocity Ω (R' = R hat(Ω)),  u' = dcay⁻¹_u(Ω) = Ω + ½ u × Ω + ¼ (u·Ω) u  — exact and polynomial, where the
/// exponential's J_r⁻¹ is a series (HLW §IV.8.3, dcay⁻¹_C(H) = (I − C/2) H (I + C/2), in vector form;
/// tests/core/test_so3.cpp differentiates cayley_inverse to check it).
template <class T>
Vec3<T> cayley_right_jacobian_inverse(const Vec3<T>& u, const Vec3<T>& v) {
  return v + T(0.5) * u.cross(v) + (T(0.25) * u.dot(v)) * u;
}

/// ‖RᵀR − I‖_F: distance from orthogonality. A diagnostic: with Jets its derivative at an exactly
/// orthogonal R is NaN (the Frobenius norm is not differentiable at 0).
template <class T>
T orthogonality_error(const Mat3<T>& R) {
  Mat3<T> E = R.transpose() * R;
  E.diagonal().array() -= T(1);
  return E.norm();
}

}  // namespace lgi::so3
