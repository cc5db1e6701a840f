/// \file
/// lgi/integrators/free_body_flows.hpp — approximate and exact-in-pieces flows of the free rigid body in
/// principal axes, the building blocks of the heavy-top splittings (splitting.hpp).
///
/// Setting. Principal axes: J = Q diag(I) Qᵀ (Q a rotation, I the principal moments), body momentum
/// Π = Qᵀ J Ω and attitude R_p = R Q, stored as a unit quaternion q (R_p = R(q)). Free-body flow of
/// H = ½ Σ Π_i²/I_i:  Π' = Π × Ω,  R_p' = R_p hat(Ω),  Ω_i = Π_i/I_i. Every flow below maps (q, Π) to
/// (q ⊗ p, R(p)ᵀ Π) for some unit quaternion p: the spatial momentum m = R_p Π is kept to round-off by
/// construction, |Π| too, and R stays on SO(3) (q is renormalised each step — (a) without a square root,
/// q ← q (3 − |q|²)/2, (b, c) by the 1/√(|q|² α) that normalises the DMV rotation anyway — so |q| − 1
/// stays at round-off instead of random-walking).
///
/// (a) AxisRotations — splitting of H into the three exactly solvable H_i = Π_i²/(2I_i) (McLachlan,
///     Phys. Rev. Lett. 71 (1993) 3043; Touma & Wisdom, Astron. J. 107 (1994) 1189; Reich, Physica D 76
///     (1994) 375; Dullweber, Leimkuhler & McLachlan, J. Chem. Phys. 107 (1997) 5840). The flow of H_i
///     for a time τ rotates about e_i by θ = τ Π_i/I_i:  q ← q ⊗ (cos θ/2, sin θ/2 e_i),  (Π_j, Π_k) ←
///     rotation by −θ. Composed symmetrically, a(h/2) b(h/2) c(h) b(h/2) a(h/2): order 2, symmetric,
///     symplectic (a composition of exact Hamiltonian flows); |Π| and m exact to round-off, H with a
///     bounded O(h²) error. The size of that error depends on the order (a, b, c) by orders of
///     magnitude (Fassò, J. Comput. Phys. 189 (2003) 527, "Comparison of splitting algorithms for the rigid
///     body": its abstract, which we read, says the comparison rests on the dominant term of the modified
///     Hamiltonian, that the energy errors of the algorithms differ by several orders of magnitude, and that
///     for the flat body I ∝ (1, 0.75, 0.25) one of them is of order four; HLW 2nd ed. §VII.5.3 cites it for
///     this comparison. The paper's text was not available, so its selection rule is not quoted here). The
///     default order is chosen by measurement over all six orders (tests/integrators/test_splitting.cpp): smallest
///     moment outermost, intermediate in the middle, largest innermost with the full step — the order
///     that is of fourth order for Fassò's flat body I ∝ (1, 0.75, 0.25), see axis_order_for().
///     Overridable by the scene key "axis_order" (StepperOptions::axis_order, [outer, middle, inner]):
///     axis i is the body axis e_i when J is diagonal, else the principal axis of the i-th smallest moment.
///
/// (b) Dmv — the discrete Moser–Veselov algorithm (Moser & Veselov, Comm. Math. Phys. 139 (1991) 217),
///     equivalently RATTLE for the free body (Hairer, Lubich & Wanner, Geometric Numerical Integration,
///     2nd ed. 2006, §VII.5.3): with the quaternion p = (1, c)/√α, α = 1 + |c|², the step solves
///       c_i = α w_i + ((I_j − I_k)/I_i) c_j c_k,   w_i = h Π_i/(2 I_i),   (i, j, k) cyclic
///     (HLW eq. (VII.5.27) in Hairer's fast 3-variable form; the same equation the LGVI solves in the
///     body frame, lgvi.hpp: G(c) = Jc + c × Jc − ½ α hΠ = 0), then q ← q ⊗ p, Π ← R(p)ᵀ Π (written
///     Π + (2/α)(c × (c × Π) − c × Π), so m = R Π is kept for any c, converged or not, to the rounding of
///     α; dmv_solve says which α). The fixed point
///     (Gauss–Seidel sweeps from a one-sweep predictor; the number before the first convergence test
///     predicted from |w|, DmvSweepTable) contracts by ≈ |c|·max|I_j − I_k|/I_i per sweep and runs until
///     c is exact to round-off, proven by a bound on the contraction (4 sweeps at h|Ω| = 0.03; a solve
///     stopped at a relative tolerance makes step(h) and step(−h) inverse only to that tolerance, see
///     dmv_solve); where it stalls (worse than ¼ per sweep) or the bound cannot hold (|w| > ≈ 0.1, i.e.
///     h|Ω| > ≈ 0.2) Newton on G takes over (dmv_newton_update, Cramer's rule; the same equation and
///     Jacobian as the LGVI's, written for principal axes). Order 2, symmetric,
///     symplectic; for a steady rotation about a principal axis it advances asin(h|Ω|) instead of h|Ω|
///     (McLachlan & Zanna, Found. Comput. Math. 5 (2005) 87). The equation has no solution once h|Π|
///     exceeds about max I (on a principal axis: h|Ω| > 1); the flow then takes ⌈h|Π|/min I⌉ substeps
///     (dmv_substeps), so it stays finite and bounded at any step (h|Ω| = 3: tests/integrators/test_dmv.cpp; there the
///     substeps are what keep it finite — the plain fixed point converges at the substep size too, Newton
///     only in fewer iterations).
///     Cost: the fixed-point solve is the largest part of a kick + DMV step; fewer sweeps would need a cheap
///     predictor of the solution, which none gives (dmv_solve), or weaker guarantees.
///
/// (c) `PreprocessedDmv<r>` — Hairer & Vilmart, J. Phys. A 39 (2006) 13225: DMV applied with modified
///     inverse moments 1/Ĩ_i = σ/I_i + δ, where σ = 1 + Σ_k s_k(η, χ), δ = Σ_k d_k(η, χ) are polynomials
///     in η = ½h²|Π|² and χ = h² H (H = ½ Σ Π_i²/I_i) with coefficients that are rational functions of
///     the moments, has order 2r on the free body (r = 2, 3, 4, 5: orders 4, 6, 8, 10) for a few dozen
///     flops more per step. The coefficients (hv_coefficients below, degrees 1–4 in (η, χ)) are those of
///     the authors' published Fortran code DMV10.f (version of 29 Aug 2006, corrected 28 Dec 2007); we
///     could not read the paper itself, so we cite no equation number for them. They are checked here by
///     the measured orders 4, 6, 8, 10 on the free body (tests/integrators/test_dmv.cpp, in long double against a
///     long-double reference). DMV preserves |Π| and H exactly, so Ĩ is the same computed from the start
///     or the end of the step: the method stays symmetric. It is not claimed symplectic: Ĩ depends on the
///     state through H and |Π|, and whether the paper proves the map symplectic could not be checked (the
///     paper's text, and its preprint unige.ch/~hairer/preprints/predmv.pdf named in the code's header,
///     were not available to us; the header of the authors' DMV10.f, which we read, describes the method
///     and its Strang splitting with a potential but says nothing on symplecticity), so the trait stays
///     false. m and |Π| are kept to round-off.
///
/// Non-diagonal J: PrincipalAxes diagonalises it once. For double it is Eigen's symmetric eigensolver;
/// for ceres::Jet the value part is diagonalised in double and the derivative parts follow by first-order
/// perturbation theory (dI_i = (Qᵀ dJ Q)_ii, dQ = Q K with K_ij = (Qᵀ dJ Q)_ij/(I_j − I_i)), exact for
/// first derivatives when the principal moments are distinct (a derivative that splits two equal moments
/// is not representable by a smooth Q and is dropped: see PrincipalAxes).
#pragma once

#include "../core/state_io.hpp"
#include "../core/inertia.hpp"
#include "../core/integrator.hpp"
#include "../core/scalar.hpp"
#include "../core/so3.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>

namespace lgi {

/// A quaternion (w, v) representing R(q) = I + (2/|q|²)(w hat(v) + hat(v)²); unit to round-off in use.
template <class T>
struct Quaternion {
  T w = T(1);                   ///< the scalar part
  Vec3<T> v = Vec3<T>::Zero();  ///< the vector part
  LGI_NUMBERS(w, v)
};

/// Quaternion helpers of the free-body flows and the splittings.
namespace quat {

/// R(q), orthogonal to round-off for any q ≠ 0 (the 2/|q|² scaling absorbs |q| ≠ 1).
template <class T>
Mat3<T> to_matrix(const Quaternion<T>& q) {
  const T s = T(2) / (q.w * q.w + q.v.squaredNorm());
  Mat3<T> R = so3::rodrigues(q.v, T(s * q.w), s);
  return R;
}

/// The unit quaternion with R(q) = R (R a rotation), w ≥ 0 (Shepperd's choice of the largest pivot, so
/// no square root of a small or negative number — also for Jets).
template <class T>
Quaternion<T> from_matrix(const Mat3<T>& R) {
  using std::sqrt;
  const T tr = R.trace();
  Quaternion<T> q;
  int k = -1;  // −1: trace pivot
  auto big = value_of(tr);
  for (int i = 0; i < 3; ++i)
    if (value_of(R(i, i)) > big) {
      big = value_of(R(i, i));
      k = i;
    }
  if (k < 0) {
    const T s = sqrt(T(1) + tr) * T(2);  // 4w
    q.w = T(0.25) * s;
    q.v = Vec3<T>(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1)) / s;
  } else {
    const int i = k, j = (k + 1) % 3, l = (k + 2) % 3;
    const T s = sqrt(T(1) + R(i, i) - R(j, j) - R(l, l)) * T(2);  // 4 v_i
    q.v(i) = T(0.25) * s;
    q.v(j) = (R(j, i) + R(i, j)) / s;
    q.v(l) = (R(l, i) + R(i, l)) / s;
    q.w = (R(l, j) - R(j, l)) / s;
    if (value_of(q.w) < 0) {
      q.w = -q.w;
      q.v = -q.v;
    }
  }
  return q;
}

/// A rotation A with A a = |a| e3 (norm returns |a|): A = 1 exactly when a = |a| e3. For a₃ ≥ 0 the
/// rotation about a × e3 (Rodrigues with sin θ = |n|, cos θ = â₃: A = 1 + hat(n) + hat(n)²/(1 + â₃),
/// n = â × e3); for a₃ < 0 that rotation after the half turn diag(1, −1, −1), so 1 + â₃ is never small.
/// Smooth in a (Jets: derivatives follow) away from a₃ = 0, where both branches are rotations and the
/// choice only changes the internal frame. a = 0: A = 1, norm 0.
template <class T>
Mat3<T> rotation_to_e3(const Vec3<T>& a, T& norm) {
  using std::sqrt;
  norm = sqrt(a.squaredNorm());
  if (!(value_of(norm) > 0)) {
    norm = T(0);
    return Mat3<T>::Identity();
  }
  const bool flip = value_of(a(2)) < 0;
  const Vec3<T> u = flip ? Vec3<T>(a(0) / norm, -a(1) / norm, -a(2) / norm) : Vec3<T>(a / norm);
  const Vec3<T> n(u(1), -u(0), T(0));  // u × e3
  const Mat3<T> N = so3::hat(n);
  Mat3<T> A = Mat3<T>::Identity() + N + (N * N) / (T(1) + u(2));
  if (flip) {  // A · diag(1, −1, −1)
    A.col(1) = -A.col(1);
    A.col(2) = -A.col(2);
  }
  return A;
}

/// q ← q (3 − |q|²)/2: one Newton step towards |q| = 1 (no square root), written as an increment.
template <class T>
void renormalise(Quaternion<T>& q) {
  const T e = T(0.5) * (T(1) - (q.w * q.w + q.v(0) * q.v(0) + q.v(1) * q.v(1) + q.v(2) * q.v(2)));
  q.w += e * q.w;
  q.v(0) += e * q.v(0);
  q.v(1) += e * q.v(1);
  q.v(2) += e * q.v(2);
}

// q ← q ⊗ (1, c)/√(|q|² α), the DMV rotation (1, c)/√α with α = 1 + |c|² given (dmv_apply). |q ⊗ (1, c)|²
// = |q|² α exactly, so dividing by √(|q|² α) instead of √α also takes out the rounding of |q| left by earlier
// steps: |q| − 1 stays at round-off instead of random-walking, with no separate renormalisation (the scalar
// factor changes only |q|, never the rotation R(q)). Written as an increment, q + (g q + q ⊗ (0, s c)) with
// s = 1/√(|q|² α) = 1 + g, so each component is rounded once: the shorter s·(q + δ) rounds twice and makes
// the m·k random walk larger (docs/findings.md).
// The four components are formed alike, lane by lane, (g q_i + ((s x) a_i + (s y) b_i + (s z) c_i)) with
// (a, b, c) signed permutations of q, so that for double GCC's vector extensions can compute them two at a
// time (SSE2 at the baseline, no FMA): the same operations in the same order, bit for bit the scalar
// result (tests/integrators/test_dmv.cpp), in fewer instructions than the scalar code (docs/performance.md,
// "Design measurements behind the code").
namespace detail {
template <class T>
void multiply_increment_scalar(Quaternion<T>& q, const T& x, const T& y, const T& z, const T& a) {
  using std::sqrt;
  const T w = q.w, v0 = q.v(0), v1 = q.v(1), v2 = q.v(2);
  const T s = T(1) / sqrt(((w * w + v1 * v1) + (v0 * v0 + v2 * v2)) * a);
  const T g = s - T(1);  // exact for s in [½, 2]; the rounding of s scales q, it never turns it
  const T xs = s * x, ys = s * y, zs = s * z;
  q.w = w + (g * w + ((-(v0 * xs) - v1 * ys) - v2 * zs));
  q.v(0) = v0 + (g * v0 + ((w * xs - v2 * ys) + v1 * zs));
  q.v(1) = v1 + (g * v1 + ((v2 * xs + w * ys) - v0 * zs));
  q.v(2) = v2 + (g * v2 + ((v0 * ys - v1 * xs) + w * zs));
}
#if defined(__GNUC__) && !defined(__clang__)
inline void multiply_increment_vector(Quaternion<double>& q, double x, double y, double z, double a) {
  using v2d = double __attribute__((vector_size(16)));
  using v2i = long long __attribute__((vector_size(16)));
  static_assert(sizeof(Quaternion<double>) == 4 * sizeof(double) && alignof(Vec3<double>) == alignof(double),
                "Quaternion<double>: w, v(0), v(1), v(2) contiguous");
  v2d A, B;  // (w, v0), (v1, v2)
  __builtin_memcpy(&A, &q.w, sizeof A);
  __builtin_memcpy(&B, &q.v(1), sizeof B);
  const v2d AA = A * A + B * B;                        // (w² + v1², v0² + v2²)
  const double s = 1 / std::sqrt((AA[0] + AA[1]) * a);
  const double g = s - 1;
  const v2d X = {s * x, s * x}, Y = {s * y, s * y}, Z = {s * z, s * z}, G = {g, g};
  const v2d As = __builtin_shuffle(A, v2i{1, 0}), Bs = __builtin_shuffle(B, v2i{1, 0});  // (v0, w), (v2, v1)
  const v2d col0A = As * v2d{-1.0, 1.0}, col0B = Bs * v2d{1.0, -1.0};                   // (−v0, w), (v2, −v1)
  const v2d col2A = Bs * v2d{-1.0, 1.0};                                                 // (−v2, v1)
  const v2d RA = A + (G * A + ((X * col0A - Y * B) + Z * col2A));
  const v2d RB = B + (G * B + ((X * col0B + Y * A) + Z * col0A));
  __builtin_memcpy(&q.w, &RA, sizeof RA);
  __builtin_memcpy(&q.v(1), &RB, sizeof RB);
}
#endif
}  // namespace detail

/// q ← q ⊗ (1, (x, y, z))/√(a |q|²), written as an increment of q (a = 1 + x² + y² + z² makes the factor a unit
/// quaternion; the |q|² in the root renormalises q as it goes). In double with GCC, the same operations in two-lane
/// vector code.
template <class T>
void multiply_increment(Quaternion<T>& q, const T& x, const T& y, const T& z, const T& a) {
#if defined(__GNUC__) && !defined(__clang__)
  if constexpr (std::is_same_v<T, double>) {
    detail::multiply_increment_vector(q, x, y, z, a);
    return;
  }
#endif
  detail::multiply_increment_scalar(q, x, y, z, a);
}

}  // namespace quat

// PrincipalAxes (J = Q diag(I) Qᵀ): core/inertia.hpp.

// ---------------------------------------------------------------------------------------------------
// (a) Axis rotations.

/// The default axis order (outer, middle, inner) for moments I: the smallest moment outermost, the
/// intermediate in the middle, the largest integrated with the full step innermost. Checked against all six
/// orders (see the header; tests/integrators/test_splitting.cpp, AxisOrderChangesEnergyErrorByOrdersOfMagnitude):
/// the best order on two of its three bodies and within 3× of the best on the third; on the flat body
/// I ∝ (1, 0.75, 0.25) it is the order whose h² error term vanishes (energy error below 1e-4 × the worst order's:
/// Fassò's fourth-order case; the figures are in docs/validation.md).
template <class T>
std::array<int, 3> axis_order_for(const Vec3<T>& I) {
  std::array<int, 3> idx{0, 1, 2};
  std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) { return value_of(I(a)) < value_of(I(b)); });
  return idx;  // outer: smallest, middle: intermediate, inner: largest
}

/// Flow (a) of the header: the free body as five exact principal-axis rotations, symmetric, explicit, order 2.
template <class T>
class AxisRotations {
 public:
  /// Unit moments, axis order 1, 2, 3.
  AxisRotations() = default;
  /// Principal moments I (> 0); options.axis_order, or axis_order_for(I) when it is {0, 0, 0}.
  AxisRotations(const Vec3<T>& I, const StepperOptions& options) : inv_I_(I.cwiseInverse()) {
    if (options.axis_order[0] == 0) {
      order_ = axis_order_for(I);
    } else {
      for (int i = 0; i < 3; ++i) order_[static_cast<std::size_t>(i)] = options.axis_order[static_cast<std::size_t>(i)] - 1;
    }
  }

  /// The five rotations are composed into one quaternion p = 1 + (δw, u) (kept as an increment, so its
  /// rounding scales with the small angles) while Π is rotated along to give the angles; then q ← q ⊗ p
  /// and Π ← R(p)ᵀ Π₀, each rounded once per step instead of five times (m·k after 10⁷ HV-top steps:
  /// 1.3e-12 with five sequential updates, see tests/integrators/test_splitting.cpp for the figure with one).
  LGI_FLATTEN StepStatus operator()(Quaternion<T>& q, Vec3<T>& Pi, const T& h) {
    Vec3<T> dPi;
    const StepStatus s = advance(q, Pi, h, dPi);
    Pi += dPi;
    return s;
  }
  /// The same step, with Π's increment R(p)ᵀΠ − Π returned instead of added (splitting.hpp adds it with the
  /// kicks in one rounding).
  StepStatus advance(Quaternion<T>& q, const Vec3<T>& Pi, const T& h, Vec3<T>& dPi) {
    const T half = T(0.5) * h;
    Vec3<T> P = Pi;
    T dw = T(0);
    Vec3<T> u = Vec3<T>::Zero();
    rotate(order_[0], half, dw, u, P);
    rotate(order_[1], half, dw, u, P);
    rotate(order_[2], h, dw, u, P);
    rotate(order_[1], half, dw, u, P);
    rotate(order_[0], half, dw, u, P);
    // q ⊗ (1 + δw, u) = q + (w δw − v·u, w u + δw v + v × u)
    const T w = q.w;
    const Vec3<T> v = q.v;
    q.w = w + (w * dw - v.dot(u));
    q.v = v + (w * u + dw * v + v.cross(u));
    quat::renormalise(q);
    // Π ← R(p)ᵀ Π = Π + (2/|p|²)(−p_w (u × Π) + u × (u × Π)),  p_w = 1 + δw
    const T pw = T(1) + dw;
    const T s = T(2) / (pw * pw + u.squaredNorm());
    const Vec3<T> up = u.cross(Pi);
    dPi = s * (u.cross(up) - pw * up);
    return StepStatus::ok;
  }

  /// The axes (0-based) in the order outer, middle, inner.
  const std::array<int, 3>& order() const { return order_; }

 private:
  /// Exact flow of H_i = Π_i²/(2 I_i) for a time tau, composed into p = 1 + (dw, u) and applied to P.
  void rotate(int i, const T& tau, T& dw, Vec3<T>& u, Vec3<T>& P) const {
    using std::cos;
    using std::sin;
    const T half_theta = T(0.5) * tau * P(i) * inv_I_(i);
    T s, c, cm1;  // sin(θ/2), cos(θ/2), cos(θ/2) − 1 (without cancellation)
    const T x2 = half_theta * half_theta;
    if (value_of(x2) < 0.01) {
      // Taylor polynomials, exact to < 3e-19 relative for |θ/2| < 0.1 (next terms x¹¹/11!, x¹⁰/10!);
      // cheaper than libm's sin and cos, which would dominate the step.
      static constexpr double sc[] = {1.0, -1.0 / 6, 1.0 / 120, -1.0 / 5040, 1.0 / 362880};
      static constexpr double cc[] = {-0.5, 1.0 / 24, -1.0 / 720, 1.0 / 40320, -1.0 / 3628800};
      s = half_theta * so3::detail::horner(x2, sc);
      cm1 = x2 * so3::detail::horner(x2, cc);
      c = T(1) + cm1;
    } else {
      s = sin(half_theta);
      c = cos(half_theta);
      cm1 = -(s * s) / (T(1) + c);
    }
    // p ⊗ (c, s e_i) = p + (c − 1) p + s p ⊗ (0, e_i);  p ⊗ (0, e) = (−u·e, p_w e + u × e), p_w = 1 + dw
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const T pw = T(1) + dw, ui = u(i), uj = u(j), uk = u(k);
    dw = dw + (cm1 * pw - s * ui);
    u(i) = ui + (cm1 * ui + s * pw);
    u(j) = uj + (cm1 * uj + s * uk);
    u(k) = uk + (cm1 * uk - s * uj);
    // (P_j, P_k) rotated by −θ: sin θ = 2sc, cos θ − 1 = −2s²
    const T sn = T(2) * s * c, cn1 = T(-2) * s * s;
    const T pj = P(j), pk = P(k);
    P(j) = pj + (cn1 * pj + sn * pk);
    P(k) = pk + (cn1 * pk - sn * pj);
  }

  Vec3<T> inv_I_ = Vec3<T>::Ones();
  std::array<int, 3> order_{0, 1, 2};
};

// ---------------------------------------------------------------------------------------------------
// (b) DMV in principal axes.

/// Newton update Δ = dG⁻¹ G for G_i(c) = I_i c_i + d_i c_j c_k − ½ α μ_i, α = 1 + |c|², d_i = I_k − I_j,
/// μ = hΠ; dG = diag(I) + off-diagonal d_i c_k (column j), d_i c_j (column k), minus μ cᵀ. Cramer's rule.
template <class T>
Vec3<T> dmv_newton_update(const Vec3<T>& c, const Vec3<T>& I, const Vec3<T>& d, const Vec3<T>& half_mu) {
  const T a = T(1) + c.squaredNorm();
  const T c0 = c(0), c1 = c(1), c2 = c(2);
  const Vec3<T> G(I(0) * c0 + d(0) * c1 * c2 - a * half_mu(0), I(1) * c1 + d(1) * c2 * c0 - a * half_mu(1),
                  I(2) * c2 + d(2) * c0 * c1 - a * half_mu(2));
  const Vec3<T> m = T(2) * half_mu;
  const Vec3<T> r0(I(0) - m(0) * c0, d(0) * c2 - m(0) * c1, d(0) * c1 - m(0) * c2);
  const Vec3<T> r1(d(1) * c2 - m(1) * c0, I(1) - m(1) * c1, d(1) * c0 - m(1) * c2);
  const Vec3<T> r2(d(2) * c1 - m(2) * c0, d(2) * c0 - m(2) * c1, I(2) - m(2) * c2);
  const Vec3<T> c12 = r1.cross(r2), c20 = r2.cross(r0), c01 = r0.cross(r1);
  return (G(0) * c12 + G(1) * c20 + G(2) * c01) / r0.dot(c12);
}

/// Counters of the DMV solver (diagnostics).
struct DmvCounters {
  /// Fixed-point sweeps beyond DmvSweepTable's prediction (a first convergence test that failed). The
  /// predicted ones are not counted: a counter bumped every step is a measurable part of a kick + DMV step
  /// (docs/performance.md, "Design measurements behind the code").
  std::int64_t extra_sweeps = 0;
  std::int64_t newton = 0;  ///< Newton updates
  std::int64_t fallbacks = 0;  ///< steps where the fixed point stalled and Newton took over
  std::int64_t substeps = 0;   ///< substeps taken where h|Π| > min I (dmv_substeps)
};

/// Constants of the DMV fixed point that depend on the moments only, computed once per flow.
///
/// Contraction bound (used by the convergence test of dmv_solve). One Gauss–Seidel sweep maps c to c' with
/// c'_i = F_i(α(c̃) w_i, c̃_j, c̃_k), c̃ the latest values; ∂F_i/∂c = 2w_i c + r_i (c_k e_j + c_j e_k) has
/// 1-norm ≤ 2|w_i|·√3|c| + |r_i|·√2|c|, so in the max norm ‖c' − c*‖ ≤ ρ‖c − c*‖ with
/// ρ ≤ (2√3|w| + √2 r)|c| (r = max|r_i|, |c| the largest along the segments from the iterate to the
/// solution c*), and ρ² ≤ (2.2 r² + 252|w|²)|c|² (as 4√6 r|w| ≤ 0.2 r² + 240|w|²), no square root needed.
/// The error after a sweep whose update is Δ is then ‖c' − c*‖ ≤ ρ/(1 − ρ)‖Δ‖ (max norm).
///
/// sweeps(|w|²): after how many Gauss–Seidel sweeps the convergence test is first made, from a model of
/// the iteration: the predictor leaves an error ≈ A|w|³, each sweep multiplies it by ≈ B|w|, with
/// A = 0.1 r² + 0.005 and B = 0.1 r + 2|w|; the test passes when (4/3)·ρ·(update) ≤ target. A and B follow the
/// median case of random momentum directions on six bodies (their distribution: docs/findings.md). The model is not
/// a bound: it only decides where the test is first made; a prediction one short costs one more sweep and test,
/// never accuracy.
/// quick_w2: below this |w|² = ¼h²|Π/I|² one substep certainly suffices (h|Π| ≤ 2 max I |w| ≤ min I), so
/// dmv_substeps need not be evaluated (1 % margin for rounding).
template <class V>
struct DmvSweepTable {
  static constexpr int max_sweeps = 12;  ///< fixed-point sweeps before Newton takes over
  std::array<V, max_sweeps + 1> w2{};  ///< w2[k]: the largest |w|² for which k sweeps are predicted to do
  V quick_w2 = 0;  ///< below this |w|², one substep (above)
  V tol2 = 0;                                                            ///< tolerance²
  /// (ε/4)², the round-off target.
  V round_off2 = V(0.25) * std::numeric_limits<V>::epsilon() * V(0.25) * std::numeric_limits<V>::epsilon();
  ///@{
  /// ρ² ≤ (rho_w |w|² + rho_r)|c|²: 252 and 2.2 r².
  V rho_w = 0, rho_r = 0;
  ///@}
  V fixed_point_w2 = 0;    ///< above this |w|², ρ ≤ ¼ cannot be shown (|c|² ≤ 1.2|w|²): Newton from the start
  ///@{
  /// The same constants as dmv_solve's test uses them: (9/16) target² = min(test_tol2 |w|², test_round_off2),
  /// ρ² ≤ (test_rho_w |w|² + test_rho_r)(|c|² + 300 U) (factors 9/16 and 1.02 folded in once, not per step)
  V test_tol2 = 0, test_round_off2 = 0, test_rho_w = 0, test_rho_r = 0;
  ///@}
  V fast_w2 = 0;  ///< min(quick_w2, fixed_point_w2)

  /// All zeros: a placeholder, to be assigned a table built from the moments.
  DmvSweepTable() = default;
  /// The table for r_max = max|r_i|, the smallest and largest moments and the Newton tolerance (StepperOptions).
  DmvSweepTable(V r_max, V min_I, V max_I, V tol)
      : quick_w2(V(0.99) * min_I * min_I / (V(4) * max_I * max_I)), tol2(tol * tol), rho_w(V(252)),
        rho_r(V(2.2) * r_max * r_max) {
    using std::sqrt;
    const V A = V(0.1) * r_max * r_max + V(0.005);
    const V round_off = sqrt(round_off2);
    w2[0] = 0;
    {
      V lo = 0, hi = 1;  // largest W2 with 1.02 (rho_w W2 + rho_r) 1.2 W2 ≤ 1/16
      for (int it = 0; it < 64; ++it) {
        const V x2 = V(0.5) * (lo + hi);
        (V(1.02) * (rho_w * x2 + rho_r) * V(1.2) * x2 <= V(0.0625) ? lo : hi) = x2;
      }
      fixed_point_w2 = lo;
    }
    fast_w2 = std::min(quick_w2, fixed_point_w2);
    test_tol2 = V(9) / V(16) * tol2;
    test_round_off2 = V(9) / V(16) * round_off2;
    test_rho_w = V(1.02) * rho_w;
    test_rho_r = V(1.02) * rho_r;
    for (int k = 1; k <= max_sweeps; ++k) {
      // largest x = |w| with (4/3)·ρ(x)·A x³ (B(x) x)^(k−1) ≤ min(tol x, ε/4), both sides increasing
      // in x: bisection
      V lo = 0, hi = 1;
      for (int it = 0; it < 64; ++it) {
        const V x = V(0.5) * (lo + hi);
        V e = A * x * x * x * V(4) / V(3) * sqrt(rho_w * x * x + rho_r) * x;
        for (int j = 1; j < k; ++j) e *= (V(0.1) * r_max + V(2) * x) * x;
        (e <= std::min(tol * x, round_off) ? lo : hi) = x;
      }
      w2[static_cast<std::size_t>(k)] = lo * lo;
    }
    // Non-decreasing (it is in the range used, below fixed_point_w2), so that sweeps() may bisect: the first
    // k with W2 ≤ w2[k] is unchanged by this.
    for (int k = 2; k <= max_sweeps; ++k)
      w2[static_cast<std::size_t>(k)] = std::max(w2[static_cast<std::size_t>(k)], w2[static_cast<std::size_t>(k - 1)]);
  }
  /// The smallest k ≥ 1 with W2 ≤ w2[k] (max_sweeps if none; 1 for NaN).
  int sweeps(V W2) const {
    if (!(W2 > w2[2])) return W2 > w2[1] ? 2 : 1;  // two comparisons up to 4 sweeps (w2 non-decreasing)
    if (!(W2 > w2[4])) return W2 > w2[3] ? 4 : 3;
    int k = 5;
    while (k < max_sweeps && W2 > w2[static_cast<std::size_t>(k)]) ++k;
    return k;
  }
};

/// Solves c_i = α w_i + r_i c_j c_k (w_i = ½h Π_i/I_i, r_i = (I_j − I_k)/I_i = −d_i/I_i) for c; see the header.
/// w and W2 = |w|² (its value part) come from the caller, which needs them for the substep decision.
///
/// Iteration: the predictor is one Gauss–Seidel sweep from c = w (error O(|w|³), much smaller than that of
/// Hairer's explicit predictor c_i = w_i + r_i c_j c_k, which lacks the α|w|² w term, for 4 more flops:
/// docs/findings.md); then Gauss–Seidel sweeps, the first convergence test after table.sweeps(W2) (the sweeps
/// before it unrolled). Fewer sweeps need a better start than the predictor gives: on the HV top at h = 0.01 the
/// error after the predictor and 3 sweeps is above ε/4 on part of the trajectory, and the better predictors
/// tried (an explicit series through |w|³, a sweep from c = w + r∘(w_j w_k)) are no better after two more sweeps
/// (docs/performance.md, "Where the instructions go"), so even a test that knew the error exactly would need the
/// 4th sweep there.
///
/// Accuracy: the solution is wanted to round-off, not to a tolerance. c enters the state as an increment
/// of the unit quaternion, so an error δc moves the state by ≈ 2|δc| (and Π by ≈ 2|Π||δc|): the sweeps stop
/// when every component's remaining error is below ε/4 (ε of the value type; or below tolerance·|w| where
/// that is smaller, at tiny steps) by the contraction bound of DmvSweepTable: with U the squared update of
/// the last sweep, ρ² ≤ P = 1.02 (2.2r² + 252|w|²)(|c|² + 300U) (|c|² at the sweep's start; the
/// second term covers the distance to the solution: (x + y)² ≤ 1.02x² + 51y², |e|² ≤ 3 (4/3)² U),
/// converged when P ≤ 1/16 (ρ ≤ ¼) and (16/9)·P·U ≤ target². That is a bound, not an estimate, and it
/// needs the update of the last sweep only (an estimate of ρ from two updates costs a second one). Newton
/// (below) takes over when an update is not 16× smaller than the one before (contraction worse than ¼ per
/// sweep), on NaN/overflow, after max_sweeps, and from the start where the bound cannot reach ¼
/// (|w|² > table.fixed_point_w2, |w| ≈ 0.1, h|Ω| ≈ 0.2). Stopping at a relative tolerance instead leaves a
/// solution error that is not the same for the step h and its reverse −h, and the step is then symmetric only
/// to that error (docs/findings.md); converged to round-off, step(h) ∘ step(−h) returns to the start within
/// 2e-15 at h = 0.1 on the skew top (tests/integrators/test_splitting.cpp, StepThenReverseStepIsIdentity).
///
/// alpha (for dmv_apply): α = 1 + |c|². Where the fixed point converged it is the α the test sweep started
/// from, not recomputed from the sweep's result (5 flops saved every step: docs/performance.md): the two differ
/// by 2c·Δ + |Δ|² (Δ the last update, ≈ 1e-16 at h|Ω| = 0.03), which changes the rounded α, by one ulp, in a
/// small fraction of the steps. |q| is then off by half an ulp, corrected the next step (q is renormalised from
/// its current norm); Π's rotation is orthogonal to ≈ 2|c| ulp(1) instead of to rounding in those steps. The
/// m·k random walk is the same with and without (docs/findings.md). Newton's result gets its own α.
template <class T>
StepStatus dmv_solve(const Vec3<T>& Pi, const T& h, const Vec3<T>& w, value_type_t<T> W2, const Vec3<T>& I,
                     const Vec3<T>& r, const Vec3<T>& d, const DmvSweepTable<value_type_t<T>>& table,
                     const StepperOptions& options, Vec3<T>& c, T& alpha, DmvCounters& counters,
                     bool fixed_point_ok = false) {
  using V = value_type_t<T>;
  const T w0 = w(0), w1 = w(1), w2 = w(2), r0 = r(0), r1 = r(1), r2 = r(2);
  const T a0 = T(1) + (w0 * w0 + w1 * w1 + w2 * w2);
  T c0 = a0 * w0 + r0 * w1 * w2;
  T c1 = a0 * w1 + r1 * c0 * w2;
  T c2 = a0 * w2 + r2 * c0 * c1;
  int k = 0;
  bool converged = false;
  if (fixed_point_ok || W2 <= table.fixed_point_w2) [[likely]] {
    const auto sweep = [&] {
      const T a = T(1) + (c0 * c0 + c1 * c1 + c2 * c2);
      c0 = a * w0 + r0 * c1 * c2;
      c1 = a * w1 + r1 * c0 * c2;
      c2 = a * w2 + r2 * c0 * c1;
    };
    // The sweeps before the first test, unrolled (a loop with a counter costs kick + DMV and its preprocessed
    // variants instructions every step: docs/performance.md, "Design measurements behind the code").
    k = table.sweeps(W2) - 1;
    if (k > 3) [[unlikely]]
      for (int i = 3; i < k; ++i) sweep();
    switch (k) {
      default:
        sweep();
        [[fallthrough]];
      case 2:
        sweep();
        [[fallthrough]];
      case 1:
        sweep();
        [[fallthrough]];
      case 0:
        break;
    }
    const V target2 = std::min(table.test_tol2 * W2, table.test_round_off2);  // (9/16) target²
    const V rho2_per_c2 = table.test_rho_w * W2 + table.test_rho_r;           // 1.02 (252|w|² + 2.2 r²)
    V last = std::numeric_limits<V>::infinity();
    for (;;) {
      const V p0 = static_cast<V>(value_of(c0)), p1 = static_cast<V>(value_of(c1)), p2 = static_cast<V>(value_of(c2));
      const T cc = c0 * c0 + c1 * c1 + c2 * c2;
      const T a = T(1) + cc;
      c0 = a * w0 + r0 * c1 * c2;
      c1 = a * w1 + r1 * c0 * c2;
      c2 = a * w2 + r2 * c0 * c1;
      ++k;
      const V d0 = static_cast<V>(value_of(c0)) - p0, d1 = static_cast<V>(value_of(c1)) - p1,
              d2 = static_cast<V>(value_of(c2)) - p2;
      const V upd = d0 * d0 + d1 * d1 + d2 * d2;
      const V rho2 = (static_cast<V>(value_of(cc)) + V(300) * upd) * rho2_per_c2;  // ρ² bound
      if (rho2 <= V(0.0625) && rho2 * upd <= target2) {
        converged = true;
        alpha = a;
        break;
      }
      if (!(V(16) * upd <= last) || k >= table.max_sweeps) break;  // worse than 1/4 per sweep, NaN
      last = upd;
      ++counters.extra_sweeps;
    }
  }
  c = Vec3<T>(c0, c1, c2);
  const T half_h = T(0.5) * h;
  if (!converged) [[unlikely]] {
    ++counters.fallbacks;
    if (!all_finite(c)) c = w;
    const Vec3<T> half_mu = half_h * Pi;
    const double floor = std::max(static_cast<double>(options.tolerance), 16 * static_cast<double>(epsilon_v<T>));
    bool newton_converged = false;
    for (int it = 0; it < options.max_iterations; ++it) {
      const Vec3<T> delta = dmv_newton_update(c, I, d, half_mu);
      c -= delta;
      ++counters.newton;
      const double dn = static_cast<double>(value_of(delta.cwiseAbs().maxCoeff()));
      const double sc = static_cast<double>(value_of(c.cwiseAbs().maxCoeff()));
      if (!std::isfinite(dn)) return StepStatus::non_finite;
      if (dn <= floor * sc) {
        newton_converged = true;
        break;
      }
    }
    if (!newton_converged) return StepStatus::not_converged;
    alpha = T(1) + c.squaredNorm();
  }
  if constexpr (is_dual_v<T>) {  // one Newton update makes the derivative part exact (implicit function theorem)
    c -= dmv_newton_update(c, I, d, Vec3<T>(half_h * Pi));
    ++counters.newton;
    alpha = T(1) + c.squaredNorm();
  }
  return StepStatus::ok;
}

/// q ← q ⊗ (1, c)/√α (quat::multiply_increment: renormalised, as an increment) and Π ← R((1, c)/√α)ᵀ Π =
/// Π + (2/α)(c × (c × Π) − c × Π), α = 1 + |c|² (from dmv_solve).
template <class T>
Vec3<T> dmv_apply(const Vec3<T>& c, const T& a, Quaternion<T>& q, const Vec3<T>& Pi) {  // returns Π's increment
  const T x = c(0), y = c(1), z = c(2);
  quat::multiply_increment(q, x, y, z, a);
  const T p0 = Pi(0), p1 = Pi(1), p2 = Pi(2);
  const T e0 = y * p2 - z * p1, e1 = z * p0 - x * p2, e2 = x * p1 - y * p0;  // c × Π
  const T f0 = y * e2 - z * e1, f1 = z * e0 - x * e2, f2 = x * e1 - y * e0;  // c × (c × Π)
  const T t = T(2) / a;
  return Vec3<T>(t * (f0 - e0), t * (f1 - e1), t * (f2 - e2));
}

/// Substeps of the DMV flow over h. The equation has a solution only while h|Π| is small enough: with
/// c = t u (|u| = 1), |hΠ|² = (4/α²)(|Ic|² + |c × Ic|²) ≤ I_max² + (I_max − I_min)² (as 4t²/(1 + t²)² ≤ 1,
/// 4t⁴/(1 + t²)² ≤ 4 and |u × Iu| ≤ (I_max − I_min)/2); on a principal axis exactly h|Ω| ≤ 1. Where
/// h|Π|/min I > 1 the flow takes m = ⌈h|Π|/min I⌉ equal DMV substeps (as the authors' code can, MSPLIT).
/// m depends on |Π| only, which the flow preserves, so the map stays symmetric; at ordinary steps m = 1
/// and this is plain DMV.
template <class T>
int dmv_substeps(const Vec3<T>& Pi, const T& h, double min_I) {
  const double hv = static_cast<double>(value_of(h));
  const double x2 = hv * hv * static_cast<double>(value_of(Pi.squaredNorm()));  // (h|Π|)², no root on the fast path
  if (x2 <= min_I * min_I) [[likely]]
    return 1;
  const double x = std::sqrt(x2) / min_I;
  return x < 1e6 ? static_cast<int>(std::ceil(x)) : 1000000;  // NaN: 1000000, and the solve reports it
}

/// w = ½h Π/I (inverse moments given) and its squared norm's value part.
template <class T>
Vec3<T> dmv_w(const Vec3<T>& Pi, const T& h, const Vec3<T>& inv_I, value_type_t<T>& W2) {
  const T half_h = T(0.5) * h;
  const Vec3<T> w(half_h * (Pi(0) * inv_I(0)), half_h * (Pi(1) * inv_I(1)), half_h * (Pi(2) * inv_I(2)));
  W2 = static_cast<value_type_t<T>>(value_of(w(0) * w(0) + w(1) * w(1) + w(2) * w(2)));
  return w;
}

/// Flow (b) of the header: the discrete Moser–Veselov step (the LGVI's free-body map), symmetric, symplectic,
/// order 2; an implicit solve for c (dmv_solve) in a few flops per sweep.
template <class T>
class Dmv {
 public:
  /// Unit moments.
  Dmv() = default;
  /// Principal moments I (> 0); options: the Newton tolerance and max_iterations.
  Dmv(const Vec3<T>& I, const StepperOptions& options)
      : I_(I), inv_I_(I.cwiseInverse()), options_(options),
        min_I_(static_cast<double>(value_of(I.minCoeff()))) {
    using V = value_type_t<T>;
    d_ = Vec3<T>(I(2) - I(1), I(0) - I(2), I(1) - I(0));
    r_ = Vec3<T>(-d_(0) * inv_I_(0), -d_(1) * inv_I_(1), -d_(2) * inv_I_(2));
    const V r_max = std::max({std::abs(V(value_of(r_(0)))), std::abs(V(value_of(r_(1)))), std::abs(V(value_of(r_(2))))});
    table_ = DmvSweepTable<V>(r_max, V(value_of(I.minCoeff())), V(value_of(I.maxCoeff())), V(options.tolerance));
  }

  /// One step of h: q ← q ⊗ p, Π ← R(p)ᵀ Π. ok; not_converged when the solve fails within max_iterations, or
  /// non_finite; Π untouched unless ok, q possibly moved by the substeps before a failing one (the splittings
  /// step a copy). Allocates nothing.
  LGI_FLATTEN StepStatus operator()(Quaternion<T>& q, Vec3<T>& Pi, const T& h) {
    Vec3<T> dPi;
    const StepStatus s = advance(q, Pi, h, dPi);
    if (s == StepStatus::ok) Pi += dPi;
    return s;
  }
  /// The same step, with Π's increment R(p)ᵀΠ − Π returned instead of added (splitting.hpp adds it with the
  /// kicks in one rounding).
  StepStatus advance(Quaternion<T>& q, const Vec3<T>& Pi, const T& h, Vec3<T>& dPi) {
    value_type_t<T> W2;
    const Vec3<T> w = dmv_w(Pi, h, inv_I_, W2);
    if (W2 <= table_.fast_w2) [[likely]]  // one substep, and the fixed point's bound can hold
      return substep(q, Pi, h, w, W2, dPi, true);
    const int m = dmv_substeps(Pi, h, min_I_);
    if (m == 1) return substep(q, Pi, h, w, W2, dPi);
    counters_.substeps += m;
    const T hm = h / T(m);
    Vec3<T> sum = Vec3<T>::Zero();
    for (int i = 0; i < m; ++i) {
      const Vec3<T> P = Pi + sum;
      const Vec3<T> wm = dmv_w(P, hm, inv_I_, W2);
      Vec3<T> inc;
      if (const StepStatus s = substep(q, P, hm, wm, W2, inc); s != StepStatus::ok) return s;
      sum += inc;
    }
    dPi = sum;
    return StepStatus::ok;
  }
  /// The solver's counters since construction.
  const DmvCounters& counters() const { return counters_; }

 private:
  StepStatus substep(Quaternion<T>& q, const Vec3<T>& Pi, const T& h, const Vec3<T>& w, value_type_t<T> W2,
                     Vec3<T>& dPi, bool fixed_point_ok = false) {
    Vec3<T> c;
    T alpha;
    if (const StepStatus s = dmv_solve(Pi, h, w, W2, I_, r_, d_, table_, options_, c, alpha, counters_, fixed_point_ok);
        s != StepStatus::ok)
      return s;
    dPi = dmv_apply(c, alpha, q, Pi);
    return StepStatus::ok;
  }

  Vec3<T> I_ = Vec3<T>::Ones(), inv_I_ = Vec3<T>::Ones(), d_ = Vec3<T>::Zero(), r_ = Vec3<T>::Zero();
  StepperOptions options_;
  double min_I_ = 1;
  DmvSweepTable<value_type_t<T>> table_;
  DmvCounters counters_;
};

// ---------------------------------------------------------------------------------------------------
// (c) Preprocessed DMV (Hairer & Vilmart 2006).

/// Coefficients of σ − 1 = Σ_{n=1}^{4} Σ_{j=0}^{n} s[n][j] η^(n−j) χ^j and δ = Σ d[n][j] η^(n−j) χ^j, with
/// η = ½h²|Π|², χ = h² H, as functions of the moments (DMV10.f: S3C*, D3C* → n = 1; S5C*, D5C* → 2;
/// S7C*, D7C* → 3; S9C*, D9C* → 4; C1 is the pure η power, the last the pure χ power).
template <class T>
struct HvCoefficients {
  ///@{
  /// s[n][j] and d[n][j], n = 1 … 4 (row 0 unused).
  std::array<std::array<T, 5>, 5> s{}, d{};
  ///@}
};

/// The coefficients for principal moments I (> 0), in T (Jets: derivatives with respect to I follow).
template <class T>
HvCoefficients<T> hv_coefficients(const Vec3<T>& I) {
  const T a1 = I(0), a2 = I(1), a3 = I(2);
  const auto p = [](const T& x, int n) {
    T r = T(1);
    for (int i = 0; i < n; ++i) r *= x;
    return r;
  };
  const auto inv_sum = [&](int n) { return T(1) / p(a1, n) + T(1) / p(a2, n) + T(1) / p(a3, n); };
  const auto sum = [&](int n) { return p(a1, n) + p(a2, n) + p(a3, n); };
  // Σ (I_i^m + I_j^m)/I_k^n over the three cyclic (i, j, k).
  const auto mixed = [&](int m, int n) {
    return (p(a1, m) + p(a2, m)) / p(a3, n) + (p(a2, m) + p(a3, m)) / p(a1, n) + (p(a3, m) + p(a1, m)) / p(a2, n);
  };
  const T xi1 = inv_sum(1), xi2 = inv_sum(2), xi3 = inv_sum(3), xi4 = inv_sum(4);
  const T det = a1 * a2 * a3, det2 = det * det, det3 = det2 * det, det4 = det2 * det2;
  const T s1 = sum(1), s2 = sum(2), s3 = sum(3), s4 = sum(4);
  const T si = mixed(1, 1), si12 = mixed(1, 2), si21 = mixed(2, 1), si13 = mixed(1, 3), si31 = mixed(3, 1),
          si22 = mixed(2, 2);
  HvCoefficients<T> k;
  k.s[1][0] = s1 / (T(6) * det);
  k.s[1][1] = -xi1 / T(3);
  k.d[1][0] = T(-1) / (T(3) * det);
  k.d[1][1] = k.s[1][0];

  k.s[2][0] = (s2 / det - xi1) / (T(30) * det);
  k.s[2][1] = (T(1) - si) / (T(30) * det);
  k.s[2][2] = (T(3) * s1 / det + T(2) * xi2) / T(60);
  k.d[2][0] = -s1 / det2 / T(60);
  k.d[2][1] = xi1 / det / T(10) - s2 / det2 / T(60);
  k.d[2][2] = -(T(9) + si) / det / T(60);

  k.s[3][0] = (T(4) * det + T(17) * s3 - T(15) * det * si) / (T(2520) * det3);
  k.s[3][1] = (T(9) * s1 + T(10) * det * xi2 - T(6) * si21) / (T(420) * det2);
  k.s[3][2] = ((T(6) * si12 - T(100) * xi1) * det + T(53) * s2) / (T(2520) * det2);
  k.s[3][3] = (T(15) - det * xi3 - T(2) * si) / (T(630) * det);
  k.d[3][0] = (T(34) * det * xi1 - T(19) * s2) / (T(2520) * det3);
  k.d[3][1] = (s3 + T(2) * det * si - T(85) * det) / (T(1260) * det3);
  k.d[3][2] = (T(47) * s1 + T(13) * si21 - T(38) * det * xi2) / (T(2520) * det2);
  k.d[3][3] = (T(9) * det * xi1 + det * si12 - T(11) * s2) / (T(1260) * det2);

  k.s[4][0] = (T(62) * s4 - T(94) * det * si21 + T(66) * det2 * xi2 + T(81) * det * s1) / (T(45360) * det4);
  k.s[4][1] = (T(-77) * si31 + T(75) * det * si12 + T(214) * s2 - T(240) * det * xi1) / (T(22680) * det3);
  k.s[4][2] = (T(26) * det * si22 + T(55) * s3 + T(204) * det - T(50) * det2 * xi3 - T(59) * det * si) / (T(7560) * det3);
  k.s[4][3] = (T(137) * det * xi2 - det * si13 + T(3) * s1 - T(69) * si21) / (T(11340) * det2);
  k.s[4][4] = (T(2) * det2 * xi4 + T(5) * det * si12 - T(171) * det * xi1 + T(159) * s2) / (T(45360) * det2);
  k.d[4][0] = (T(60) * si * det - T(61) * s3 - T(247) * det) / (T(45360) * det4);
  k.d[4][1] = (T(54) * det * s1 - s4 + T(218) * det * si21 - T(426) * det2 * xi2) / (T(45360) * det4);
  k.d[4][2] = (T(125) * det * xi1 - T(5) * si31 - T(130) * s2 + T(4) * det * si12) / (T(7560) * det3);
  k.d[4][3] = (T(67) * s3 - T(735) * det - T(15) * det * si22 + T(87) * det * si + T(34) * det2 * xi3) / (T(22680) * det3);
  k.d[4][4] = (T(165) * s1 - det * si13 - T(9) * si21 - T(145) * det * xi2) / (T(45360) * det2);
  return k;
}

/// Preprocessed DMV of order 2·R on the free body (R = 1: plain DMV with the modified-inertia machinery,
/// for testing; R = 2..5: orders 4..10).
template <class T, int R>
class PreprocessedDmv {
  static_assert(R >= 1 && R <= 5, "PreprocessedDmv: order 2R with R in 1..5");

 public:
  /// Unit moments.
  PreprocessedDmv() = default;
  /// Principal moments I (> 0); options: the Newton tolerance and max_iterations.
  PreprocessedDmv(const Vec3<T>& I, const StepperOptions& options)
      : inv_I_(I.cwiseInverse()), options_(options), k_(hv_coefficients(I)),
        min_I_(static_cast<double>(value_of(I.minCoeff()))) {
    // The sweep table of the unmodified moments: the modified ones differ by O(h²|Ω|²), and the table
    // only says where the first convergence test is made (DmvSweepTable).
    using V = value_type_t<T>;
    const Vec3<V> Iv(static_cast<V>(value_of(I(0))), static_cast<V>(value_of(I(1))), static_cast<V>(value_of(I(2))));
    const V r_max = std::max({std::abs((Iv(1) - Iv(2)) / Iv(0)), std::abs((Iv(2) - Iv(0)) / Iv(1)),
                              std::abs((Iv(0) - Iv(1)) / Iv(2))});
    table_ = DmvSweepTable<V>(r_max, Iv.minCoeff(), Iv.maxCoeff(), V(options.tolerance));
  }

  /// One step of h of the modified-inertia DMV (header, (c)); status and contract as Dmv's.
  LGI_FLATTEN StepStatus operator()(Quaternion<T>& q, Vec3<T>& Pi, const T& h) {
    Vec3<T> dPi;
    const StepStatus s = advance(q, Pi, h, dPi);
    if (s == StepStatus::ok) Pi += dPi;
    return s;
  }
  /// The same step, with Π's increment returned instead of added (as Dmv::advance).
  StepStatus advance(Quaternion<T>& q, const Vec3<T>& Pi, const T& h, Vec3<T>& dPi) {
    const int m = dmv_substeps(Pi, h, min_I_);
    if (m == 1) [[likely]]
      return substep(q, Pi, h, dPi);
    counters_.substeps += m;
    const T hm = h / T(m);
    Vec3<T> sum = Vec3<T>::Zero();
    for (int i = 0; i < m; ++i) {
      Vec3<T> inc;
      if (const StepStatus s = substep(q, Vec3<T>(Pi + sum), hm, inc); s != StepStatus::ok) return s;
      sum += inc;
    }
    dPi = sum;
    return StepStatus::ok;
  }
  /// The solver's counters since construction.
  const DmvCounters& counters() const { return counters_; }
  /// The modified-inertia coefficients, writable: for tests (a perturbed coefficient must lose the order).
  HvCoefficients<T>& coefficients() { return k_; }

 private:
  StepStatus substep(Quaternion<T>& q, const Vec3<T>& Pi, const T& h, Vec3<T>& dPi) {
    const T h2 = h * h;
    const Vec3<T> Pi2 = Pi.cwiseProduct(Pi);
    const T eta = T(0.5) * h2 * (Pi2(0) + Pi2(1) + Pi2(2));
    const T chi = T(0.5) * h2 * (Pi2(0) * inv_I_(0) + Pi2(1) * inv_I_(1) + Pi2(2) * inv_I_(2));
    T sigma = T(1), delta = T(0);
    // Σ_n Σ_j c[n][j] η^(n−j) χ^j
    std::array<T, R> eta_pow, chi_pow;
    if constexpr (R > 1) {
      eta_pow[0] = T(1);
      chi_pow[0] = T(1);
      for (int n = 1; n < R; ++n) {
        eta_pow[static_cast<std::size_t>(n)] = eta_pow[static_cast<std::size_t>(n - 1)] * eta;
        chi_pow[static_cast<std::size_t>(n)] = chi_pow[static_cast<std::size_t>(n - 1)] * chi;
      }
      for (int n = 1; n < R; ++n) {
        const auto un = static_cast<std::size_t>(n);
        for (int j = 0; j <= n; ++j) {
          const auto uj = static_cast<std::size_t>(j);
          const T mono = eta_pow[un - uj] * chi_pow[uj];
          sigma += k_.s[un][uj] * mono;
          delta += k_.d[un][uj] * mono;
        }
      }
    }
    const Vec3<T> inv_I = sigma * inv_I_ + Vec3<T>::Constant(delta);
    const Vec3<T> I = inv_I.cwiseInverse();
    const Vec3<T> d(I(2) - I(1), I(0) - I(2), I(1) - I(0));
    const Vec3<T> r(-d(0) * inv_I(0), -d(1) * inv_I(1), -d(2) * inv_I(2));
    value_type_t<T> W2;
    const Vec3<T> w = dmv_w(Pi, h, inv_I, W2);
    Vec3<T> c;
    T alpha;
    if (const StepStatus s = dmv_solve(Pi, h, w, W2, I, r, d, table_, options_, c, alpha, counters_);
        s != StepStatus::ok)
      return s;
    dPi = dmv_apply(c, alpha, q, Pi);
    return StepStatus::ok;
  }

  Vec3<T> inv_I_ = Vec3<T>::Ones();
  StepperOptions options_;
  HvCoefficients<T> k_;
  double min_I_ = 1;
  DmvSweepTable<value_type_t<T>> table_;
  DmvCounters counters_;
};

}  // namespace lgi
