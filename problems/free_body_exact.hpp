/// \file
/// lgi/problems/free_body_exact.hpp — the exact motion of the free rigid body (Euler–Poinsot), by Jacobi
/// elliptic functions and the elliptic integral of the third kind.
///
/// Problem: J Ω' = (JΩ) × Ω, R' = R hat(Ω) (problems/free_body.hpp), J any symmetric positive-definite
/// tensor. J is diagonalised once, J = Q diag(I1, I2, I3) Qᵀ with I1 ≤ I2 ≤ I3 and Q a rotation (exactly a
/// signed permutation when J is diagonal); in principal axes the attitude is R_p = R Q and the body momentum
/// m = Qᵀ J Ω. Everything below is in principal axes. Integrals: G² = |m|², 2T = Σ m_i²/I_i, R m = μ.
///
/// Euler's equations m' = m × Ω, Ω_i = m_i/I_i (Celledoni, Fassò, Säfström, Zanna [CFSZ], §2.2), with
/// Leroy's cancellation-free forms (Leroy [L], "The quantity Δ_j"):
/// ~~~{.unparsed}
///   Δ1 = m2² I21/I2 + m3² I31/I3 ≥ 0,   Δ3 = −(m1² I31/I1 + m2² I32/I2) ≤ 0,   Δ2 = m3² I32/I3 − m1² I21/I1,
///   (Δj = G² − 2T Ij, Ijh = Ij − Ih). The sign of Δ2 is the regime:
///   Δ2 < 0  [CFSZ case (i)]: m circles the axis of the smallest moment I1 (m1 keeps its sign σ), a = 1, p = 3;
///   Δ2 > 0  [CFSZ case (ii)]: m circles the axis of the largest moment I3 (m3 keeps its sign σ), a = 3, p = 1;
///   Δ2 = 0  [CFSZ case (iii)]: the separatrix.
///   Elliptic cases, u = λ t + u0:
///     m_p = A_p cn(u, κ),   m2 = A2 sn(u, κ),   m_a = σ A_a dn(u, κ),
///     A1² = −Δ3 I1/I31,  A3² = Δ1 I3/I31,  A2² = −Δ3 I2/I32 (a = 3) or Δ1 I2/I21 (a = 1),
///     λ = σ A1 A3 I31/(A2 I1 I3)  (λ² = Δ1 I32/(I1I2I3) for a = 3, −Δ3 I21/(I1I2I3) for a = 1),
///     κ² = −Δ3 I21/(Δ1 I32) (a = 3) or Δ1 I32/(−Δ3 I21) (a = 1), and the complementary parameter without
///     cancellation, m_c = 1 − κ² = Δ2 I31/(Δ1 I32) or Δ2 I31/(Δ3 I21) [L, "The elliptic modulus"];
///     u0 = F(am0, κ) with am0 = atan2(m2/A2, m_p/A_p) ∈ (−π, π] (the full quadrant: the one-argument
///     arctan of [L], "Phase and initial value", fixes am0 only modulo π, i.e. the signs of sn and cn
///     together, and is wrong when m_p < 0).
///   Separatrix: m = (σ1 A1 sech u, G tanh u, σ3 A3 sech u), λ = σ1σ3 A1 A3 I31/(G I1 I3), u0 = asinh(m2/√(m1² + m3²))
///     ([L], "Case (iii)": the published case (iii) forces m1, m3 to one sign; [L] adds the second sign).
///   The sign of λ corrects [CFSZ]: it is that of m_a (here, with the sn component written +A2 sn; [L],
///   "Case (i)"/"Case (ii)" give the same correction, λ = −σλ3 / −σλ1 with −B sn). Every sign above was
///   checked by differentiating m(t) against Euler's equations and, end to end, by the tests.
/// ~~~
///
/// Attitude. With the polar axis e_a (the component that keeps its sign, so ρ² = G² − m_a² > 0 throughout),
/// the body frame B(m) = [b1 b2 b3], b3 = m/G, b1 = e_a × m/ρ, b2 = b3 × b1, depends on m alone, and
/// ~~~{.unparsed}
///     R_p(t) = R_p(0) B(m(0)) E(φ(t)) B(m(t))ᵀ,      E(φ) = rotation by φ about e3,
/// ~~~
/// keeps R_p m = μ by construction; R_p' = R_p hat(Ω) holds iff φ' = Ω·b3 − b2'·b1, which Euler's equations
/// turn into the classical precession rate (Landau & Lifshitz, Mechanics, §37, for a = 3)
/// ~~~{.unparsed}
///     φ' = G (m_b²/I_b + m_c²/I_c)/ρ² = G/I_a − (G Δ_a/I_a)/ρ²,     ρ² = A_p² (1 − n sn²u),
///     n = −I3 I21/(I1 I32) (a = 3) or −I1 I32/(I3 I21) (a = 1)  (n < 0: no pole),
/// ~~~
/// so, with Π(n; ϕ, κ) = ∫₀^ϕ dθ / ((1 − n sin²θ) √(1 − κ² sin²θ)) (Boost's and A&S's sign of n; GSL's is
/// the opposite),
/// ~~~{.unparsed}
///     φ(t) = (G/I_a) t + s (G I31/(I1 I3 λ)) [Π(n; am u, κ) − Π(n; am u0, κ)],   s = +1 (a = 3), −1 (a = 1).
/// ~~~
/// This is the same Π(n) as [L]'s corrected "alternative quaternionic solution" (his n = I3 I21/(I1 I23) in
/// case (ii), I1 I32/(I3 I12) in case (i)): his quaternion maps m to e_a by the smallest rotation, which adds
/// an arctan(… sc u) term that jumps at every zero of cn; the frame B above differs from his by a rotation
/// about m and needs no arctan and no unwrapping. On the separatrix the integral is elementary:
/// ~~~{.unparsed}
///     φ(t) = (2T/G) t − (Δ_a/(I_a λ G)) β [atan(β tanh u) − atan(β tanh u0)],   β = A_a/A_p,
/// ~~~
/// with a = 1 if A1 ≤ A3, else 3 (then ρ² ≥ G²/2).
/// Special cases, exactly: m = 0 (rest); m along a principal axis (steady rotation, R_p(t) = R_p(0) exp(tΩ));
/// two equal moments (I_j = I_k = I⊥ ≠ I_s: R_p(t) = R_p(0) exp(t hat(m(0))/I⊥) exp(t c ê_s),
/// m(t) = exp(−t c ê_s) m(0), c = (1/I_s − 1/I⊥) m_s), and the sphere. Principal moments closer than
/// 8 ε(T) I3 are taken equal (their mean): J itself is only known to ε(T) in T.
///
/// Numerics.
/// - Incomplete elliptic integrals by Carlson's forms (DLMF §19.25(i), F: 19.25.5; R_F and R_J by one shared
///   duplication, detail::carlson_f_j), fed with cn², dn² = cn² + m_c sn² and m_c, never
///   1 − κ² sin²: Π(n; ϕ, κ) = s RF(c², d², 1) + (n/3) s³ RJ(c², d², 1, 1 − n s²) for |ϕ| ≤ π/2 (s, c =
///   sin, cos ϕ; d² = c² + m_c s²), extended by Π(ϕ + jπ) = Π(ϕ) + 2jΠ(n | κ); the complete K(κ), Π(n | κ)
///   by one arithmetic-geometric mean from κ' (DLMF §19.8(i), detail::complete); all checked against
///   Boost's ellint_1/ellint_3 in the tests.
/// - sn, cn, dn by the descending Landen transformation (DLMF §22.7(i), A&S 16.12) from κ and κ' = √m_c,
///   rational on the way up (detail::jacobi). Not Boost's jacobi_elliptic, measured in the tests: it takes κ
///   and rebuilds κ' by cancellation (sn, cn lose accuracy near the separatrix: docs/free_body_exact.md), its
///   AGM takes asin of arguments → 1 where sn → ±1, and Boost 1.74 returns dn = 1 instead of κ' at u = K (0/0
///   in its cos ϕ₀/cos(ϕ₁ − ϕ₀)).
/// - Near the separatrix Δ2 cancels: it is summed in twice W's precision (error-free transformations), from
///   Ω when J is diagonal and the input is (R, Ω) (Ω_p is then exact), so m_c keeps W's relative accuracy
///   however small it is: with J diagonal the solution stays at round-off of a 113-bit integration over
///   t ≤ 100 down to Δ2/G² = 1e-14 (closer, double data cannot resolve). With J non-diagonal the
///   eigensolver's rounding (in long double) perturbs Δ2 by ≈ 1e-19 G², so the error grows like
///   1e-19/(Δ2/G²) per period, and the 1e-12 accuracy holds only down to |Δ2|/G² ≈ 1e-7 (tests:
///   SeparatrixAgainst113BitIntegration, the δ = ±1e-12, −1e-14 and non-diagonal −1e-8 cases in every run;
///   more with LGI_SLOW_TESTS=1; the figures: docs/free_body_exact.md).
/// - u is reduced to r ∈ [−K, K] (u = 2jK + r; sn, cn change sign with j, dn does not) for long times.
/// - Round-off in t (Vilmart, J. Comput. Phys. 227 (2008)): the phases λt and φ(t) are linear in t, so the
///   relative error of the constants λ, K, Π(n | κ), G/I_a becomes an absolute error growing linearly in t.
///   Every constant and phase is computed in the wide type W (default long double, ε = 1.1e-19) and only the
///   result is rounded to T (the error against a 113-bit evaluation, for W = double and long double:
///   docs/free_body_exact.md).
/// - Flows composed many times (flow(x, h), a splitting's sub-step) are formed as increments
///   (Solution::increment): R + R (Q dM Qᵀ), Ω + Q (dm/I), with dM = M − I and dm = m(h) − m(0) O(h) and
///   built without their O(1) parts — the addition theorems for sn, cn, dn (DLMF §22.8(i)) from the values at
///   u0 read off m(0), and the frame increment B(m(h)) − B(m(0)) without cancellation. Rebuilt from scratch
///   each call instead, m(h) and R(h) make the invariants drift linearly; as increments they random-walk
///   (docs/free_body_exact.md). flow(x, 0) = x.
///
/// Exact: order ∞ up to round-off. Preserves R_p m = μ by construction (to round-off, with no growth in t),
/// |m| and T to round-off (m(t) lies on the invariant curve for every t), R on SO(3) to round-off; the flow
/// is a group: flow(t2) ∘ flow(t1) = flow(t1 + t2) to round-off (≈ ε (1 + |Ω| t2), the rounding of the
/// intermediate state).
///
/// Scalars: T = float, double or long double; W ≥ T a floating-point type (long double, double, or a
/// Boost.Multiprecision type, used by the tests as a 113-bit reference; the eigensolver then still runs in
/// long double). Not ceres::Jet (floating-point scalars only).
/// Cost: one solve = one Carlson duplication (R_F and R_J together); one evaluation = one Landen descent + one
/// duplication (+ one AGM for K, Π(n | κ) at long times or when am u crosses ±π/2, unless precompute_periods); W = long double is several times slower than
/// W = double (x87 transcendental functions; times per call: docs/free_body_exact.md, CostPerCall). Use
/// `FreeBodyExact<double, double>` for splittings (short h: the linear growth in t is irrelevant, and
/// invariants random-walk as above), the default W = long double as a reference solution.
///
/// References.
/// [CFSZ] E. Celledoni, F. Fassò, N. Säfström, A. Zanna, "The exact computation of the free rigid body motion
///   and its use in splitting methods", SIAM J. Sci. Comput. 30 (2008) 2084–2112: §2.2 (Euler's equations
///   by Jacobi elliptic functions, cases (i)–(iii), section number as cited by [L] for the 2007 preprint);
///   the attitude by Π. Equation numbers of the article could not be confirmed from a source available
///   here; none are cited.
/// [L] P. Leroy, "On an Article by Celledoni et al.", Principia repository (mockingbirdnest/Principia),
///   documentation/Celledoni.tex (unnumbered sections named above): corrected λ signs, case (iii), Δ_j and
///   m_c without cancellation, the Π(n) of the attitude angle.
/// Landau & Lifshitz, Mechanics, 3rd ed., §37 (the precession rate of the free asymmetric top; equation
///   number not confirmed). DLMF: NIST Digital Library of Mathematical Functions. A&S: Abramowitz & Stegun,
///   Handbook of Mathematical Functions, 16.12–16.13 (Landen; small-parameter forms), 17.2 (Π's sign of n).
#pragma once

#include "../core/scalar.hpp"
#include "../core/so3.hpp"
#include "../core/state.hpp"

#include <Eigen/Eigenvalues>
#include <boost/math/constants/constants.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <type_traits>

namespace lgi {

namespace free_body_exact_detail {

// R_C(1, 1 + e) = atan(√e)/√e for e ≥ 0 (DLMF 19.2.18 with x = 1); for e ≤ 1/64 by its Maclaurin series
// Σ (−e)^k/(2k + 1), whose terms fall by 64 or more each and are summed until they are below ε/4 (at most
// W's digits/6 + 2 terms past the first).
template <class W>
W rc_one_plus(const W& e) {
  using std::abs;
  using std::atan;
  using std::sqrt;
  if (e <= W(1) / 64) {
    using Table = std::array<W, std::numeric_limits<W>::digits / 6 + 3>;
    static const Table inverse_odd = [] {
      Table r{};
      for (std::size_t k = 0; k < r.size(); ++k) r[k] = W(1) / W(2 * k + 1);
      return r;
    }();
    const W tol = std::numeric_limits<W>::epsilon() / 4;
    W sum = 1, power = 1;
    for (std::size_t k = 1; k < inverse_odd.size(); ++k) {
      power *= -e;
      const W term = power * inverse_odd[k];
      sum += term;
      if (abs(term) <= tol) break;
    }
    return sum;
  }
  const W s = sqrt(e);
  return atan(s) / s;
}

template <class W>
struct CarlsonFJ {
  W RF, RJ;
};

// R_F(x, y, z) and R_J(x, y, z, p) together, for x, y, z ≥ 0 (at most one zero) and p ≥ max(x, y, z) (as in
// Π(n; ϕ, κ) with n < 0: then δ_m ≥ 0 and every R_C term is an arctangent's), by one
// duplication (Carlson, Numer. Algorithms 10 (1995) 13, §2, Algorithms 1 and 3; the two share x_m, y_m,
// z_m and λ_m): with λ_m = √x_m√y_m + √x_m√z_m + √y_m√z_m, d_m = (√p_m + √x_m)(√p_m + √y_m)(√p_m + √z_m),
// (x, y, z, p, A, B)_{m+1} = ((x, y, z, p, A, B)_m + λ_m)/4, δ_{m+1} = δ_m/64, A₀ = (x + y + z + 2p)/5,
// B₀ = (x + y + z)/3, δ₀ = (p − x)(p − y)(p − z),
//   R_F = B_M^{−1/2} (1 − E₂/10 + E₃/14 + E₂²/24 − 3E₂E₃/44 − 5E₂³/208 + 3E₃²/104 + E₂²E₃/16)   (DLMF 19.36.1)
//   R_J = 4^{−M} A_M^{−3/2} (1 − 3E₂/14 + E₃/6 + 9E₂²/88 − 3E₄/22 − 9E₂E₃/52 + 3E₅/26)  (DLMF 19.36.2 to
//         fifth order, Carlson's cut, for which the (ε/4)^{−1/6} below is chosen)
//         + 6 Σ_{m<M} 4^{−m} R_C(1, 1 + δ_m/d_m²)/d_m,
// each E from its own scaled differences (B₀ − x₀)4^{−M}/B_M, (A₀ − x₀)4^{−M}/A_M, …; M the first index with
// 4^{−M} (ε/4)^{−1/6} max|A₀ − (x, y, z, p)₀| < |A_M| and 4^{−M} (3ε)^{−1/6} max|B₀ − (x, y, z)₀| < |B_M|.
// Relative errors a few ε (tests: F and Π against Boost's ellint_1, ellint_3 in 113 bits). Not Boost's ellint_rf and
// ellint_rj: two duplications of the same x, y, z, and an R_C call (with atan) for every step of R_J.
template <class W>
CarlsonFJ<W> carlson_f_j(const W& x0, const W& y0, const W& z0, const W& p0) {
  using std::abs;
  using std::max;
  using std::pow;
  using std::sqrt;
  static const W scale_j = pow(std::numeric_limits<W>::epsilon() / 4, W(-1) / W(6));
  static const W scale_f = pow(3 * std::numeric_limits<W>::epsilon(), W(-1) / W(6));
  const W A0 = (x0 + y0 + z0 + 2 * p0) / 5, B0 = (x0 + y0 + z0) / 3;
  const W QJ = scale_j * max(max(abs(A0 - x0), abs(A0 - y0)), max(abs(A0 - z0), abs(A0 - p0)));
  const W QF = scale_f * max(max(abs(B0 - x0), abs(B0 - y0)), abs(B0 - z0));
  W x = x0, y = y0, z = z0, p = p0, A = A0, B = B0, delta = (p0 - x0) * (p0 - y0) * (p0 - z0), f = 1, sum = 0;
  for (int m = 0; m < 100 && (f * QJ >= abs(A) || f * QF >= abs(B)); ++m) {
    const W rx = sqrt(x), ry = sqrt(y), rz = sqrt(z), rp = sqrt(p);
    const W d = (rp + rx) * (rp + ry) * (rp + rz);
    sum += f * rc_one_plus(W(delta / (d * d))) / d;
    const W lambda = rx * ry + rx * rz + ry * rz;
    x = (x + lambda) / 4;
    y = (y + lambda) / 4;
    z = (z + lambda) / 4;
    p = (p + lambda) / 4;
    A = (A + lambda) / 4;
    B = (B + lambda) / 4;
    f /= 4;
    delta /= 64;
  }
  CarlsonFJ<W> r;
  {
    const W X = f * (B0 - x0) / B, Y = f * (B0 - y0) / B, Z = -(X + Y);
    const W E2 = X * Y - Z * Z, E3 = X * Y * Z;
    r.RF = (1 + E3 * (W(1) / 14 + 3 * E3 / 104) + E2 * (W(-1) / 10 + E2 / 24 - 3 * E3 / 44 - 5 * E2 * E2 / 208 + E2 * E3 / 16)) /
           sqrt(B);
  }
  const W X = f * (A0 - x0) / A, Y = f * (A0 - y0) / A, Z = f * (A0 - z0) / A, P = -(X + Y + Z) / 2;
  const W P2 = P * P, XYZ = X * Y * Z;
  const W E2 = X * Y + X * Z + Y * Z - 3 * P2;
  const W E3 = XYZ + 2 * E2 * P + 4 * P * P2;
  const W E4 = (2 * XYZ + E2 * P + 3 * P * P2) * P;
  const W E5 = XYZ * P2;
  const W series = 1 - 3 * E2 / 14 + E3 / 6 + 9 * E2 * E2 / 88 - 3 * E4 / 22 - 9 * E2 * E3 / 52 + 3 * E5 / 26;
  r.RJ = f * series / (A * sqrt(A)) + 6 * sum;
  return r;
}

template <class W>
struct Complete {
  W K, Pi;
};

// K(κ) and Π(n | κ) for n < 1 from κ' = √m_c by one arithmetic-geometric mean (DLMF §19.8(i), 19.8.5–19.8.7):
// a₀ = 1, g₀ = κ', p₀ = √(1 − n), Q₀ = 1; ε_m = (p_m² − a_m g_m)/(p_m² + a_m g_m), Q_{m+1} = Q_m ε_m/2,
// p_{m+1} = (p_m² + a_m g_m)/(2p_m), (a, g)_{m+1} = ((a_m + g_m)/2, √(a_m g_m)) until a and Σ Q are
// converged; K = π/(2M), Π = π/(4M) (2 + n/(1 − n) Σ Q), M = lim a_m taken as (a + g)/2 of the last pair.
// Quadratic convergence: ≈ 5 steps at κ' = 0.01, where the duplication of R_F(0, m_c, 1) and R_J(0, m_c, 1, 1 − n)
// takes ≈ 10 each.
template <class W>
Complete<W> complete(const W& kc, const W& n) {
  using std::abs;
  using std::sqrt;
  const W tol = std::numeric_limits<W>::epsilon();
  W a = 1, g = kc, p = sqrt(W(1) - n), Q = 1, sum = 0;
  for (int m = 0; m < 64; ++m) {
    const W ag = a * g, p2 = p * p;
    sum += Q;
    if (abs(a - g) <= tol * a && abs(Q) <= tol * abs(sum)) break;
    Q *= (p2 - ag) / (2 * (p2 + ag));
    p = (p2 + ag) / (2 * p);
    a = (a + g) / 2;
    g = sqrt(ag);
  }
  const W quarter_pi_over_M = boost::math::constants::pi<W>() / (2 * (a + g));
  return {2 * quarter_pi_over_M, quarter_pi_over_M * (2 + n / (1 - n) * sum)};
}

// x − y·round(x/y), and whether the integer-valued j is odd (written with floor only, so that W may be a
// Boost.Multiprecision type).
template <class W>
W reduce(const W& x, const W& y, W& j) {
  using std::floor;
  j = floor(x / y + W(0.5));
  return x - y * j;
}
template <class W>
bool is_odd(const W& j) {
  using std::floor;
  return j - 2 * floor(j / 2) != 0;
}

// exp(angle · hat(n)) − I for a unit vector n (Rodrigues, with 1 − cos = 2 sin²(angle/2): no 1 formed).
template <class W>
Mat3<W> rotation_increment(const Vec3<W>& n, const W& angle) {
  using std::sin;
  Mat3<W> N;
  N << W(0), -n(2), n(1), n(2), W(0), -n(0), -n(1), n(0), W(0);
  const W h = sin(angle / 2);
  return Mat3<W>(sin(angle) * N + (2 * h * h) * (N * N));
}
template <class W>
Mat3<W> rotation(const Vec3<W>& n, const W& angle) {
  return Mat3<W>(Mat3<W>::Identity() + rotation_increment(n, angle));
}

// Error-free transformations (Dekker, Numer. Math. 18 (1971) 224; Ogita, Rump, Oishi, SIAM J. Sci. Comput. 26
// (2005) 1955, Alg. 3.1 TwoSum and 3.3 TwoProduct with Veltkamp's split, no FMA needed): a value carried as
// hi + lo in twice W's precision.
template <class W>
struct Double {
  W hi, lo;
};
template <class W>
Double<W> two_sum(const W& a, const W& b) {
  const W s = a + b, bb = s - a;
  return {s, (a - (s - bb)) + (b - bb)};
}
template <class W>
Double<W> two_product(const W& a, const W& b) {
  using std::ldexp;
  const W factor = ldexp(W(1), (std::numeric_limits<W>::digits + 1) / 2) + W(1);
  const W ca = factor * a, cb = factor * b;
  const W ah = ca - (ca - a), al = a - ah, bh = cb - (cb - b), bl = b - bh;
  const W p = a * b;
  return {p, ((ah * bh - p) + ah * bl + al * bh) + al * bl};
}
// (x.hi + x.lo) · b, relative error O(ε²).
template <class W>
Double<W> times(const Double<W>& x, const W& b) {
  Double<W> p = two_product(x.hi, b);
  p.lo += x.lo * b;
  return two_sum(p.hi, p.lo);
}
template <class W>
Double<W> plus(const Double<W>& x, const Double<W>& y) {
  Double<W> s = two_sum(x.hi, y.hi);
  s.lo += x.lo + y.lo;
  return two_sum(s.hi, s.lo);
}
// a² b c as a double-word.
template <class W>
Double<W> square_times(const W& a, const W& b, const W& c) {
  return times(times(two_product(a, a), b), c);
}

template <class W>
struct Jacobi {
  W sn, cn, dn;
};

// sn, cn, dn of u for the modulus k and complementary modulus kc = √(1 − k²) (both given: kc = √m_c keeps
// m_c's accuracy near the separatrix), by the descending Landen (Gauss)
// transformation (DLMF §22.7(i); A&S 16.12): with k₁ = (1 − κ')/(1 + κ') and v = u/(1 + k₁),
//   sn(u, κ) = (1 + k₁) sn(v, k₁)/(1 + k₁ sn²),  cn(u, κ) = cn(v, k₁) dn(v, k₁)/(1 + k₁ sn²),
//   dn(u, κ) = (1 − k₁ sn²)/(1 + k₁ sn²) = ((1 − k₁) + k₁ cn²)/(1 + k₁ sn²),
// applied until k_N² ≤ √ε, where sn, cn, dn = sin, cos, 1 to O(k_N²) with the O(k_N²) terms of A&S 16.13
// added. k_{n+1} = k_n²/(1 + κ'_n)², κ'_{n+1} = 2√κ'_n/(1 + κ'_n) and 1 − k_{n+1} = 2κ'_n/(1 + κ'_n) are
// formed without cancellation, so a tiny mc (near the separatrix) keeps full relative accuracy, and the
// ascent is rational: cn keeps
// an absolute error of a few ε where sn ≈ ±1. (The AGM form with asin((c_n/a_n) sin ϕ_n), Boost's, loses
// accuracy there: asin's argument tends to 1; measured in the tests.)
// sech u = 2e^{−|u|}/(1 + e^{−2|u|}): 1/cosh u overflows cosh for |u| > 11356 (long double; 710 in double) on
// long separatrix runs — an ∞ that the tests' floating-point traps catch; this form underflows to 0 instead.
template <class W>
W sech(const W& u) {
  using std::abs;
  using std::exp;
  const W e = exp(-abs(u));
  return W(2) * e / (W(1) + e * e);
}

template <class W>
Jacobi<W> jacobi(const W& u, const W& k, const W& kc) {
  using std::cos;
  using std::cosh;
  using std::sin;
  using std::sqrt;
  using std::tanh;
  if (!(kc > 0)) return {tanh(u), sech(u), sech(u)};  // κ = 1
  constexpr int max_levels = 16;
  W r[max_levels], one_minus_r[max_levels];  // k_{n+1}, 1 − k_{n+1}
  const W small = sqrt(std::numeric_limits<W>::epsilon());
  W kn = k, kcn = kc, v = u;
  int N = 0;
  while (N < max_levels && kn * kn > small) {
    const W opk = 1 + kcn;
    r[N] = kn * kn / (opk * opk);  // k_{n+1} = (1 − κ'_n)/(1 + κ'_n) = k_n²/(1 + κ'_n)²
    one_minus_r[N] = 2 * kcn / opk;
    v /= 1 + r[N];
    kn = r[N];
    kcn = 2 * sqrt(kcn) / opk;
    ++N;
  }
  // The last level, modulus² m = k_N² ≤ √ε: A&S 16.13.1–16.13.3 (error O(m²)).
  const W m = kn * kn;
  const W sv = sin(v), cv = cos(v), w = (m / 4) * (v - sv * cv);
  W sn = sv - w * cv, cn = cv + w * sv, dn = 1 - (m / 2) * sv * sv;
  for (int i = N - 1; i >= 0; --i) {
    const W denom = 1 + r[i] * sn * sn;
    const W s1 = (1 + r[i]) * sn / denom, c1 = cn * dn / denom, d1 = (one_minus_r[i] + r[i] * cn * cn) / denom;
    sn = s1;
    cn = c1;
    dn = d1;
  }
  return {sn, cn, dn};
}

// Π(n; ϕ, κ) for |ϕ| ≤ π/2 from s = sin ϕ, c = cos ϕ ≥ 0, d² = c² + mc s² (DLMF 19.25(i) with the Carlson
// integrals' homogeneity): s RF(c², d², 1) + (n/3) s³ RJ(c², d², 1, 1 − n s²). Also returns F(ϕ, κ), the
// first term.
template <class W>
void legendre_f_pi(const W& s, const W& c, const W& d2, const W& n, W& F, W& Pi) {
  const W c2 = c * c;
  const CarlsonFJ<W> r = carlson_f_j(c2, d2, W(1), W(1) - n * s * s);
  F = s * r.RF;
  Pi = F + (n / 3) * s * s * s * r.RJ;
}

}  // namespace free_body_exact_detail

/// The exact free rigid body of inertia J (this header): T the scalar of states (floating point; no Jets), W the
/// working precision (at least T's). Immutable after construction: solve and flow may be called from several
/// threads at once. Each evaluation costs O(1) in t: a few Jacobi elliptic functions and elliptic integrals.
template <class T = double, class W = long double>
class FreeBodyExact {
  static_assert(std::is_floating_point_v<T> && std::numeric_limits<W>::is_specialized && !std::numeric_limits<W>::is_integer,
                "FreeBodyExact: floating-point scalars only (no ceres::Jet)");
  static_assert(std::numeric_limits<W>::digits >= std::numeric_limits<T>::digits, "FreeBodyExact: W narrower than T");

 public:
  /// The kind of motion, fixed by the initial momentum (this header's cases).
  enum class Regime {
    rest,        ///< m = 0
    steady,      ///< m along a principal axis: uniform rotation
    symmetric,   ///< two (or three) equal principal moments: trigonometric solution
    axis1,       ///< Δ2 < 0, [CFSZ] case (i): m circles the axis of the smallest moment
    axis3,       ///< Δ2 > 0, [CFSZ] case (ii): m circles the axis of the largest moment
    separatrix,  ///< Δ2 = 0, [CFSZ] case (iii)
  };

  /// The motion from one initial state at t = 0; state(t) at any t (also negative), O(1) cost in t.
  class Solution {
   public:
    /// (R, Ω) at time t (any sign), evaluated in W and rounded to T once.
    State<T> state(const T& t) const {
      Mat3<W> Rp;
      Vec3<W> m;
      evaluate(W(t), Rp, m);
      const Vec3<W> Omega = Q_ * Vec3<W>(m.cwiseQuotient(I_));
      return {Mat3<W>(Rp * Q_.transpose()).template cast<T>(), Omega.template cast<T>()};
    }
    /// (R, Π = JΩ) at time t (any sign), evaluated in W and rounded to T once.
    MomentumState<T> momentum_state(const T& t) const {
      Mat3<W> Rp;
      Vec3<W> m;
      evaluate(W(t), Rp, m);
      return {Mat3<W>(Rp * Q_.transpose()).template cast<T>(), Vec3<W>(Q_ * m).template cast<T>()};
    }
    /// The principal-axis body momentum at t (internal precision), for tests and diagnostics.
    Vec3<W> principal_momentum(const W& t) const {
      Mat3<W> Rp;
      Vec3<W> m;
      evaluate(t, Rp, m);
      return m;
    }

    /// Which case of the header the motion is.
    Regime regime() const { return regime_; }
    /// 1 − κ² (elliptic regimes): the distance to the separatrix; 0 on it.
    W parameter_complement() const { return mc_; }
    /// Δ2/G²: signed relative distance to the separatrix (< 0: axis1, > 0: axis3).
    W relative_delta2() const { return delta2_rel_; }
    /// The motion over a short time t as increments, for flows composed many times (a splitting): with
    /// R_p(t) = R_p(0) M(t), returns dM = M(t) − I and dm = m(t) − m(0), both O(t) and formed without their
    /// O(1) parts, so that R + R·(Q dM Qᵀ) and m + dm carry round-off ∝ ε·|t| per call rather than ε, which
    /// would add up to a drift of the invariants over many calls (measured in the tests). Elliptic regimes:
    /// m(t) by the addition theorems (DLMF 22.8.1–22.8.3) from sn, cn, dn of u0 (read off m(0)) and of λt,
    /// with cn v − 1, dn v − 1 and 1 − κ² sn²u sn²v = cn²u + sn²u dn²v written without cancellation; the frame
    /// increment B(m(t)) − B(m(0)) likewise. Other regimes: their closed forms as increments (the separatrix,
    /// of measure zero, by difference). Requires |λt| ≤ 4 in the elliptic regimes (else: state(t)).
    bool increment(const W& t, Mat3<W>& dM, Vec3<W>& dm) const {
      using std::abs;
      using std::atan2;
      using std::floor;
      using std::sin;
      switch (regime_) {
        case Regime::rest:
          dM.setZero();
          dm.setZero();
          return true;
        case Regime::steady: {
          W turns;
          dM = free_body_exact_detail::rotation_increment(axis_, free_body_exact_detail::reduce(W(t * rate_), two_pi(), turns));
          dm.setZero();
          return true;
        }
        case Regime::symmetric: {
          W turns;
          Vec3<W> es = Vec3<W>::Zero();
          es(sym_axis_) = W(1);
          const Mat3<W> D1 =
              free_body_exact_detail::rotation_increment(axis_, free_body_exact_detail::reduce(W(t * rate_), two_pi(), turns));
          const Mat3<W> D2 =
              free_body_exact_detail::rotation_increment(es, free_body_exact_detail::reduce(W(t * spin_), two_pi(), turns));
          dM = D1 + D2 + D1 * D2;
          dm = D2.transpose() * m0_;
          return true;
        }
        case Regime::separatrix: {  // m(t) − m(0) by difference (a set of measure zero)
          Vec3<W> m;
          W phi;
          separatrix_motion(t, m, phi);
          dm = m - m0_;
          dM = frame_increment(dm, phi);
          return true;
        }
        case Regime::axis1:
        case Regime::axis3:
          break;
      }
      const W v = lambda_ * t;
      if (!(abs(v) <= W(4))) return false;
      using free_body_exact_detail::is_odd;
      using free_body_exact_detail::jacobi;
      using free_body_exact_detail::legendre_f_pi;
      const free_body_exact_detail::Jacobi<W> f = jacobi(v, k_, kc_);
      const W k2 = k_ * k_, sv2 = f.sn * f.sn;
      const W cm1 = f.cn >= 0 ? W(-sv2 / (1 + f.cn)) : W(f.cn - 1);  // cn v − 1
      const W dm1 = -k2 * sv2 / (1 + f.dn);                            // dn v − 1
      const W su = sn_u0_, cu = cn_u0_, du = dn_u0_;
      const W q = k2 * su * su * sv2;                                  // 1 − D
      const W D = cu * cu + su * su * f.dn * f.dn;
      const W dsn = (su * ((cm1 * f.dn + dm1) + q) + cu * du * f.sn) / D;
      const W dcn = (cu * (cm1 + q) - su * du * f.sn * f.dn) / D;
      const W ddn = (du * (dm1 + q) - k2 * su * cu * f.sn * f.cn) / D;
      dm(p_) = A_(p_) * dcn;
      dm(1) = A_(1) * dsn;
      dm(a_) = sigma_ * A_(a_) * ddn;
      // am u − am u0: as am' = dn ∈ [κ', 1], Δam lies within |v|(1 − κ')/2 ≤ 2 of v(1 + κ')/2; of the
      // candidates atan2(sn u, cn u) − atan2(sn u0, cn u0) + 2πj exactly one does. Then Π(n; am u) by
      // reduction to [−π/2, π/2].
      const W sn1 = su + dsn, cn1 = cu + dcn;
      const W pi = boost::math::constants::pi<W>();
      const W am1 = am0_ + branch(W(atan2(sn1, cn1) - atan2(su, cu)), v);
      const W j1 = floor(am1 / pi + W(0.5));
      const W sj = is_odd(j1) ? W(-1) : W(1);
      W F, Pi;
      legendre_f_pi(W(sj * sn1), W(sj * cn1), W(cn1 * cn1 + mc_ * sn1 * sn1), n_, F, Pi);
      W dPi = Pi - Pir0_;
      if (j1 != j0_) dPi += 2 * (j1 - j0_) * complete_pi();
      dM = frame_increment(dm, W(rate_ * t + cphi_ * dPi));
      return true;
    }

    /// M − I = B0 E(φ) B1ᵀ − I = (B0 (E − I) − ΔB) B1ᵀ with the frame increment ΔB = B(m0 + dm) − B(m0)
    /// formed from dm without cancellation: Δb3 = dm/G, Δb1 = (e_a × dm)/ρ1 − (e_a × m0) Δρ/(ρ0 ρ1) with
    /// Δρ = (ρ1² − ρ0²)/(ρ0 + ρ1) = dm⊥·(2 m0⊥ + dm⊥)/(ρ0 + ρ1), Δb2 = Δb3 × b1_1 + b3_0 × Δb1.
    Mat3<W> frame_increment(const Vec3<W>& dm, const W& phi_total) const {
      using std::sin;
      using std::sqrt;
      const Vec3<W> m1 = m0_ + dm;
      const int b = a_ == 2 ? 0 : 1, c = a_ == 2 ? 1 : 2;  // the components ⊥ e_a
      const W rho0 = rho0_;
      const W rho1 = sqrt(m1(b) * m1(b) + m1(c) * m1(c));
      const W drho = (dm(b) * (2 * m0_(b) + dm(b)) + dm(c) * (2 * m0_(c) + dm(c))) / (rho0 + rho1);
      const Vec3<W> e_dm = polar_cross(dm), e_m0 = polar_cross(m0_);
      const Vec3<W> db1 = e_dm / rho1 - e_m0 * (drho / (rho0 * rho1));
      const Vec3<W> db3 = dm / G_;
      const Vec3<W> b1_0 = B0_.col(0), b2_0 = B0_.col(1), b3_0 = B0_.col(2);
      const Vec3<W> b1_1 = b1_0 + db1;
      const Vec3<W> db2 = db3.cross(b1_1) + b3_0.cross(db1);
      Mat3<W> B1, X;
      B1 << b1_1, Vec3<W>(b2_0 + db2), Vec3<W>(b3_0 + db3);
      W turns;
      const W phi = free_body_exact_detail::reduce(phi_total, two_pi(), turns);
      const W sp = sin(phi), hs = sin(phi / 2), cm = -2 * hs * hs;  // sin φ, cos φ − 1
      X << Vec3<W>(cm * b1_0 + sp * b2_0 - db1), Vec3<W>(-sp * b1_0 + cm * b2_0 - db2), Vec3<W>(-db3);
      return X * B1.transpose();
    }

    /// Separatrix: m(t) and φ(t).
    void separatrix_motion(const W& t, Vec3<W>& m, W& phi) const {
      using std::atan;
      using std::cosh;
      using std::tanh;
      const W u = u0_ + lambda_ * t;
      const W th = tanh(u), se = free_body_exact_detail::sech(u);
      m(0) = sigma1_ * A_(0) * se;
      m(1) = G_ * th;
      m(2) = sigma3_ * A_(2) * se;
      phi = rate_ * t - cphi_ * beta_ * (atan(beta_ * th) - atan0_);
    }

    /// Computes K(κ) and Π(n | κ) once (elliptic regimes; no effect in the others), so that state(t) and
    /// momentum_state(t) at long times (|λt| > 4), and where am u crosses ±π/2, cost one Landen descent + 1 RF +
    /// 1 RJ and no AGM: for a solution evaluated at many times. The values are those computed otherwise (the
    /// same bits: both come from detail::complete).
    void precompute_periods() {
      if (regime_ != Regime::axis1 && regime_ != Regime::axis3) return;
      const free_body_exact_detail::Complete<W> c = free_body_exact_detail::complete(kc_, n_);
      K_ = c.K;
      Pic_ = c.Pi;
      periods_ = true;
    }

    /// Period of m(t) (elliptic regimes): 4K/|λ|.
    W period() const {
      using std::abs;
      return 4 * complete_k() / abs(lambda_);
    }

   private:
    friend class FreeBodyExact;

    void evaluate(const W& t, Mat3<W>& Rp, Vec3<W>& m) const {
      using std::cos;
      using std::sin;
      switch (regime_) {
        case Regime::rest:
          Rp = Rp0_;
          m = m0_;
          return;
        case Regime::steady: {
          // R_p(0) exp(tΩ): the angle reduced modulo 2π in W.
          W turns;
          const W angle = free_body_exact_detail::reduce(W(t * rate_), two_pi(), turns);
          Rp = Rp0_ * free_body_exact_detail::rotation(axis_, angle);
          m = m0_;
          return;
        }
        case Regime::symmetric: {
          W turns;
          const W a1 = free_body_exact_detail::reduce(W(t * rate_), two_pi(), turns);  // about m(0), rate G/I⊥
          const W a2 = free_body_exact_detail::reduce(W(t * spin_), two_pi(), turns);  // about e_s, rate c
          Vec3<W> es = Vec3<W>::Zero();
          es(sym_axis_) = W(1);
          const Mat3<W> S = free_body_exact_detail::rotation(es, a2);
          Rp = Rp0_ * free_body_exact_detail::rotation(axis_, a1) * S;
          m = S.transpose() * m0_;
          return;
        }
        case Regime::separatrix: {
          W phi;
          separatrix_motion(t, m, phi);
          attitude(phi, m, Rp);
          return;
        }
        case Regime::axis1:
        case Regime::axis3: {
          using std::abs;
          using std::atan2;
          using free_body_exact_detail::is_odd;
          using free_body_exact_detail::jacobi;
          using free_body_exact_detail::legendre_f_pi;
          using free_body_exact_detail::reduce;
          // u = u0 + λt = 2 j0 K + v, v = F(ϕ_r0) + λt. Short times (|λt| ≤ 4, a splitting's sub-step):
          // sn, cn, dn of v directly, and K, Π(n | κ) only if am(v) leaves [−π/2, π/2]. Long times: u
          // reduced modulo 2K first, in W.
          const W lt = lambda_ * t;
          W sn, cn, dn, dPi, F, Pi;  // sn, cn, dn of u; Π(am u) − Π(am u0)
          if (abs(lt) <= W(4)) {
            const free_body_exact_detail::Jacobi<W> f = jacobi(W(F0_ + lt), k_, kc_);
            using std::floor;
            // am v = am(F0 + λt) = ϕ_r0 + Δam, Δam the branch of the atan2 difference within |λt|(1 − κ')/2
            // of λt(1 + κ')/2 (am' = dn ∈ [κ', 1]); then am v = ϕ + j1 π with |ϕ| ≤ π/2.
            const W am = phi_r0_ + branch(W(atan2(f.sn, f.cn) - phi_r0_), lt);
            const W j1 = floor(am / boost::math::constants::pi<W>() + W(0.5));
            const W sj = is_odd(j1) ? W(-1) : W(1);
            legendre_f_pi(W(sj * f.sn), W(sj * f.cn), W(f.dn * f.dn), n_, F, Pi);
            dPi = Pi - Pir0_;
            if (j1 != 0) dPi += 2 * j1 * complete_pi();
            const W s0 = is_odd(j0_) ? W(-1) : W(1);
            sn = s0 * f.sn;
            cn = s0 * f.cn;
            dn = f.dn;
          } else {
            const free_body_exact_detail::Complete<W> c = complete_integrals();
            const W K = c.K, Pic = c.Pi;
            W j;
            const W r = reduce(W(2 * j0_ * K + F0_ + lt), W(2 * K), j);
            const free_body_exact_detail::Jacobi<W> f = jacobi(r, k_, kc_);
            legendre_f_pi(f.sn, f.cn, W(f.dn * f.dn), n_, F, Pi);
            dPi = 2 * (j - j0_) * Pic + Pi - Pir0_;
            const W sj = is_odd(j) ? W(-1) : W(1);
            sn = sj * f.sn;
            cn = sj * f.cn;
            dn = f.dn;
          }
          m(p_) = A_(p_) * cn;
          m(1) = A_(1) * sn;
          m(a_) = sigma_ * A_(a_) * dn;
          attitude(W(rate_ * t + cphi_ * dPi), m, Rp);
          return;
        }
      }
    }

    /// K(κ) and Π(n | κ) by one AGM (detail::complete): only long times and a
    /// crossing of am u = ±π/2 need them, so they are not part of solve() (precompute_periods stores them for
    /// a solution evaluated at many times).
    free_body_exact_detail::Complete<W> complete_integrals() const {
      return periods_ ? free_body_exact_detail::Complete<W>{K_, Pic_} : free_body_exact_detail::complete(kc_, n_);
    }
    W complete_k() const { return complete_integrals().K; }
    W complete_pi() const { return complete_integrals().Pi; }

    /// The increment of the amplitude over Δu = v, |v| ≤ 4, from its value modulo 2π: am' = dn ∈ [κ', 1], so
    /// Δam lies within |v|(1 − κ')/2 ≤ 2 of v(1 + κ')/2, and of the candidates d + 2πj exactly one does.
    W branch(const W& d, const W& v) const {
      using std::floor;
      return d - two_pi() * floor((d - v * (1 + kc_) / 2) / two_pi() + W(0.5));
    }

    /// e_a × v for the polar axis.
    Vec3<W> polar_cross(const Vec3<W>& v) const {
      return a_ == 2 ? Vec3<W>(-v(1), v(0), W(0)) : Vec3<W>(W(0), -v(2), v(1));
    }

    /// B(m) for the polar axis a_: columns b1 = e_a × m/ρ, b2 = b3 × b1, b3 = m/G.
    Mat3<W> frame(const Vec3<W>& m) const {
      using std::sqrt;
      Mat3<W> B;
      if (a_ == 2) {
        const W rho = sqrt(m(0) * m(0) + m(1) * m(1));
        const W gr = G_ * rho;
        B << -m(1) / rho, -m(0) * m(2) / gr, m(0) / G_,  //
            m(0) / rho, -m(1) * m(2) / gr, m(1) / G_,    //
            W(0), rho / G_, m(2) / G_;
      } else {
        const W rho = sqrt(m(1) * m(1) + m(2) * m(2));
        const W gr = G_ * rho;
        B << W(0), rho / G_, m(0) / G_,                //
            -m(2) / rho, -m(0) * m(1) / gr, m(1) / G_,  //
            m(1) / rho, -m(0) * m(2) / gr, m(2) / G_;
      }
      return B;
    }

    void attitude(const W& phi_total, const Vec3<W>& m, Mat3<W>& Rp) const {
      using std::cos;
      using std::sin;
      W turns;
      const W phi = free_body_exact_detail::reduce(phi_total, two_pi(), turns);
      const W c = cos(phi), s = sin(phi);
      Mat3<W> E;
      E << c, -s, W(0), s, c, W(0), W(0), W(0), W(1);
      Rp = RB0_ * E * frame(m).transpose();
    }

    static W two_pi() { return 2 * boost::math::constants::pi<W>(); }

    Regime regime_ = Regime::rest;
    Mat3<W> Q_;       ///< body = Q · principal
    Vec3<W> I_;       ///< principal moments
    Mat3<W> Rp0_;     ///< R(0) Q
    Mat3<W> RB0_;     ///< R_p(0) B(m(0))
    Mat3<W> B0_;      ///< B(m(0))
    Vec3<W> m0_;      ///< principal body momentum at t = 0
    Vec3<W> axis_ = Vec3<W>::Zero();  ///< steady/symmetric: unit rotation axis (body, principal frame)
    Vec3<W> A_ = Vec3<W>::Zero();     ///< amplitudes A1, A2, A3
    W G_ = 0, rate_ = 0, spin_ = 0, lambda_ = 0, u0_ = 0, k_ = 0, kc_ = 0, mc_ = 0, n_ = 0, F0_ = 0, Pir0_ = 0,
      j0_ = 0, K_ = 0, Pic_ = 0, am0_ = 0, phi_r0_ = 0, sn_u0_ = 0, cn_u0_ = 0, dn_u0_ = 0, rho0_ = 0, cphi_ = 0, sigma_ = 1, sigma1_ = 1, sigma3_ = 1, beta_ = 0, atan0_ = 0, delta2_rel_ = 0;
    int a_ = 2, p_ = 0, sym_axis_ = 2;
    bool periods_ = false;  ///< K_, Pic_ hold K(κ), Π(n | κ) (precompute_periods)
  };

  /// Diagonalises J once (in W). Throws std::invalid_argument unless J is finite, symmetric to 1e-12 and
  /// positive definite.
  explicit FreeBodyExact(const Mat3<T>& inertia) : J_(inertia.template cast<W>()) {
    using std::abs;
    if (!J_.allFinite()) throw std::invalid_argument("FreeBodyExact: inertia is not finite");
    const W scale = J_.cwiseAbs().maxCoeff();
    if ((J_ - J_.transpose()).cwiseAbs().maxCoeff() > W(1e-12) * scale)
      throw std::invalid_argument("FreeBodyExact: inertia is not symmetric");
    J_ = (W(0.5) * (J_ + J_.transpose())).eval();
    diagonal_ = J_(0, 1) == 0 && J_(0, 2) == 0 && J_(1, 2) == 0;
    if (diagonal_) {
      // Q a signed permutation (exact): columns e_{p(i)} sorted by moment, last column negated if odd.
      std::array<int, 3> p{0, 1, 2};
      for (int i = 0; i < 3; ++i)
        for (int j = i + 1; j < 3; ++j)
          if (J_(p[j], p[j]) < J_(p[i], p[i])) std::swap(p[i], p[j]);
      Q_.setZero();
      for (int i = 0; i < 3; ++i) {
        Q_(p[i], i) = W(1);
        I_(i) = J_(p[i], p[i]);
      }
      if (Q_.determinant() < 0) Q_.col(2) = -Q_.col(2);
    } else {
      // Eigen's solver in W when W is a built-in type; in long double for a multiprecision W (Eigen's
      // solver needs NumTraits that Boost.Multiprecision 1.74 does not complete).
      using E = std::conditional_t<std::is_floating_point_v<W>, W, long double>;
      const Eigen::SelfAdjointEigenSolver<Mat3<E>> eig(Mat3<E>(J_.template cast<E>()));
      I_ = eig.eigenvalues().template cast<W>();
      Q_ = eig.eigenvectors().template cast<W>();
      if (Q_.determinant() < 0) Q_.col(2) = -Q_.col(2);
    }
    if (!(I_(0) > 0) || !(I_(2) < std::numeric_limits<W>::max())) throw std::invalid_argument("FreeBodyExact: inertia is not positive definite");
    const W tol = 8 * W(std::numeric_limits<T>::epsilon()) * I_(2);
    equal12_ = I_(1) - I_(0) <= tol;
    equal23_ = I_(2) - I_(1) <= tol;
    if (equal12_ && equal23_) {
      I_.setConstant(I_.sum() / 3);
    } else if (equal12_) {
      I_(0) = I_(1) = (I_(0) + I_(1)) / 2;
    } else if (equal23_) {
      I_(1) = I_(2) = (I_(1) + I_(2)) / 2;
    }
  }

  /// I1 ≤ I2 ≤ I3 (equal to within 8 ε(T) I3 are made exactly equal).
  const Vec3<W>& principal_moments() const { return I_; }
  /// Q, a rotation with J = Q diag(I) Qᵀ (a signed permutation when J is diagonal).
  const Mat3<W>& principal_axes() const { return Q_; }

  /// The motion from x0 at t = 0 (R a rotation, Ω any finite vector). Non-finite input gives a Solution whose
  /// states are not finite; nothing throws.
  Solution solve(const State<T>& x0) const {
    const Vec3<W> Omega = x0.Omega.template cast<W>();
    if (diagonal_) {  // Ω in principal axes is exact (a signed permutation): Δ2 from Ω, see solve_principal
      const Vec3<W> Omega_p = Q_.transpose() * Omega;
      return solve_principal(x0.R.template cast<W>(), Vec3<W>(I_.cwiseProduct(Omega_p)), &Omega_p);
    }
    return solve_principal(x0.R.template cast<W>(), Vec3<W>(Q_.transpose() * (J_ * Omega)), nullptr);
  }
  /// The motion from (R, Π) at t = 0, as solve(State).
  Solution solve(const MomentumState<T>& y0) const {
    return solve_principal(y0.R.template cast<W>(), Vec3<W>(Q_.transpose() * y0.Pi.template cast<W>()), nullptr);
  }

  /// The exact flow over h: the free-body sub-flow of a splitting. Constants are recomputed from x (a
  /// kick changes them).
  /// As increments (Solution::increment): R + R (Q dM Qᵀ), Ω + Q (dm/I) or Π + Q dm, for |λh| ≤ 4; longer
  /// steps by direct evaluation.
  State<T> flow(const State<T>& x, const T& h) const {
    const Solution s = solve(x);
    Mat3<W> dM;
    Vec3<W> dm;
    if (!s.increment(W(h), dM, dm)) return s.state(h);
    const Mat3<W> R = x.R.template cast<W>();
    return {Mat3<W>(R + R * (Q_ * dM * Q_.transpose())).template cast<T>(),
            Vec3<W>(x.Omega.template cast<W>() + Q_ * dm.cwiseQuotient(I_)).template cast<T>()};
  }
  /// The exact flow over h of the momentum form (R, Π), as flow(State).
  MomentumState<T> flow(const MomentumState<T>& y, const T& h) const {
    const Solution s = solve(y);
    Mat3<W> dM;
    Vec3<W> dm;
    if (!s.increment(W(h), dM, dm)) return s.momentum_state(h);
    const Mat3<W> R = y.R.template cast<W>();
    return {Mat3<W>(R + R * (Q_ * dM * Q_.transpose())).template cast<T>(),
            Vec3<W>(y.Pi.template cast<W>() + Q_ * dm).template cast<T>()};
  }

 private:
  /// m: principal body momentum; Omega_p: the principal angular velocity when it is exact (diagonal J,
  /// State input), for Δ2 without the rounding of m = IΩ.
  Solution solve_principal(const Mat3<W>& R0, const Vec3<W>& m, const Vec3<W>* Omega_p) const {
    using std::abs;
    using std::asinh;
    using std::atan;
    using std::sqrt;
    using std::tanh;
    using free_body_exact_detail::legendre_f_pi;
    Solution s;
    s.Q_ = Q_;
    s.I_ = I_;
    s.Rp0_ = R0 * Q_;
    s.m0_ = m;
    const W I1 = I_(0), I2 = I_(1), I3 = I_(2);
    const W m1 = m(0), m2 = m(1), m3 = m(2);
    const W G2 = m.squaredNorm();
    s.G_ = sqrt(G2);
    if (!(G2 > 0)) {  // rest (or non-finite input: the NaN propagates through evaluate)
      s.regime_ = G2 == 0 ? Regime::rest : Regime::steady;
      s.axis_ = m;
      return s;
    }
    const int zeros = (m1 == 0) + (m2 == 0) + (m3 == 0);
    if (zeros == 2) {
      s.regime_ = Regime::steady;
      const Vec3<W> Omega = m.cwiseQuotient(I_);
      s.rate_ = Omega.norm();
      s.axis_ = Omega / s.rate_;
      return s;
    }
    if (equal12_ || equal23_) {
      // I_s ≠ I⊥ (or a sphere): R_p(t) = R_p(0) exp(t hat(m0)/I⊥) exp(t c ê_s), m(t) = exp(−t c ê_s) m0.
      s.regime_ = Regime::symmetric;
      s.sym_axis_ = equal12_ ? 2 : 0;
      const W Iperp = I_(equal12_ ? 0 : 2);
      const W Is = I_(s.sym_axis_);
      s.rate_ = s.G_ / Iperp;
      s.axis_ = m / s.G_;
      s.spin_ = (W(1) / Is - W(1) / Iperp) * m(s.sym_axis_);
      return s;
    }
    const W I21 = I2 - I1, I31 = I3 - I1, I32 = I3 - I2;
    const W D1 = (m2 * m2 * I21 * I3 + m3 * m3 * I31 * I2) / (I2 * I3);   // Δ1 ≥ 0
    const W D3n = (m1 * m1 * I31 * I2 + m2 * m2 * I32 * I1) / (I1 * I2);  // −Δ3 ≥ 0
    // Δ2 = (m3² I1 (I3 − I2) − m1² I3 (I2 − I1))/(I1 I3) cancels near the separatrix: its numerator is
    // summed from the four products m3² I1 I3 − m3² I1 I2 − m1² I3 I2 + m1² I3 I1 in twice W's precision
    // (or, from an exact Ω, Δ2 = Ω3² I3 I3 − Ω3² I3 I2 − Ω1² I1 I2 + Ω1² I1 I1), so that m_c ∝ Δ2 keeps W's
    // relative accuracy however close the data are to the separatrix — for a diagonal J; otherwise the
    // principal moments and m carry W's rounding from the eigensolver.
    using free_body_exact_detail::plus;
    using free_body_exact_detail::square_times;
    W D2;  // Δ2
    const W eps2 = std::numeric_limits<W>::epsilon() * std::numeric_limits<W>::epsilon();
    if (Omega_p) {
      const W w1 = (*Omega_p)(0), w3 = (*Omega_p)(2);
      const free_body_exact_detail::Double<W> d = plus(plus(square_times(w3, I3, I3), square_times(w3, I3, W(-I2))),
                                                       plus(square_times(w1, I1, W(-I2)), square_times(w1, I1, I1)));
      D2 = d.hi + d.lo;
      // Within the double-word sum's own rounding (≈ ε_W² of the terms) of zero: on the separatrix.
      if (abs(D2) <= 16 * eps2 * (w3 * w3 * I3 * (I3 + I2) + w1 * w1 * I1 * (I2 + I1))) D2 = 0;
    } else {
      const free_body_exact_detail::Double<W> num = plus(plus(square_times(m3, I1, I3), square_times(m3, I1, W(-I2))),
                                                         plus(square_times(m1, I3, W(-I2)), square_times(m1, I3, I1)));
      D2 = num.hi + num.lo;
      if (abs(D2) <= 16 * eps2 * (m3 * m3 * I1 * (I3 + I2) + m1 * m1 * I3 * (I2 + I1))) D2 = 0;
      D2 /= I1 * I3;
    }
    s.delta2_rel_ = D2 / G2;
    s.A_(0) = sqrt(D3n * I1 / I31);
    s.A_(2) = sqrt(D1 * I3 / I31);
    const W twoT = m1 * m1 / I1 + m2 * m2 / I2 + m3 * m3 / I3;
    if (D2 == 0) {
      s.regime_ = Regime::separatrix;
      s.A_(1) = s.G_;
      s.sigma1_ = m1 < 0 ? W(-1) : W(1);
      s.sigma3_ = m3 < 0 ? W(-1) : W(1);
      s.lambda_ = s.sigma1_ * s.sigma3_ * s.A_(0) * s.A_(2) * I31 / (s.G_ * I1 * I3);
      s.u0_ = asinh(m2 / sqrt(m1 * m1 + m3 * m3));
      s.a_ = s.A_(0) <= s.A_(2) ? 0 : 2;
      s.p_ = 2 - s.a_;
      const W Da = s.a_ == 0 ? D1 : -D3n;
      s.beta_ = s.A_(s.a_) / s.A_(s.p_);
      s.rate_ = twoT / s.G_;
      s.cphi_ = Da / (I_(s.a_) * s.lambda_ * s.G_);
      s.atan0_ = atan(s.beta_ * tanh(s.u0_));
      s.B0_ = s.frame(m);
      s.RB0_ = s.Rp0_ * s.B0_;
      s.rho0_ = s.a_ == 2 ? W(sqrt(m1 * m1 + m2 * m2)) : W(sqrt(m2 * m2 + m3 * m3));
      return s;
    }
    W Dk;  // the denominator of κ² and m_c
    if (D2 > 0) {  // case (ii): about the axis of I3
      s.regime_ = Regime::axis3;
      s.a_ = 2;
      s.p_ = 0;
      s.A_(1) = sqrt(D3n * I2 / I32);
      s.sigma_ = m3 < 0 ? W(-1) : W(1);
      s.lambda_ = s.sigma_ * sqrt(D1 * I32 / (I1 * I2 * I3));
      Dk = D1 * I32;
      s.k_ = sqrt(D3n * I21 / Dk);
      s.n_ = -I3 * I21 / (I1 * I32);
      s.rate_ = s.G_ / I3;
      s.cphi_ = s.G_ * I31 / (I1 * I3 * s.lambda_);
    } else {  // case (i): about the axis of I1
      s.regime_ = Regime::axis1;
      s.a_ = 0;
      s.p_ = 2;
      s.A_(1) = sqrt(D1 * I2 / I21);
      s.sigma_ = m1 < 0 ? W(-1) : W(1);
      s.lambda_ = s.sigma_ * sqrt(D3n * I21 / (I1 * I2 * I3));
      Dk = D3n * I21;
      s.k_ = sqrt(D1 * I32 / Dk);
      s.n_ = -I1 * I32 / (I3 * I21);
      s.rate_ = s.G_ / I1;
      s.cphi_ = -s.G_ * I31 / (I1 * I3 * s.lambda_);
    }
    s.mc_ = abs(D2) * I31 / Dk;
    s.kc_ = sqrt(s.mc_);
    // am(u0) = atan2(sn0, cn0) ∈ (−π, π]; reduce to ϕ_r0 ∈ [−π/2, π/2] with am u0 = ϕ_r0 + j0 π, so that
    // u0 = 2 j0 K + F(ϕ_r0) and Π(n; am u0) = 2 j0 Π(n | κ) + Π(n; ϕ_r0).
    W sn0 = m2 * s.A_(s.p_), cn0 = m(s.p_) * s.A_(1);  // ∝ (m2/A2, m_p/A_p)
    const W norm = sqrt(sn0 * sn0 + cn0 * cn0);
    sn0 /= norm;
    cn0 /= norm;
    s.sn_u0_ = sn0;
    s.cn_u0_ = cn0;
    s.dn_u0_ = sqrt(cn0 * cn0 + s.mc_ * sn0 * sn0);
    {
      using std::atan2;
      s.am0_ = atan2(sn0, cn0);
    }
    W j0 = 0;
    if (cn0 < 0) {
      j0 = sn0 < 0 ? W(-1) : W(1);
      sn0 = -sn0;
      cn0 = -cn0;
    }
    legendre_f_pi(sn0, cn0, W(cn0 * cn0 + s.mc_ * sn0 * sn0), s.n_, s.F0_, s.Pir0_);
    {
      using std::atan2;
      s.phi_r0_ = atan2(sn0, cn0);
    }
    s.j0_ = j0;
    s.B0_ = s.frame(m);
    s.RB0_ = s.Rp0_ * s.B0_;
    s.rho0_ = s.a_ == 2 ? W(sqrt(m1 * m1 + m2 * m2)) : W(sqrt(m2 * m2 + m3 * m3));
    return s;
  }

  Mat3<W> J_;
  Mat3<W> Q_;
  Vec3<W> I_;
  bool diagonal_ = false, equal12_ = false, equal23_ = false;
};

}  // namespace lgi
