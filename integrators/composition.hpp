/// \file
/// lgi/integrators/composition.hpp — symmetric compositions of a symmetric second-order one-step method.
///
/// Update (Hairer–Lubich–Wanner, GNI 2nd ed., §V.3.2, eq. (3.8) with symmetric coefficients (3.10)): for a
/// symmetric method S_h of order 2 (the LGVI; any kick–drift–kick splitting),
///
/// ~~~{.unparsed}
///   Ψ_h = S_{γ_s h} ∘ ⋯ ∘ S_{γ_2 h} ∘ S_{γ_1 h},      γ_{s+1−i} = γ_i,   Σ γ_i = 1,
/// ~~~
///
/// sub-step i starting at t + (γ_1 + … + γ_{i−1}) h. Ψ_h is symmetric; its order is that of the
/// coefficient set when the γ_i satisfy the order conditions of HLW Theorem V.3.4 (Σγ_i = 1, Σγ_i³ = 0 for
/// order 4, …; HLW Example V.3.5 and Fig. V.3.3 for orders up to 10). Some γ_i are negative: the base
/// method is stepped backwards. The composition inherits what the base preserves: a composition of
/// symplectic maps is symplectic, of maps that keep R on SO(3) or the momentum m·k keeps them, and the
/// energy error of a symplectic composition stays bounded. The cost is s base steps.
///
/// Coefficient sets (constexpr data below, each with its source; coefficients stored in long double, so
/// that long-double runs measure the high orders beyond double round-off):
/// ~~~{.unparsed}
///   yoshida4   order 4, s = 3:  γ_1 = γ_3 = 1/(2 − 2^{1/3}), γ_2 = −2^{1/3}/(2 − 2^{1/3}) — the "triple
///              jump" of Yoshida, Phys. Lett. A 150 (1990) 262 (his section number, "§4", not confirmed);
///              HLW (II.4.4) with p = 2, Example II.4.2, which credits Creutz & Gocksch 1989, Forest 1989,
///              Suzuki 1990 and Yoshida 1990.
///   suzuki4    order 4, s = 5:  γ_1 = γ_2 = γ_4 = γ_5 = 1/(4 − 4^{1/3}), γ_3 = −4^{1/3}/(4 − 4^{1/3}) —
///              Suzuki's fractal decomposition, Phys. Lett. A 146 (1990) 319; HLW (II.4.5) with p = 2,
///              Example II.4.3.
///   yoshida6   order 6, s = 7:  Yoshida 1990 solution A (his Table 1), to 26 digits as HLW (V.3.11) p6 s7.
///   kahan_li6  order 6, s = 9:  Kahan & Li, Math. Comp. 66 (1997) 1089; HLW (V.3.12) p6 s9.
///   yoshida8   order 8, s = 15: Yoshida 1990 solution A (his Table 2), 15 published digits; the middle
///              coefficient w_0 = 1 − 2 Σ w_i as Yoshida defines it, so that Σγ = 1 to round-off.
///   kahan_li8  order 8, s = 17: Kahan & Li 1997; HLW (V.3.14) p8 s17.
///   sofroniou_spaletta10  order 10, s = 35: Sofroniou & Spaletta, Optim. Methods Softw. 20 (2005) 597,
///              as printed in HLW 2nd ed. at the end of §V.3.2, just before §V.3.3 (which the table of
///              contents puts at p. 158), labelled "p10 s35"; in the copy read no equation number is legible
///              for it (the sets before it are (V.3.13) p8 s15 and (V.3.14) p8 s17), and HLW date it
///              "Sofroniou & Spaletta (2004)". Kahan & Li's own order-10 sets (s = 31, 33) could not be
///              obtained; HLW 2nd ed. calls this one "significantly improved" over them.
/// ~~~
/// Equation numbers are HLW 2nd ed. (2006) as confirmed from its text ((V.3.8), (V.3.10), Theorem V.3.4,
/// Example V.3.5, Fig. V.3.3, (V.3.11), (V.3.12), (V.3.14), (II.4.4), (II.4.5); the 26-digit p6 s7 and p10 s35
/// values above agree with the legible digits of that text); Yoshida's and Suzuki's own equation numbers
/// could not be confirmed and are not given. Every set is checked by tests/integrators/test_composition.cpp:
/// symmetric, Σγ = 1, and its observed order on the free body and a heavy top.
#pragma once

#include "../core/integrator.hpp"
#include "../core/problem.hpp"
#include "../core/state.hpp"
#include "lagrange_split.hpp"
#include "lgvi.hpp"
#include "splitting.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>

namespace lgi {

/// A symmetric composition Φ_h = Ψ_{γ_N h} ∘ … ∘ Ψ_{γ_1 h} of a symmetric order-2 method Ψ: its coefficients
/// (γ palindromic, Σγ = 1) as data, for Composition.
template <std::size_t N>
struct CompositionCoefficients {
  static constexpr std::size_t stages = N;  ///< base steps per step
  std::string_view name;   ///< the suffix of the composed method's scene name
  std::string_view title;  ///< a one-line description
  int order;               ///< the order of the composition of a symmetric order-2 base
  std::array<long double, N> gamma;  ///< γ_1 … γ_N, in long double
  std::string_view reference;        ///< the paper and table
};

/// Coefficient sets of symmetric compositions (CompositionCoefficients), with their references.
namespace compositions {
namespace detail {
// γ_1 … γ_m followed by γ_{m−1} … γ_1: the symmetric list of 2m − 1 coefficients from its first half and middle.
template <std::size_t M>
constexpr std::array<long double, 2 * M - 1> palindrome(const std::array<long double, M>& half) {
  std::array<long double, 2 * M - 1> g{};
  for (std::size_t i = 0; i < M; ++i) g[i] = g[2 * M - 2 - i] = half[i];
  return g;
}
// 1 − 2 Σ_{i<m} γ_i: the middle coefficient that makes Σγ = 1 (Yoshida's w_0).
template <std::size_t M>
constexpr std::array<long double, M> with_consistent_middle(std::array<long double, M> half) {
  long double s = 0;
  for (std::size_t i = 0; i + 1 < M; ++i) s += half[i];
  half[M - 1] = 1.0L - 2.0L * s;
  return half;
}
}  // namespace detail

/// 2^{1/3} and 4^{1/3} to 30 digits (the cube roots are not constexpr in C++20).
inline constexpr long double cbrt2 = 1.25992104989487316476721060728L;
/// 4^{1/3} (cbrt2's companion).
inline constexpr long double cbrt4 = 1.58740105196819947475170563927L;

/// Yoshida's triple jump (order 4, 3 stages).
inline constexpr CompositionCoefficients<3> yoshida4{
    .name = "yoshida4",
    .title = "Yoshida triple jump, order 4, 3 stages",
    .order = 4,
    .gamma = detail::palindrome<2>({1.0L / (2.0L - cbrt2), -cbrt2 / (2.0L - cbrt2)}),
    .reference = "Yoshida, Phys. Lett. A 150 (1990) 262; HLW GNI (II.4.4)",
};

/// Suzuki's fractal (order 4, 5 stages).
inline constexpr CompositionCoefficients<5> suzuki4{
    .name = "suzuki4",
    .title = "Suzuki fractal, order 4, 5 stages",
    .order = 4,
    .gamma = detail::palindrome<3>({1.0L / (4.0L - cbrt4), 1.0L / (4.0L - cbrt4), -cbrt4 / (4.0L - cbrt4)}),
    .reference = "Suzuki, Phys. Lett. A 146 (1990) 319; HLW GNI (II.4.5)",
};

/// Yoshida's solution A of order 6 (7 stages).
inline constexpr CompositionCoefficients<7> yoshida6{
    .name = "yoshida6",
    .title = "Yoshida solution A, order 6, 7 stages",
    .order = 6,
    .gamma = detail::palindrome<4>({0.78451361047755726381949763L, 0.23557321335935813368479318L,
                                    -1.17767998417887100694641568L, 1.31518632068391121888424973L}),
    .reference = "Yoshida, Phys. Lett. A 150 (1990) 262, Table 1 (A); HLW GNI (V.3.11)",
};

/// Kahan and Li's order 6 (9 stages).
inline constexpr CompositionCoefficients<9> kahan_li6{
    .name = "kahan_li6",
    .title = "Kahan-Li, order 6, 9 stages",
    .order = 6,
    .gamma = detail::palindrome<5>({0.39216144400731413927925056L, 0.33259913678935943859974864L,
                                    -0.70624617255763935980996482L, 0.08221359629355080023149045L,
                                    0.79854399093482996339895035L}),
    .reference = "Kahan, Li, Math. Comp. 66 (1997) 1089; HLW GNI (V.3.12)",
};

/// Yoshida's w_7 … w_1 (Table 2, solution A), then w_0 = 1 − 2 Σ w_i.
inline constexpr CompositionCoefficients<15> yoshida8{
    .name = "yoshida8",
    .title = "Yoshida solution A, order 8, 15 stages",
    .order = 8,
    .gamma = detail::palindrome<8>(detail::with_consistent_middle<8>(
        {0.104242620869991e1L, 0.182020630970714e1L, 0.157739928123617e0L, 0.244002732616735e1L,
         -0.716989419708120e-2L, -0.244699182370524e1L, -0.161582374150097e1L, 0.0L})),
    .reference = "Yoshida, Phys. Lett. A 150 (1990) 262, Table 2 (A)",
};

/// Kahan and Li's order 8 (17 stages).
inline constexpr CompositionCoefficients<17> kahan_li8{
    .name = "kahan_li8",
    .title = "Kahan-Li, order 8, 17 stages",
    .order = 8,
    .gamma = detail::palindrome<9>({0.13020248308889008087881763L, 0.56116298177510838456196441L,
                                    -0.38947496264484728640807860L, 0.15884190655515560089621075L,
                                    -0.39590389413323757733623154L, 0.18453964097831570709183254L,
                                    0.25837438768632204729397911L, 0.29501172360931029887096624L,
                                    -0.60550853383003451169892108L}),
    .reference = "Kahan, Li, Math. Comp. 66 (1997) 1089; HLW GNI (V.3.14)",
};

/// Sofroniou and Spaletta's order 10 (35 stages).
inline constexpr CompositionCoefficients<35> sofroniou_spaletta10{
    .name = "sofroniou_spaletta10",
    .title = "Sofroniou-Spaletta, order 10, 35 stages",
    .order = 10,
    .gamma = detail::palindrome<18>(
        {0.07879572252168641926390768L,  0.31309610341510852776481247L,  0.02791838323507806610952027L,
         -0.22959284159390709415121340L, 0.13096206107716486317465686L,  -0.26973340565451071434460973L,
         0.07497334315589143566613711L,  0.11199342399981020488957508L,  0.36613344954622675119314812L,
         -0.39910563013603589787862981L, 0.10308739852747107731580277L,  0.41143087395589023782070412L,
         -0.00486636058313526176219566L, -0.39203335370863990644808194L, 0.05194250296244964703718290L,
         0.05066509075992449633587434L,  0.04967437063972987905456880L,  0.04931773575959453791768001L}),
    .reference = "Sofroniou, Spaletta, Optim. Methods Softw. 20 (2005) 597; HLW GNI 2nd ed. sec. V.3.2 (p10 s35)",
};

}  // namespace compositions

namespace detail {
// A string_view's characters as a fixed array, so that names can be joined at compile time (with a
// terminating '\0' beyond the view, so that data() is also a C string).
template <std::size_t N>
struct JoinedName {
  std::array<char, N + 1> chars{};
  constexpr std::string_view view() const { return {chars.data(), N}; }
};
template <std::size_t N>
constexpr JoinedName<N> join(std::string_view a, std::string_view sep, std::string_view b) {
  JoinedName<N> r;
  std::size_t k = 0;
  for (const char ch : a) r.chars[k++] = ch;
  for (const char ch : sep) r.chars[k++] = ch;
  for (const char ch : b) r.chars[k++] = ch;
  return r;
}
}  // namespace detail

/// The composition of `Base<P>` (a symmetric order-2 stepper) with the coefficient set C. A stepper where `Base<P>`
/// is one (lagrange_split: axisymmetric problems only), so the registry offers it exactly there; the class
/// itself exists for any problem, as `Base<P>` does, so that its traits can be read.
template <const auto& C, template <class> class Base, class P>
class Composition {
  using B = Base<P>;
  static_assert(B::traits.order == 2 && B::traits.symmetric,
                "lgi::Composition: the base method must be symmetric and of order 2");
  /// A base of higher order on the free body (preprocessed DMV) would need coefficient sets that respect
  /// its free-body order; none is provided.
  static_assert(B::traits.free_body_order == 0, "lgi::Composition: the base must be of order 2 on every problem");

  static constexpr std::string_view base_name = B::traits.name;
  static constexpr auto name_ = detail::join<base_name.size() + 1 + C.name.size()>(base_name, "_", C.name);
  static constexpr auto title_ =
      detail::join<C.title.size() + 17 + base_name.size()>(C.title, ", composition of ", base_name);
  static constexpr auto reference_ =
      detail::join<C.reference.size() + 8 + B::traits.reference.size()>(C.reference, "; base: ", B::traits.reference);

 public:
  using Problem = P;                      ///< the problem type
  using Scalar = typename P::Scalar;      ///< its scalar
  using Internal = typename B::Internal;  ///< the base method's state
  using BaseMethod = B;                   ///< `Base<P>`
  static constexpr const auto& coefficients = C;  ///< the coefficient set

  /// The traits: the coefficients' order, the base's geometric properties, names joined (`<base>_<coefficients>`).
  static constexpr MethodTraits traits{
      .name = name_.view(),
      .title = title_.view(),
      .order = C.order,
      .symplectic = B::traits.symplectic,
      .symmetric = true,
      .explicit_method = B::traits.explicit_method,
      .exact_on_group = B::traits.exact_on_group,
      .preserves_momentum = B::traits.preserves_momentum,
      .reference = reference_.view(),
      .options = B::traits.options,
  };

  /// The base method built from (problem, options) (its exceptions propagate).
  explicit Composition(const P& problem, const StepperOptions& options = {})
    requires StateStepper<B>
      : base_(problem, options) {}

  /// The base method's coordinates of x.
  Internal to_internal(const State<Scalar>& x, const Scalar& t) const
    requires StateStepper<B>
  {
    return base_.to_internal(x, t);
  }
  /// The base method's state of y.
  State<Scalar> to_state(const Internal& y) const
    requires StateStepper<B>
  {
    return base_.to_state(y);
  }

  /// The base step inlined into the loop: a splitting's step() goes through a runtime-dispatched copy
  /// (core/scalar.hpp), a call per substep that slows the compositions (bench_steps; docs/performance.md, "Run-time
  /// dispatch for AVX2"); its step_inline() is the same step, compiled here.
  StepStatus base_step(Internal& z, const Scalar& tau, const Scalar& hi)
    requires StateStepper<B>
  {
    if constexpr (requires { base_.step_inline(z, tau, hi); })
      return base_.step_inline(z, tau, hi);
    else
      return base_.step(z, tau, hi);
  }

  /// s base steps on a copy of y; y is written only when all succeeded.
  /// The first failed base step's status is returned; cost: N base steps (γ_i h each, some of them negative).
  LGI_FLATTEN StepStatus step(Internal& y, const Scalar& t, const Scalar& h)
    requires StateStepper<B>
  {
    Internal z = y;
    Scalar tau = t;
    for (std::size_t i = 0; i < C.stages; ++i) {
      const Scalar hi = gamma<Scalar>(i) * h;
      if (const StepStatus s = base_step(z, tau, hi); s != StepStatus::ok) return s;
      tau += hi;
    }
    y = z;
    return StepStatus::ok;
  }

  /// Newton updates of the base method over the stepper's lifetime, where the base counts them.
  std::int64_t newton_iterations() const
    requires requires(const B& b) { b.newton_iterations(); }
  {
    return base_.newton_iterations();
  }
  /// The base stepper.
  const B& base() const { return base_; }

 private:
  /// γ_i in the scalar type: directly for floating types (long double keeps every digit), through double
  /// for others (ceres::Jet has no long double constructor).
  template <class T>
  static T gamma(std::size_t i) {
    if constexpr (std::is_floating_point_v<T>)
      return static_cast<T>(C.gamma[i]);
    else
      return T(static_cast<double>(C.gamma[i]));
  }

  B base_;
};

/// Compositions of the LGVI (scene names `lgvi_<coefficients>`).
/// lgvi_yoshida4: the LGVI composed with compositions::yoshida4 (order 4, 3 stages).
template <RigidBodyProblem P>
using LgviYoshida4 = Composition<compositions::yoshida4, Lgvi, P>;
/// lgvi_suzuki4: the LGVI composed with compositions::suzuki4 (order 4, 5 stages).
template <RigidBodyProblem P>
using LgviSuzuki4 = Composition<compositions::suzuki4, Lgvi, P>;
/// lgvi_yoshida6: the LGVI composed with compositions::yoshida6 (order 6, 7 stages).
template <RigidBodyProblem P>
using LgviYoshida6 = Composition<compositions::yoshida6, Lgvi, P>;
/// lgvi_kahan_li6: the LGVI composed with compositions::kahan_li6 (order 6, 9 stages).
template <RigidBodyProblem P>
using LgviKahanLi6 = Composition<compositions::kahan_li6, Lgvi, P>;
/// lgvi_yoshida8: the LGVI composed with compositions::yoshida8 (order 8, 15 stages).
template <RigidBodyProblem P>
using LgviYoshida8 = Composition<compositions::yoshida8, Lgvi, P>;
/// lgvi_kahan_li8: the LGVI composed with compositions::kahan_li8 (order 8, 17 stages).
template <RigidBodyProblem P>
using LgviKahanLi8 = Composition<compositions::kahan_li8, Lgvi, P>;
/// lgvi_sofroniou_spaletta10: the LGVI composed with compositions::sofroniou_spaletta10 (order 10, 35 stages).
template <RigidBodyProblem P>
using LgviSofroniouSpaletta10 = Composition<compositions::sofroniou_spaletta10, Lgvi, P>;

/// Compositions of kick + DMV (splitting.hpp; scene names `split_dmv_<coefficients>`): the same maps as the
/// LGVI's compositions (kick + DMV is the LGVI's map, NUMERICS.md), at the cost of the fast fixed-point
/// DMV step in principal axes — the cheap high-order heavy-top methods.
/// split_dmv_yoshida4: kick + DMV composed with compositions::yoshida4 (order 4, 3 stages).
template <AttitudeTorqueProblem P>
using SplitDmvYoshida4 = Composition<compositions::yoshida4, SplitDmv, P>;
/// split_dmv_suzuki4: kick + DMV composed with compositions::suzuki4 (order 4, 5 stages).
template <AttitudeTorqueProblem P>
using SplitDmvSuzuki4 = Composition<compositions::suzuki4, SplitDmv, P>;
/// split_dmv_kahan_li6: kick + DMV composed with compositions::kahan_li6 (order 6, 9 stages).
template <AttitudeTorqueProblem P>
using SplitDmvKahanLi6 = Composition<compositions::kahan_li6, SplitDmv, P>;
/// split_dmv_kahan_li8: kick + DMV composed with compositions::kahan_li8 (order 8, 17 stages).
template <AttitudeTorqueProblem P>
using SplitDmvKahanLi8 = Composition<compositions::kahan_li8, SplitDmv, P>;
/// split_dmv_sofroniou_spaletta10: kick + DMV composed with compositions::sofroniou_spaletta10 (order 10, 35 stages).
template <AttitudeTorqueProblem P>
using SplitDmvSofroniouSpaletta10 = Composition<compositions::sofroniou_spaletta10, SplitDmv, P>;

/// Compositions of the Lagrange top's splitting around the exact symmetric free flow (lagrange_split.hpp;
/// scene names `lagrange_split_<coefficients>`; axisymmetric problems only). Every sub-step integrates the
/// spin about the symmetry axis exactly, so the step size is set by the slow motions (nutation, precession)
/// and not by the spin rate: on the fast Lagrange top (Ω3 = 150) they are the fastest methods of lgi and its
/// peers, by an order of magnitude (benchmarks/work_precision; docs/performance.md, docs/benchmarks.md).
/// Symplectic and symmetric; m_ψ kept bit for bit (no sub-step touches Π3).
/// lagrange_split_yoshida4: the Lagrange split composed with compositions::yoshida4 (order 4, 3 stages).
template <AttitudeTorqueProblem P>
using LagrangeSplitYoshida4 = Composition<compositions::yoshida4, LagrangeSplit, P>;
/// lagrange_split_kahan_li6: the Lagrange split composed with compositions::kahan_li6 (order 6, 9 stages).
template <AttitudeTorqueProblem P>
using LagrangeSplitKahanLi6 = Composition<compositions::kahan_li6, LagrangeSplit, P>;
/// lagrange_split_kahan_li8: the Lagrange split composed with compositions::kahan_li8 (order 8, 17 stages).
template <AttitudeTorqueProblem P>
using LagrangeSplitKahanLi8 = Composition<compositions::kahan_li8, LagrangeSplit, P>;
/// lagrange_split_sofroniou_spaletta10: the Lagrange split composed with compositions::sofroniou_spaletta10
/// (order 10, 35 stages).
template <AttitudeTorqueProblem P>
using LagrangeSplitSofroniouSpaletta10 = Composition<compositions::sofroniou_spaletta10, LagrangeSplit, P>;

}  // namespace lgi
