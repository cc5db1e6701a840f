/// \file
/// lgi/integrators/rkmk.hpp — Runge–Kutta–Munthe-Kaas methods for any explicit Butcher tableau, with
/// adaptive steps and dense output on the group for embedded pairs.
///
/// With body angular velocity the flow is R(t) = R_n exp(u(t)), and u obeys the ODE in the Lie algebra
/// (right trivialisation; Hairer–Lubich–Wanner, GNI 2nd ed., eq. (IV.8.9) and Algorithm IV.8.3, with the
/// sign of ad flipped for right products):
///
/// ~~~{.unparsed}
///   u' = J_r⁻¹(u) Ω = Ω + ½ u × Ω + (1/12) u × (u × Ω) + …,     Ω' = J⁻¹((JΩ) × Ω + M(t, R_n exp(u))),
/// ~~~
///
/// u(0) = 0. One step applies the tableau (a, b, c) to this pair:
///
/// ~~~{.unparsed}
///   stage i:  u_i = h Σ_j a_ij U_j,   W_i = Ω_n + h Σ_j a_ij V_j,
///             U_i = J_r⁻¹(u_i) W_i (series truncated after ad^K),   V_i = Ω'(t_n + c_i h, R_n exp(u_i), W_i)
///   update:   R_{n+1} = R_n exp(h Σ b_i U_i),   Ω_{n+1} = Ω_n + h Σ b_i V_i.
/// ~~~
///
/// Truncation after the ad^(p−2) term keeps the order p of the tableau (HLW Theorem IV.8.5: classical order
/// p and truncation index q ≥ p − 2 in (IV.8.9) give order p — checked against the book's text, whose proof is
/// the argument below; HLW credit Algorithm IV.8.3 to Munthe-Kaas (1999), Appl. Numer. Math. 29 (1999) 115,
/// whose own theorem numbers were not checked): along the exact flow u = tΩ + O(t²), so ad_u^k Ω = O(t^(k+1))
/// and the dropped terms change a step by O(h^(p+1)). It makes the stage map a polynomial. Since B_k = 0 for
/// odd k ≥ 3, K is lowered to the last non-zero term. One non-zero term short, the order falls to the dropped
/// power + 1 (tests/integrators/test_rkmk_family.cpp, RkmkSeriesTruncation, each within 0.2: RKMK3 with K = 0
/// order 2; RKMK4 and DP5 with K = 1 order 3; DOP853 and Verner 9(8) with K = 4 order 7).
/// An embedded pair keeps K = p (DP5: K = 4; DOP853 and Verner 9(8): K = 8): the dropped terms are the same in
/// the solution and in its embedded companion, so the error estimate cannot see them, and at K = p − 2 they are
/// of the solution's own order — at large h|Ω| they dominate its error while the estimate stays small
/// (docs/findings.md). With K = p they fall two orders below it. A fixed-step tableau keeps K = p − 2 (RKMK4: 2).
/// Zero tableau entries are skipped at compile time, and so are trailing stages with b_i = 0 in fixed steps
/// (Dormand–Prince's 7th stage); for a torque-free problem no stage attitude is formed at all, and for a
/// torque that depends on R only through Γ = Rᵀa (ReducedAttitudeProblem: the heavy top) the stages
/// rotate Γ_i = exp(u_i)ᵀ Γ_n instead of forming R_n exp(u_i).
///
/// Embedded pairs (EmbeddedTableau: Dormand–Prince 5(4), DOP853, Verner 9(8)) also give, for adaptive steps
/// (integrators/adaptive.hpp):
/// ~~~{.unparsed}
///   error:   the two solutions R_n exp(u), R_n exp(û) differ by log(exp(û)ᵀ exp(u)) = δu + O(|u| |δu|) with
///            δu = u − û = h Σ e_i U_i (e = b − b̂), and in Ω by δΩ = h Σ e_i V_i. The six components are
///            scaled by sc = atol + rtol·1 for the attitude (a unit-size quantity: δu is the angle by which
///            the body axes, unit vectors, move) and sc_k = atol + rtol·max(|Ω_n,k|, |Ω_{n+1},k|) for Ω
///            (HNW I, §II.4, the scaling of Hairer's codes), and combined in the RMS norm
///            err = √(Σ (δ_k/sc_k)²/6) — for DOP853 err = ‖δ₅‖²/√(‖δ₅‖² + 0.01‖δ₃‖²) as in dop853.f.
///   dense:   the continuous extension applied in the Lie algebra, u(θh) = h Σ b_i(θ) U_i, Ω(t_n + θh) =
///            Ω_n + h Σ b_i(θ) V_i, R(t_n + θh) = R_n exp(u(θh)): it is the RK dense output of the ODE above,
///            so it has the tableau's dense order (4 for DP5, 7 for DOP853, 9 for Verner 9(8)) and R stays on
///            SO(3). The extra stages — DOP853's four (at the new point, and c = 0.1, 0.2, 7/9), Verner's ten
///            (the first at the new point) — are computed only when a step is asked for output. Munthe-Kaas,
///            BIT 38 (1998) 92 (the continuous RKMK idea); Engø, BIT 40 (2000) 41 ("Numerical analysis of Lie
///            group methods", variable steps and interpolation).
/// ~~~
///
/// Cayley coordinates (LieChart::cayley; methods rkmk4_cayley, rkmk_dp5_cayley, rkmk_dp8_cayley,
/// rkmk_vern9_cayley). RKMK works with any coordinate map ψ: so(3) → SO(3) with ψ(0) = I, ψ'(0) = id (Iserles,
/// Munthe-Kaas, Nørsett, Zanna, Acta Numerica 9 (2000) 215, the section "Alternative coordinates"; Munthe-Kaas,
/// Appl. Numer. Math. 29 (1999) 115): the step applies the tableau to u' = dψ_u⁻¹(Ω). With the Cayley map
/// cay(u) = (I − ½û)⁻¹(I + ½û) (core/so3.hpp) the inverse differential is exact and polynomial,
///
/// ~~~{.unparsed}
///   u' = dcay_u⁻¹ Ω = Ω + ½ u × Ω + ¼ (u·Ω) u        (HLW §IV.8.3, right-trivialised),
/// ~~~
///
/// so nothing is truncated and the order is the tableau's for any tableau; the stage attitudes are rational
/// in u — Γ_i = cay(u_i)ᵀ Γ_n = Γ_n − A u_i × Γ_n + ½A ((u_i·Γ_n) u_i − |u_i|² Γ_n), A = 4/(4 + |u_i|²) — and so
/// is the update R_{n+1} = R_n cay(h Σ b_i U_i): no sin, cos or square root anywhere in the step, where the
/// exponential chart calls libm's sin at every stage with a torque once θ² = |u_i|² ≥ 1e-2. The price is in
/// the error constants: at equal fixed steps DOP853 in Cayley coordinates is less accurate than in the
/// exponential chart, by much more on the free body than on the heavy top (docs/findings.md), so the adaptive
/// Cayley pair takes more steps for an error, each one cheaper (no transcendental functions). Dense output and error
/// estimates are those above with cay in place of exp.
///
/// Verner's most efficient 9(8) pair (rkmk_vern9, rkmk_vern9_cayley; tableaus::verner9): 16 stages a step against
/// DOP853's 12, for a solution of order 9 and an estimate of order 8 whose error constants are small; in Cayley
/// coordinates it needs fewer steps than DOP853 in either chart for the same error (docs/performance.md,
/// work-precision), at about DOP853's cost per stage (docs/performance.md, "Cost per step"). Orders (each within
/// 0.2; tests/integrators/test_rkmk_family.cpp, test_adaptive.cpp): 9 in the exponential chart on the skew top and
/// the free body; in Cayley coordinates its errors fall faster than h⁹ everywhere above the double round-off floor
/// (large h¹⁰ terms), and with order 9 below it (tests/integrators/test_quad_order.cpp, coefficients
/// `tableaus::verner9_in<C>` parsed to the run's precision: binary128 on the skew top, 50 digits on the GNI free
/// body; DOP853 in Cayley coordinates order 8 on the GNI body in binary128); the observed figures are in
/// docs/validation.md. Round-off: its interpolant's weights are degree-9 polynomials with coefficients up to
/// 1.07e4, whose Horner sums carry ≈ 1e-12 absolute round-off, far more than a step's end (docs/findings.md) —
/// output times read between steps are that far off, whatever the tolerance (and 5.3e-14 h in long double, from
/// the coefficients' own rounding to double).
///
/// Scalars and coefficients: any scalar of core/scalar.hpp (double, long double, ceres::Jet, a real class type
/// such as boost::multiprecision::float128), and a tableau with any coefficient type the scalar can be made from
/// (Scalar(Tableau.a[i][j]); zero tests at compile time): the double tableaus, or `tableaus::verner9_in<C>` and
/// `dop853_in<C>` for runs beyond double precision.
///
/// Non-diagonal J: principal axes. With a non-diagonal J every stage's Ω' = J⁻¹((JΩ) × Ω + M) costs two 3×3
/// products. The equations are equivariant under a constant change of body frame: with J = Q diag(I) Qᵀ
/// (det Q = 1; PrincipalAxes, core/inertia.hpp) the state R_p = R Q, Ω_p = QᵀΩ obeys the same equations with
/// J = diag(I), the laboratory axis a unchanged (Γ_p = R_pᵀa = QᵀΓ) and the lever v of a torque Γ × v turned
/// to Qᵀv. So a run of a double (or long double) RKMK method on a problem without torque or with a reduced
/// torque that has a lever (the heavy top and its relatives; the lever is checked against the torque at
/// construction) carries its state in principal axes: to_internal and to_state turn it at the edges of a run
/// (and at output times), the steps are those of a diagonal J, and R_p stays on SO(3) like R. Exact
/// equivariance: the same RKMK step in either frame in exact arithmetic (exp, cay and the dexp⁻¹ series commute
/// with rotations), so the method, its order and its error constants are unchanged; the error norm of adaptive
/// steps scales Ω's components in the body frame (its δΩ, Ω_n, Ω_{n+1} turned back: 3 products a trial step), so
/// the step sequence is the body frame's too. Jets and other torques keep the body frame (a Jet's Q would carry
/// first-order derivatives of J only; real class types such as float128 keep it too).
/// Principal-axis runs equal the body frame's to round-off (tests/integrators/test_rkmk_family.cpp,
/// RkmkPrincipalAxes); their cost per step is in docs/performance.md.
///
/// Order: that of the tableau. R stays on SO(3) to round-off (products of exponentials or Cayley
/// rotations). Not symplectic, not symmetric; energy and momentum drift like those of the underlying
/// Runge–Kutta method (the projection of integrators/projection.hpp restores them).
#pragma once

#include "../core/inertia.hpp"
#include "../core/integrator.hpp"
#include "../core/problem.hpp"
#include "../core/so3.hpp"
#include "../core/state.hpp"
#include "butcher_tableaus.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string_view>
#include <type_traits>
#include <utility>

namespace lgi {

/// The coordinates of the RKMK step: R = R_n exp(u) (the exponential chart, canonical coordinates of the first
/// kind) or R = R_n cay(u) (the Cayley map).
enum class LieChart : std::uint8_t { exp, cayley };

#if defined(LGI_DISPATCH_CLONES)
namespace detail {
// The RKMK trial step in double, compiled for the baseline and for AVX2 as the step (core/scalar.hpp,
// core/integrator.hpp), with results equal to the last bit (tests/core/test_dispatch.cpp).
template <class S>
[[gnu::target("avx2"), gnu::flatten]] StepStatus avx2_rkmk_attempt(const S& s, const typename S::Internal& x,
                                                                   double t, double h, typename S::Internal& x1,
                                                                   double& error, typename S::Dense& d) {
  return s.template attempt_inline<true>(x, t, h, x1, error, d);
}
template <class S>
StepStatus dispatched_rkmk_attempt(const S& s, const typename S::Internal& x, double t, double h,
                                   typename S::Internal& x1, double& error, typename S::Dense& d) {
  if (cpu_has_avx2()) return avx2_rkmk_attempt(s, x, t, h, x1, error, d);
  return s.attempt_inline(x, t, h, x1, error, d);
}
}  // namespace detail

#if !defined(__clang__)
#define LGI_RKMK_V4 1
namespace detail::v4 {
// The AVX2 copy's stage arithmetic: 3-vectors of double as 4-wide vectors (GCC's vector extension; entry 3 a copy
// of entry 2, computed alongside and never read), one packet of four each. Every operation is the one Eigen
// performs on a Vec3 element by element, in the same order, so the results are the same bits as the baseline's.
// Compiled for AVX2 (target("avx2")), as is every function that passes these vectors by value, so that calls
// between them agree on how a 32-byte vector is passed where they are not inlined; reached only from the AVX2
// copy (under the baseline the 4-wide code would be emulated, far slower).
typedef double V4 __attribute__((vector_size(32)));
typedef long long I4 __attribute__((vector_size(32)));
[[gnu::target("avx2")]] inline V4 of(const Vec3<double>& a) { return V4{a[0], a[1], a[2], a[2]}; }
[[gnu::target("avx2")]] inline Vec3<double> vec3(const V4& a) { return Vec3<double>(a[0], a[1], a[2]); }
/// a × b as Eigen's cross: (a1 b2 − a2 b1, a2 b0 − a0 b2, a0 b1 − a1 b0)
[[gnu::target("avx2")]] inline V4 cross(const V4& a, const V4& b) {
  const V4 a1 = __builtin_shuffle(a, I4{1, 2, 0, 3}), a2 = __builtin_shuffle(a, I4{2, 0, 1, 3});
  const V4 b1 = __builtin_shuffle(b, I4{1, 2, 0, 3}), b2 = __builtin_shuffle(b, I4{2, 0, 1, 3});
  return a1 * b2 - a2 * b1;
}
/// a·b as Eigen's reduction of a 3-vector: (a0 b0 + a1 b1) + a2 b2
[[gnu::target("avx2")]] inline double dot(const V4& a, const V4& b) {
  const V4 p = a * b;
  return (p[0] + p[1]) + p[2];
}
/// (Σ_J c_J U_J, Σ_J c_J V_J) over the stages J < N (K_J = (U_J, V_J)) whose coefficient c_J = Coef::at<J>() is
/// not zero, J ascending: the baseline's sums term by term.
template <int N, class Coef>
[[gnu::target("avx2")]] void combine(const Eigen::Matrix<double, 6, 1>* K, V4& sum_U, V4& sum_V) {
  sum_U = V4{0, 0, 0, 0};
  sum_V = V4{0, 0, 0, 0};
  [&]<int... J>(std::integer_sequence<int, J...>) {
    ([&] {
      if constexpr (Coef::template at<J>() != 0) {
        const V4 U = {K[J][0], K[J][1], K[J][2], K[J][2]}, V = {K[J][3], K[J][4], K[J][5], K[J][5]};
        sum_U += double(Coef::template at<J>()) * U;
        sum_V += double(Coef::template at<J>()) * V;
      }
    }(), ...);
  }(std::make_integer_sequence<int, N>{});
}
}  // namespace detail::v4
#endif
#endif

/// The RKMK method of Butcher tableau Tableau (butcher_tableaus.hpp) as a Stepper on problem P (this header):
/// explicit, the tableau's order, R on SO(3) to round-off; an AdaptiveStepper when the tableau is an embedded pair.
/// SeriesDegree: the last ad-power kept in the J_r⁻¹ series (−1: the default, the least that keeps the
/// tableau's order; other values only to measure that the truncation matters, tests/integrators/test_rkmk_family.cpp).
/// Unused by the Cayley chart, whose dcay⁻¹ is exact.
template <const auto& Tableau, RigidBodyProblem P, int SeriesDegree = -1, LieChart Chart = LieChart::exp>
class Rkmk {
 public:
  using Problem = P;                         ///< the problem type
  using Scalar = typename P::Scalar;         ///< its scalar
  using Internal = State<Scalar>;            ///< (R, Ω), in principal axes for a non-diagonal J (header)
  using Vec6 = Eigen::Matrix<Scalar, 6, 1>;  ///< a stage derivative (U, V) as one 6-vector

  /// An embedded pair: error estimate, dense output, adaptive steps.
  static constexpr bool embedded = tableaus::is_embedded_v<std::remove_cvref_t<decltype(Tableau)>>;
  static constexpr LieChart chart = Chart;  ///< the coordinate map of the step

 private:
  /// K = p − 2 for a fixed-step tableau, K = p for an embedded pair (header), lowered to the last non-zero
  /// term: the Bernoulli numbers B_k vanish for odd k ≥ 3, so K = 3 is K = 2 and K = 5 is K = 4 (DP5), K = 7 is
  /// K = 6 (the same terms; the name says which are kept).
  static constexpr int series_degree = [] {
    if constexpr (SeriesDegree >= 0) {
      return SeriesDegree;
    } else {
      const int p = Tableau.order;
      const int K = embedded ? p : (p > 2 ? p - 2 : 0);
      return K >= 3 && K % 2 == 1 ? K - 1 : K;
    }
  }();
  static constexpr bool reduced = P::has_torque && ReducedAttitudeProblem<P>;
  /// A reduced torque Γ × v with a constant lever v (core/problem.hpp).
  static constexpr bool has_lever = LeverTorqueProblem<P>;
  /// Runs with a non-diagonal J in principal axes (header): floating-point scalars, no torque or one with a lever.
  static constexpr bool principal_capable = std::is_floating_point_v<Scalar> && (!P::has_torque || has_lever);
  static constexpr bool lever_in_principal_axes = principal_capable && has_lever;
  static constexpr int dense_stages = tableaus::dense_stages(Tableau);
  static constexpr bool has_second_estimate = tableaus::has_second_estimate(Tableau);
  static constexpr int update_stages = tableaus::update_stages(Tableau);  ///< the stages a fixed step needs
  using Weights = tableaus::Weights;
  /// The AVX2 copy's stages use the 4-wide arithmetic of detail::v4 (double, GCC).
#if defined(LGI_RKMK_V4)
  template <bool Avx2>
  static constexpr bool wide = Avx2 && std::is_same_v<Scalar, double>;
#else
  template <bool Avx2>
  static constexpr bool wide = false;
#endif

  /// Scene name and title: the tableau's, with "_cayley" and " in Cayley coordinates" for the Cayley chart.
  template <std::size_t N>
  struct Text {
    std::array<char, N> chars{};
    constexpr std::string_view view() const { return {chars.data(), N}; }
  };
  template <std::size_t N>
  static constexpr Text<N> join(std::string_view a, std::string_view b) {
    Text<N> t;
    std::size_t k = 0;
    for (const char ch : a) t.chars[k++] = ch;
    for (const char ch : b) t.chars[k++] = ch;
    return t;
  }
  static constexpr std::string_view cayley_suffix = "_cayley", cayley_title_suffix = " in Cayley coordinates";
  static constexpr auto cayley_name = join<Tableau.name.size() + cayley_suffix.size()>(Tableau.name, cayley_suffix);
  static constexpr auto cayley_title =
      join<Tableau.title.size() + cayley_title_suffix.size()>(Tableau.title, cayley_title_suffix);
  static constexpr std::string_view cayley_reference_suffix =
      "; Cayley coordinates: Iserles, Munthe-Kaas, Norsett, Zanna, Acta Numerica 9 (2000) 215 (Alternative "
      "coordinates); Hairer-Lubich-Wanner GNI, sec. IV.8.3";
  static constexpr auto cayley_reference =
      join<Tableau.reference.size() + cayley_reference_suffix.size()>(Tableau.reference, cayley_reference_suffix);
  static constexpr bool cayley = Chart == LieChart::cayley;

 public:

  /// The method's traits, from the tableau (name, title, order, reference) and the chart.
  static constexpr MethodTraits traits{
      .name = cayley ? cayley_name.view() : Tableau.name,
      .title = cayley ? cayley_title.view() : Tableau.title,
      .order = Tableau.order,
      .symplectic = false,
      .symmetric = false,
      .explicit_method = true,
      .exact_on_group = true,
      .preserves_momentum = false,
      .reference = cayley ? cayley_reference.view() : Tableau.reference,
      .options = embedded ? std::array<std::string_view, 6>{"rtol", "atol", "projection"}
                          : std::array<std::string_view, 6>{"projection"},
  };

  /// Copies the problem; options: rtol and atol (embedded pairs) and projection (read by Projected).
  /// std::invalid_argument from StepperOptions::check, and when a lever torque's reduced_torque_lever() does not
  /// match reduced_torque().
  explicit Rkmk(const P& problem, const StepperOptions& options = {})
      : problem_(problem), J_(problem.inertia), rtol_(options.rtol), atol_(options.atol) {
    options.check();
    if constexpr (principal_capable) {
      if (!J_.diagonal) {
        axes_ = PrincipalAxes<Scalar>(problem_.inertia);
        J_ = Inertia<Scalar>(Mat3<Scalar>(axes_.I.asDiagonal()));
        if constexpr (has_lever) {
          check_reduced_torque_lever(problem_, "lgi::Rkmk");
          lever_ = axes_.to_principal(Vec3<Scalar>(problem_.reduced_torque_lever()));
        }
      }
    }
  }

  /// The internal state: (R, Ω) itself, or (R Q, QᵀΩ) in principal axes (a non-diagonal J, see the header).
  bool internal_is_body_frame() const { return axes_.identity; }
  /// x itself, or (R Q, QᵀΩ) in principal axes.
  Internal to_internal(const State<Scalar>& x, const Scalar&) const {
    if (axes_.identity) return x;
    return {Mat3<Scalar>(x.R * axes_.Q), axes_.to_principal(x.Omega)};
  }
  /// y itself, or (R Qᵀ, QΩ) back from principal axes.
  State<Scalar> to_state(const Internal& y) const {
    if (axes_.identity) return y;
    return {Mat3<Scalar>(y.R * axes_.Q.transpose()), axes_.to_body(y.Omega)};
  }
  /// Replaces the internal velocity by the body-frame Ω, the attitude untouched (projection.hpp).
  void set_omega(Internal& y, const Vec3<Scalar>& Omega) const { y.Omega = axes_.to_principal(Omega); }

  /// One fixed step from t to t + h (the header's update, the tableau's stages up to its last non-zero b_i): ok or
  /// non_finite, x untouched unless ok. Cost: one torque per stage (none without torque), one exponential or
  /// Cayley map per stage with a torque and one for the update; no allocation. In double, through the copy
  /// compiled for this machine's instruction set (core/scalar.hpp, LGI_DISPATCH_CLONES; the same results bit for
  /// bit).
  LGI_FLATTEN StepStatus step(Internal& x, const Scalar& t, const Scalar& h) {
#if defined(LGI_DISPATCH_CLONES)
    if constexpr (std::is_same_v<Scalar, double>) {
      return detail::dispatched_step(*this, x, t, h);
    } else
#endif
    {
      if constexpr (lever_in_principal_axes)
        if (!axes_.identity) return step_principal(x, t, h);
      return step_in<false>(x, t, h);
    }
  }

  /// The step of step() itself, both frames' copies inlined (what the dispatched copies compile); Avx2: the AVX2
  /// copy's code (core/integrator.hpp, detail::avx2_step), 4-wide in double, the same results bit for bit.
  template <bool Avx2 = false>
  LGI_FLATTEN StepStatus step_inline(Internal& x, const Scalar& t, const Scalar& h) {
    if constexpr (lever_in_principal_axes)
      if (!axes_.identity) return step_in<true, wide<Avx2>>(x, t, h);
    return step_in<false, wide<Avx2>>(x, t, h);
  }

  // ---- embedded pairs: adaptive steps and dense output (integrators/adaptive.hpp) ----

  /// The exponent k of the step-size rule h ∝ err^(−1/k).
  static constexpr int control_order = [] {
    if constexpr (embedded) return Tableau.control_order; else return 0;
  }();

  /// What a step leaves for its dense output: its start, its size and its stage derivatives.
  struct Dense {
    State<Scalar> x;     ///< the step's start (internal frame)
    ///@{
    /// The step's time and size.
    Scalar t, h;
    ///@}
    Vec3<Scalar> Gamma;  ///< Γ = Rᵀa at the start (reduced-attitude torques)
    std::array<Vec6, dense_stages> K;  ///< (U_i, V_i)
    bool extended = false;  ///< the dense-only stages are computed
  };

  /// One trial step of size h from (x, t): the new state in x1 (x untouched) and the scaled error norm in
  /// `error` (≤ 1: acceptable). The stages stay in `d` for dense_output. Status non_finite when the trial
  /// state is not finite (then `error` is +inf). In double, through the dispatched copy as step().
  LGI_FLATTEN StepStatus attempt(const Internal& x, const Scalar& t, const Scalar& h, Internal& x1, double& error,
                                 Dense& d) const
    requires embedded
  {
#if defined(LGI_DISPATCH_CLONES)
    if constexpr (std::is_same_v<Scalar, double>) {
      return detail::dispatched_rkmk_attempt(*this, x, t, h, x1, error, d);
    } else
#endif
    {
      if constexpr (lever_in_principal_axes)
        if (!axes_.identity) return attempt_principal(x, t, h, x1, error, d);
      return attempt_in<false>(x, t, h, x1, error, d);
    }
  }

  /// The trial step of attempt() itself, both frames' copies inlined (what the dispatched copies compile); Avx2 as
  /// for step_inline.
  template <bool Avx2 = false>
  LGI_FLATTEN StepStatus attempt_inline(const Internal& x, const Scalar& t, const Scalar& h, Internal& x1,
                                        double& error, Dense& d) const
    requires embedded
  {
    if constexpr (lever_in_principal_axes)
      if (!axes_.identity) return attempt_in<true, wide<Avx2>>(x, t, h, x1, error, d);
    return attempt_in<false, wide<Avx2>>(x, t, h, x1, error, d);
  }

  /// The state at t + θh of the step that filled d (θ ∈ [0, 1]): R_n exp(u(θh)), Ω(θh) from the continuous
  /// extension in the Lie algebra. Computes the dense-only stages on the first call for a step.
  LGI_FLATTEN Internal dense_output(Dense& d, const Scalar& theta) const
    requires embedded
  {
    if constexpr (lever_in_principal_axes)
      if (!axes_.identity) return dense_principal(d, theta);
    return dense_in<false>(d, theta);
  }

  /// The relative error tolerance of adaptive steps (StepperOptions::rtol; 0: fixed steps).
  double rtol() const { return rtol_; }
  /// The absolute error tolerance of adaptive steps (StepperOptions::atol).
  double atol() const { return atol_; }
  /// The problem, as copied at construction.
  const P& problem() const { return problem_; }

 private:
  /// The step, trial step and dense output, with the torque Γ × Qᵀv in principal axes (Pr) or the problem's.
  /// Two copies rather than a test at every stage: the test slows the body-frame step (docs/performance.md,
  /// "Design measurements behind the code").
  [[gnu::noinline]] LGI_FLATTEN StepStatus step_principal(Internal& x, const Scalar& t, const Scalar& h) {
    return step_in<true>(x, t, h);
  }
  [[gnu::noinline]] LGI_FLATTEN StepStatus attempt_principal(const Internal& x, const Scalar& t, const Scalar& h,
                                                             Internal& x1, double& error, Dense& d) const {
    return attempt_in<true>(x, t, h, x1, error, d);
  }
  [[gnu::noinline]] LGI_FLATTEN Internal dense_principal(Dense& d, const Scalar& theta) const {
    return dense_in<true>(d, theta);
  }

  template <bool Pr, bool Wide = false>
  StepStatus step_in(Internal& x, const Scalar& t, const Scalar& h) {
    std::array<Vec6, Tableau.stages> K;
    Vec3<Scalar> Gamma;  // Rᵀa at the start of the step (reduced-attitude problems; unread otherwise)
    if constexpr (reduced)
      Gamma = x.R.transpose() * problem_.reduced_axis();
    else
      Gamma.setZero();
    [&]<int... I>(std::integer_sequence<int, I...>) {
      (stage<I, Pr, Wide>(x, Gamma, t, h, K), ...);
    }(std::make_integer_sequence<int, update_stages>{});
    Vec3<Scalar> u, dOmega;
    weighted_sum<Weights::b, update_stages, Wide>(K, u, dOmega);
    // R exp(hu) as R + R (exp(hu) − I): see core/so3.hpp on the rounding of the increment.
    const Mat3<Scalar> R1 = x.R + x.R * increment(Vec3<Scalar>(h * u));
    return commit(x, R1, Vec3<Scalar>(x.Omega + h * dOmega));
  }

  template <bool Pr, bool Wide = false>
  StepStatus attempt_in(const Internal& x, const Scalar& t, const Scalar& h, Internal& x1, double& error,
                        Dense& d) const {
    d.x = x;
    d.t = t;
    d.h = h;
    d.extended = false;
    if constexpr (reduced) d.Gamma = x.R.transpose() * problem_.reduced_axis();
    [&]<int... I>(std::integer_sequence<int, I...>) {
      (stage<I, Pr, Wide>(x, d.Gamma, t, h, d.K), ...);
    }(std::make_integer_sequence<int, Tableau.stages>{});
    Vec3<Scalar> u, dOmega, du, dW;
    weighted_sum<Weights::b, Tableau.stages, Wide>(d.K, u, dOmega);
    weighted_sum<Weights::e, Tableau.stages, Wide>(d.K, du, dW);
    const Mat3<Scalar> R1 = x.R + x.R * increment(Vec3<Scalar>(h * u));
    const Vec3<Scalar> Omega1 = x.Omega + h * dOmega;
    if (!all_finite(R1) || !all_finite(Omega1)) {
      error = std::numeric_limits<double>::infinity();
      return StepStatus::non_finite;
    }
    // The Ω components are scaled in the body frame (turned back from principal axes, where the state is carried
    // there): the same steps, to rounding, whatever the frame — a Jet run (body frame) and its double run agree.
    // The attitude's scale is the same for all three components, so |δu| needs no turning.
    const auto body = [&](const Vec3<Scalar>& w) {
      if constexpr (principal_capable) return axes_.to_body(w); else return w;
    };
    const Vec3<Scalar> Wn = body(x.Omega), W1 = body(Omega1);
    const auto scaled = [&](const Vec3<Scalar>& a, const Vec3<Scalar>& w_internal) {  // Σ (δ_k / sc_k)²
      const Vec3<Scalar> w = body(w_internal);
      const double hv = std::abs(static_cast<double>(value_of(h)));
      const double sa = atol_ + rtol_;
      double s = 0;
      for (int k = 0; k < 3; ++k) {
        const double ea = hv * static_cast<double>(value_of(a[k])) / sa;
        const double sw = atol_ + rtol_ * std::max(std::abs(static_cast<double>(value_of(Wn[k]))),
                                                   std::abs(static_cast<double>(value_of(W1[k]))));
        const double ew = hv * static_cast<double>(value_of(w[k])) / sw;
        s += ea * ea + ew * ew;
      }
      return s;
    };
    const double s5 = scaled(du, dW);
    if constexpr (has_second_estimate) {
      Vec3<Scalar> du3, dW3;
      weighted_sum<Weights::e3, Tableau.stages, Wide>(d.K, du3, dW3);
      const double deno = s5 + 0.01 * scaled(du3, dW3);
      error = deno > 0 ? s5 / std::sqrt(6.0 * deno) : 0.0;
    } else {
      error = std::sqrt(s5 / 6.0);
    }
    if (!std::isfinite(error)) error = std::numeric_limits<double>::infinity();
    x1.R = R1;
    x1.Omega = Omega1;
    return StepStatus::ok;
  }

  template <bool Pr>
  Internal dense_in(Dense& d, const Scalar& theta) const {
    if (!d.extended) {
      [&]<int... I>(std::integer_sequence<int, I...>) {
        (stage<Tableau.stages + I, Pr>(d.x, d.Gamma, d.t, d.h, d.K), ...);
      }(std::make_integer_sequence<int, dense_stages - Tableau.stages>{});
      d.extended = true;
    }
    std::array<Scalar, dense_stages> w;
    for (int i = 0; i < dense_stages; ++i) {  // b_i(θ) = Σ_m dense[i][m−1] θ^m, Horner
      Scalar p = Scalar(Tableau.dense[i][Tableau.dense_degree - 1]);
      for (int m = Tableau.dense_degree - 2; m >= 0; --m) p = p * theta + Scalar(Tableau.dense[i][m]);
      w[i] = p * theta;
    }
    Vec6 sum = Vec6::Zero();
    for (int i = 0; i < dense_stages; ++i) sum += w[i] * d.K[i];
    const Vec3<Scalar> u = sum.template head<3>(), dOmega = sum.template tail<3>();
    Internal y;
    y.R = d.x.R + d.x.R * increment(Vec3<Scalar>(d.h * u));
    y.Omega = d.x.Omega + d.h * dOmega;
    return y;
  }

  /// ψ(w) − I of the chart ψ = exp or cay.
  static Mat3<Scalar> increment(const Vec3<Scalar>& w) {
    if constexpr (cayley)
      return so3::cayley_increment(w);
    else
      return so3::exp_increment(w);
  }

  /// The tableau's weights W (b, e or e3), or row I of its a, as coefficients c_J = at<J>() (detail::v4::combine).
  template <Weights W>
  struct WeightCoef {
    template <int J>
    static constexpr auto at() { return tableaus::weight<Tableau, W, J>(); }
  };
  template <int I>
  struct RowCoef {
    template <int J>
    static constexpr auto at() { return Tableau.a[I][J]; }
  };

  /// (Σ w_i U_i, Σ w_i V_i) over the first N stages, the weights W in stage order, the zero weights skipped.
  template <Weights W, int N, bool Wide, std::size_t M>
  static void weighted_sum(const std::array<Vec6, M>& K, Vec3<Scalar>& sum_U, Vec3<Scalar>& sum_V) {
#if defined(LGI_RKMK_V4)
    if constexpr (Wide) {
      detail::v4::V4 su, sv;
      detail::v4::combine<N, WeightCoef<W>>(K.data(), su, sv);
      sum_U = detail::v4::vec3(su);
      sum_V = detail::v4::vec3(sv);
      return;
    }
#endif
    const Vec6 s = tableaus::weighted_sum<Tableau, W, N>(K);
    sum_U = s.template head<3>();
    sum_V = s.template tail<3>();
  }

  /// The torque at Γ in the internal frame: the problem's, or Γ × Qᵀv in principal axes (Pr). (Not Γ × v in the
  /// body frame too: the problem's own b (Γ × z0) rounds differently, and the batch kernels repeat its bits.)
  template <bool Pr>
  Vec3<Scalar> reduced_torque(const Vec3<Scalar>& Gamma) const {
    if constexpr (Pr) return Gamma.cross(lever_); else return problem_.reduced_torque(Gamma);
  }

  /// Ω' = J⁻¹((JΩ) × Ω + M)
  Vec3<Scalar> acceleration(const Vec3<Scalar>& Omega, const Vec3<Scalar>& M) const {
    return J_.solve(Vec3<Scalar>(J_.apply(Omega).cross(Omega) + M));
  }
  Vec3<Scalar> acceleration(const Vec3<Scalar>& Omega) const {
    return J_.solve(Vec3<Scalar>(J_.apply(Omega).cross(Omega)));
  }

  /// Stage I: K_I = (U_I, V_I). U_I and V_I are combined as the 3-vectors they are written as (a packet and a
  /// scalar each): read back as the 6-vector's three packets, the packet that straddles U_I's last component and
  /// V_I's first would be loaded from two separate stores of the stage just written, which the store buffer
  /// cannot forward, and the load waits for both to reach the cache. The same operations element by element as
  /// the 6-vector's, so the same bits.
  template <int I, bool Pr, bool Wide = false, std::size_t N>
  void stage(const State<Scalar>& x, const Vec3<Scalar>& Gamma, const Scalar& t, const Scalar& h,
             std::array<Vec6, N>& K) const {
    if constexpr (I == 0) {
      K[0].template head<3>() = x.Omega;
      if constexpr (reduced)
        K[0].template tail<3>() = acceleration(x.Omega, reduced_torque<Pr>(Gamma));
      else if constexpr (P::has_torque)
        K[0].template tail<3>() = acceleration(x.Omega, body_torque(problem_, t, x.R, x.Omega));
      else
        K[0].template tail<3>() = acceleration(x.Omega);
    } else {
      Vec3<Scalar> sum_U = Vec3<Scalar>::Zero(), sum_V = Vec3<Scalar>::Zero();
#if defined(LGI_RKMK_V4)
      if constexpr (Wide && cayley && reduced && principal_capable) {
        wide_cayley_reduced_stage<I, Pr>(x, Gamma, h, K);
        return;
      } else if constexpr (Wide) {
        detail::v4::V4 su, sv;
        detail::v4::combine<I, RowCoef<I>>(K.data(), su, sv);
        sum_U = detail::v4::vec3(su);
        sum_V = detail::v4::vec3(sv);
      } else
#endif
      {
        [&]<int... J>(std::integer_sequence<int, J...>) {
          ([&] {
            if constexpr (Tableau.a[I][J] != 0) {
              sum_U += Scalar(Tableau.a[I][J]) * K[J].template head<3>();
              sum_V += Scalar(Tableau.a[I][J]) * K[J].template tail<3>();
            }
          }(), ...);
        }(std::make_integer_sequence<int, I>{});
      }
      const Vec3<Scalar> u = h * sum_U;
      const Vec3<Scalar> W = x.Omega + h * sum_V;
      if constexpr (cayley) {
        K[I].template head<3>() = so3::cayley_right_jacobian_inverse(u, W);
        if constexpr (reduced) {
          // Γ_i = cay(u)ᵀ Γ = Γ − A u × Γ + ½A u × (u × Γ), with u × (u × Γ) = (u·Γ) u − |u|² Γ
          const Scalar u2 = u.squaredNorm();
          const Scalar A = Scalar(4) / (Scalar(4) + u2);
          const Scalar half_A = Scalar(0.5) * A;
          const Vec3<Scalar> Gamma_i = Gamma - A * u.cross(Gamma) + half_A * (u.dot(Gamma) * u - u2 * Gamma);
          K[I].template tail<3>() = acceleration(W, reduced_torque<Pr>(Gamma_i));
        } else if constexpr (P::has_torque) {
          const Mat3<Scalar> R = x.R * so3::cayley(u);
          K[I].template tail<3>() = acceleration(W, body_torque(problem_, t + Scalar(Tableau.c[I]) * h, R, W));
        } else {
          K[I].template tail<3>() = acceleration(W);
        }
        return;
      }
      K[I].template head<3>() = so3::right_jacobian_inverse_series<series_degree>(u, W);
      if constexpr (reduced) {
        const so3::Coefficients<Scalar> k = so3::exp_coefficients(u);  // Γ_i = exp(u)ᵀ Γ = exp(−u) Γ
        K[I].template tail<3>() = acceleration(W, reduced_torque<Pr>(so3::rotate(u, Scalar(-k.A), k.B, Gamma)));
      } else if constexpr (P::has_torque) {
        const Mat3<Scalar> R = x.R * so3::exp(u);
        K[I].template tail<3>() = acceleration(W, body_torque(problem_, t + Scalar(Tableau.c[I]) * h, R, W));
      } else {
        K[I].template tail<3>() = acceleration(W);
      }
    }
  }

#if defined(LGI_RKMK_V4)
  /// Stage I > 0 in Cayley coordinates with a reduced torque, J_ diagonal (principal_capable), in the AVX2 copy:
  /// stage()'s operations in the same order, on detail::v4 vectors, so the same bits.
  template <int I, bool Pr, std::size_t N>
  [[gnu::target("avx2")]] void wide_cayley_reduced_stage(const State<Scalar>& x, const Vec3<Scalar>& Gamma,
                                                         const Scalar& h, std::array<Vec6, N>& K) const {
    using detail::v4::V4, detail::v4::of, detail::v4::cross, detail::v4::dot;
    V4 sum_U, sum_V;
    detail::v4::combine<I, RowCoef<I>>(K.data(), sum_U, sum_V);
    const V4 u = h * sum_U;
    const V4 W = of(x.Omega) + h * sum_V;
    const V4 U = (W + 0.5 * cross(u, W)) + (0.25 * dot(u, W)) * u;  // so3::cayley_right_jacobian_inverse
    const double u2 = dot(u, u);
    const double A = 4.0 / (4.0 + u2);
    const double half_A = 0.5 * A;
    const V4 G = of(Gamma);
    const V4 Gamma_i = (G - A * cross(u, G)) + half_A * (dot(u, G) * u - u2 * G);
    V4 M;
    if constexpr (Pr)
      M = cross(Gamma_i, of(lever_));
    else
      M = of(problem_.reduced_torque(detail::v4::vec3(Gamma_i)));
    const V4 V = of(J_.J_inv.diagonal()) * (cross(of(J_.J.diagonal()) * W, W) + M);  // acceleration(W, M)
    K[I] << U[0], U[1], U[2], V[0], V[1], V[2];
  }
#endif

  P problem_;
  Inertia<Scalar> J_;  ///< diag(I) in principal axes
  double rtol_, atol_;
  PrincipalAxes<Scalar> axes_;                 ///< identity: the internal frame is the body frame
  Vec3<Scalar> lever_ = Vec3<Scalar>::Zero();  ///< Qᵀv in principal axes (has_lever)
};

/// lie_euler: the Lie–Euler method (order 1).
template <RigidBodyProblem P>
using LieEuler = Rkmk<tableaus::euler, P>;
/// rkmk_heun: RKMK with Heun's tableau (order 2).
template <RigidBodyProblem P>
using RkmkHeun = Rkmk<tableaus::heun, P>;
/// rkmk3: RKMK with Kutta's third-order tableau.
template <RigidBodyProblem P>
using Rkmk3 = Rkmk<tableaus::kutta3, P>;
/// rkmk4: RKMK with the classical fourth-order tableau.
template <RigidBodyProblem P>
using Rkmk4 = Rkmk<tableaus::classical_rk4, P>;
/// rkmk4_38: RKMK with the 3/8 rule (order 4).
template <RigidBodyProblem P>
using Rkmk4Rule38 = Rkmk<tableaus::rule38, P>;
/// rkmk_dp5: Dormand–Prince 5(4), adaptive with dense output (order 5).
template <RigidBodyProblem P>
using RkmkDp5 = Rkmk<tableaus::dormand_prince5, P>;
/// rkmk_dp8: DOP853, 8(5,3), adaptive with dense output (order 8).
template <RigidBodyProblem P>
using RkmkDp8 = Rkmk<tableaus::dop853, P>;
/// rkmk4_cayley: rkmk4 in Cayley coordinates.
template <RigidBodyProblem P>
using Rkmk4Cayley = Rkmk<tableaus::classical_rk4, P, -1, LieChart::cayley>;
/// rkmk_dp5_cayley: rkmk_dp5 in Cayley coordinates.
template <RigidBodyProblem P>
using RkmkDp5Cayley = Rkmk<tableaus::dormand_prince5, P, -1, LieChart::cayley>;
/// rkmk_dp8_cayley: rkmk_dp8 in Cayley coordinates.
template <RigidBodyProblem P>
using RkmkDp8Cayley = Rkmk<tableaus::dop853, P, -1, LieChart::cayley>;
/// rkmk_vern9: Verner's 9(8) pair, adaptive with dense output (order 9).
template <RigidBodyProblem P>
using RkmkVern9 = Rkmk<tableaus::verner9, P>;
/// rkmk_vern9_cayley: rkmk_vern9 in Cayley coordinates.
template <RigidBodyProblem P>
using RkmkVern9Cayley = Rkmk<tableaus::verner9, P, -1, LieChart::cayley>;

}  // namespace lgi
