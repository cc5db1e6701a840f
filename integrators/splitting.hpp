/// \file
/// lgi/integrators/splitting.hpp — Strang splitting of a torqued rigid body into potential kicks and a
/// free-body flow (free_body_flows.hpp): the heavy top as kick(h/2) ∘ free body(h) ∘ kick(h/2).
///
/// Update (principal axes, see free_body_flows.hpp: Π = Qᵀ J Ω, R_p = R Q as a unit quaternion q; M(t, R)
/// the body-frame torque, M_p = Qᵀ M):
///
/// ~~~{.unparsed}
///   Π⁺ = Π_n + ½ h M_p(t_n, R_n)                 kick: exact flow of the potential part (R fixed)
///   (q_{n+1}, Π⁻) = Φ_h(q_n, Π⁺)                 free-body flow: AxisRotations, Dmv, PreprocessedDmv<r>,
///                                                 or an exact flow
///   Π_{n+1} = Π⁻ + ½ h M_p(t_n + h, R_{n+1})     kick
/// ~~~
/// (computed as Π_n + ((½h M_n + (Π⁻ − Π⁺)) + ½h M_{n+1}), so that Π is rounded once per step, not three
/// times, which makes the m·k error of long runs smaller: docs/findings.md)
///
/// (Strang, SIAM J. Numer. Anal. 5 (1968) 506; for rigid bodies Touma & Wisdom, Astron. J. 107 (1994)
/// 1189, Dullweber, Leimkuhler & McLachlan, J. Chem. Phys. 107 (1997) 5840; HLW GNI §VII.5.) The torque at
/// the end of a step is kept for the next step's first kick: one torque per step. For a torque that
/// depends on R only through Γ = Rᵀa (ReducedAttitudeProblem, the heavy top) the internal laboratory frame
/// is turned once so that a = |a| e3 (R_internal = A R Q; A = 1 for the usual a = e3), and Γ_p = |a| R(q)ᵀe3
/// is read off the quaternion in 13 flops (30 for a general a); no matrix is formed. Where the torque is a
/// cross product with a constant body vector, M = Γ × v (the problem's reduced_torque_lever(): gravity,
/// v = b z0), it is Γ_p × Qᵀv with Qᵀv (times 2|a|) formed once: 19 flops for Γ and M together, whatever
/// J's principal axes.
///
/// Order 2 with a torque (symmetric: the splitting is a symmetric composition of symmetric pieces, so
/// symmetric compositions raise it: integrators/composition.hpp), the free-body flow's order without one
/// (the preprocessed DMV: 4–10). The traits say so for every problem alike: `order` = 2 (what holds with a
/// torque, measured on the skew heavy top), `free_body_order` = the flow's order where it is higher
/// (measured on the free body: tests/integrators/test_dmv.cpp). With kick + DMV this is the same map as the LGVI
/// (lgvi.hpp; NUMERICS.md: LGVI ≡ RATTLE ≡ Strang(kick, DMV, kick)), implemented in principal axes with a
/// quaternion. Symplectic when the free-body flow is (axis rotations, DMV, the exact flow); m·k (the
/// momentum the torque leaves alone) and |Γ| = 1 preserved to round-off; R on SO(3) to round-off.
///
/// Non-diagonal J: the state is carried in principal axes (PrincipalAxes: Eigen's eigensolver in double,
/// first-order perturbation for Jets); to_internal/to_state convert at the edges of a run.
///
/// Torques M(t, R) only (AttitudeTorqueProblem, core/problem.hpp): a kick holds R fixed and adds h·M(t, R) to the
/// momentum, which needs a torque that does not change with Ω during the kick. So do the compositions of these
/// splittings and of the LGVI (composition.hpp), split_exact.hpp and lagrange_split.hpp.
#pragma once

#include "../core/state_io.hpp"
#include "../core/integrator.hpp"
#include "../core/problem.hpp"
#include "../core/state.hpp"
#include "free_body_flows.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string_view>
#include <type_traits>

namespace lgi {

/// Traits of a free-body flow inside the splitting (name, title, order without/with torque, ...).
/// A specialisation has, as static constexpr members: name and title (the splitting's scene name and title),
/// free_order (its order on torque-free problems), symplectic, explicit_method, reference (the papers) and options
/// (the StepperOptions keys the flow reads): the Splitting's MethodTraits are made of them.
template <class Flow>
struct FlowTraits;

/// The splitting with five principal-axis rotations (split_axes): explicit, symplectic, order 2.
template <class T>
struct FlowTraits<AxisRotations<T>> {
  /// The members, for the three flows alike: name and title, free_order, symplectic, explicit_method, reference,
  /// options (FlowTraits).
  ///@{
  static constexpr std::string_view name = "split_axes";
  static constexpr std::string_view title = "Strang splitting: gravity kicks + 5 principal-axis rotations";
  static constexpr int free_order = 2;
  static constexpr bool symplectic = true;
  static constexpr bool explicit_method = true;
  static constexpr std::string_view reference =
      "McLachlan PRL 71 (1993); Touma & Wisdom AJ 107 (1994); Dullweber et al. JCP 107 (1997); axis order: "
      "Fasso JCP 189 (2003)";
  static constexpr std::array<std::string_view, 6> options{"axis_order"};
  ///@}
};

/// The splitting with the discrete Moser–Veselov flow (split_dmv): implicit, symplectic, order 2.
template <class T>
struct FlowTraits<Dmv<T>> {
  /// The members, as for AxisRotations (FlowTraits).
  ///@{
  static constexpr std::string_view name = "split_dmv";
  static constexpr std::string_view title = "Strang splitting: gravity kicks + discrete Moser-Veselov (fast form)";
  static constexpr int free_order = 2;
  static constexpr bool symplectic = true;
  static constexpr bool explicit_method = false;
  static constexpr std::string_view reference =
      "Moser & Veselov CMP 139 (1991); Hairer, Lubich, Wanner GNI 2nd ed. VII.5.3 eq. (5.27)";
  static constexpr std::array<std::string_view, 6> options{"tolerance", "max_iterations"};
  ///@}
};

/// The splittings with the preprocessed DMV of order 2R on the free body (split_dmvp2, split_dmv4 … split_dmv10).
template <class T, int R>
struct FlowTraits<PreprocessedDmv<T, R>> {
  /// The members, as for AxisRotations (FlowTraits): names[R] and titles[R] are this R's.
  ///@{
  static constexpr std::string_view names[6] = {"", "split_dmvp2", "split_dmv4", "split_dmv6", "split_dmv8",
                                               "split_dmv10"};
  static constexpr std::string_view titles[6] = {
      "", "", "Strang splitting: kicks + preprocessed DMV (free body order 4)",
      "Strang splitting: kicks + preprocessed DMV (free body order 6)",
      "Strang splitting: kicks + preprocessed DMV (free body order 8)",
      "Strang splitting: kicks + preprocessed DMV (free body order 10)"};
  static constexpr std::string_view name = names[R];
  static constexpr std::string_view title = titles[R];
  static constexpr int free_order = 2 * R;
  static constexpr bool symplectic = R == 1;  ///< modified inertia depends on H, |Π|: not claimed (see header)
  static constexpr bool explicit_method = false;
  static constexpr std::string_view reference =
      "Hairer & Vilmart, J. Phys. A 39 (2006) 13225 (coefficients: the authors' DMV10.f)";
  /// Not claimed symplectic (above): the invariant projection is offered, as for any such method.
  static constexpr std::array<std::string_view, 6> options =
      R == 1 ? std::array<std::string_view, 6>{"tolerance", "max_iterations"}
             : std::array<std::string_view, 6>{"tolerance", "max_iterations", "projection"};
  ///@}
};

/// The Strang splitting kick(h/2) ∘ Flow(h) ∘ kick(h/2) (this header) as a Stepper on problem P: explicit or
/// implicit as its Flow, order 2 with a torque, symmetric. The aliases below name the methods.
template <class Flow, AttitudeTorqueProblem P>
class Splitting {
 public:
  using Problem = P;                  ///< the problem type
  using Scalar = typename P::Scalar;  ///< its scalar
  /// The state in principal axes and the internal laboratory frame (header), with the next kick's torque.
  struct Internal {
    Quaternion<Scalar> q;  ///< R_p = R Q
    Vec3<Scalar> Pi;       ///< principal-axis body momentum
    Vec3<Scalar> M;        ///< principal-axis torque at q (the next step's first kick)
    LGI_NUMBERS(q, Pi, M)
  };

  /// The method's traits, from `FlowTraits<Flow>`.
  static constexpr MethodTraits traits{
      .name = FlowTraits<Flow>::name,
      .title = FlowTraits<Flow>::title,
      .order = 2,  // with any torque; the same on every problem (lgi list, README)
      .free_body_order = FlowTraits<Flow>::free_order == 2 ? 0 : FlowTraits<Flow>::free_order,
      .symplectic = FlowTraits<Flow>::symplectic,
      .symmetric = true,
      .explicit_method = FlowTraits<Flow>::explicit_method,
      .exact_on_group = true,
      .preserves_momentum = true,
      .reference = FlowTraits<Flow>::reference,
      .options = FlowTraits<Flow>::options,
  };

  /// Copies the problem and finds J's principal axes. std::invalid_argument from StepperOptions::check, and when
  /// the problem's reduced_torque_lever() does not match its reduced_torque() (check_reduced_torque_lever).
  explicit Splitting(const P& problem, const StepperOptions& options = {})
      : problem_(problem), axes_(problem.inertia) {
    options.check();
    flow_ = Flow(axes_.I, options);
    if constexpr (reduced) {
      const Vec3<Scalar> a(problem_.reduced_axis());
      lab_ = quat::rotation_to_e3(a, axis_norm_);
      lab_identity_ = true;  // exactly 1, derivative parts included (a Jet a = e3 + ∂ must turn the frame)
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) lab_identity_ = lab_identity_ && is_exact_zero(Scalar(lab_(i, j) - Scalar(i == j)));
      two_axis_norm_ = Scalar(2) * axis_norm_;
      if constexpr (has_lever) {
        check_reduced_torque_lever(problem_, "lgi::Splitting");
        lever_ = two_axis_norm_ * axes_.to_principal(Vec3<Scalar>(problem_.reduced_torque_lever()));
      }
    }
  }

  /// x at time t in the internal coordinates (quaternion of A R Q, Π = Qᵀ J Ω) and its torque: one evaluation.
  Internal to_internal(const State<Scalar>& x, const Scalar& t) const {
    Internal y;
    const Mat3<Scalar> R = lab_identity_ ? x.R : Mat3<Scalar>(lab_ * x.R);
    y.q = quat::from_matrix(axes_.identity ? R : Mat3<Scalar>(R * axes_.Q));
    y.Pi = axes_.I.cwiseProduct(axes_.to_principal(x.Omega));
    y.M = torque(t, y.q);
    return y;
  }
  /// (R, Ω) of y in the body and laboratory frames of the problem.
  State<Scalar> to_state(const Internal& y) const {
    const Mat3<Scalar> Rp = quat::to_matrix(y.q);
    const Mat3<Scalar> R = axes_.identity ? Rp : Mat3<Scalar>(Rp * axes_.Q.transpose());
    return {lab_identity_ ? R : Mat3<Scalar>(lab_.transpose() * R),
            axes_.to_body(Vec3<Scalar>(y.Pi.cwiseQuotient(axes_.I)))};
  }
  /// Replaces the velocity, the attitude (and with it the torque of the next kick) untouched: the invariant
  /// projection's hook (integrators/projection.hpp) for the methods that are not symplectic.
  void set_omega(Internal& y, const Vec3<Scalar>& Omega) const {
    y.Pi = axes_.I.cwiseProduct(axes_.to_principal(Omega));
  }

  /// One step. In double, through the copy compiled for this machine's instruction set (core/scalar.hpp,
  /// LGI_DISPATCH_CLONES; same results bit for bit); step_inline is the step itself.
  LGI_FLATTEN StepStatus step(Internal& y, const Scalar& t, const Scalar& h) {
#if defined(LGI_DISPATCH_CLONES)
    if constexpr (std::is_same_v<Scalar, double>) return detail::dispatched_step(*this, y, t, h);
#endif
    return step_inline(y, t, h);
  }

  /// One step from t to t + h (this header's update): ok, or the flow's not_converged (DMV flows: Newton within
  /// max_iterations), or non_finite; y untouched unless ok. One torque evaluation a step; no allocation.
  /// Avx2: compiled into the AVX2 copy (core/integrator.hpp, detail::avx2_step); the same code either way.
  template <bool Avx2 = false>
  LGI_FLATTEN StepStatus step_inline(Internal& y, const Scalar& t, const Scalar& h) {
    using T = Scalar;
    const T half_h = T(0.5) * h;
    Quaternion<T> q = y.q;
    // Π_{n+1} = Π_n + ((½h M_n + ΔΠ) + ½h M_{n+1}), ΔΠ the flow's rotation of Π⁺ = Π_n + ½h M_n: Π is
    // rounded once per step, not after each kick and the flow (Π⁺ itself only feeds the flow).
    Vec3<T> dPi;
    Vec3<T> M1 = Vec3<T>::Zero();
    Vec3<T> Pi;
    if constexpr (P::has_torque) {
      const Vec3<T> kick = half_h * y.M;
      if (const StepStatus s = flow_.advance(q, Vec3<T>(y.Pi + kick), h, dPi); s != StepStatus::ok) return s;
      M1 = torque(t + h, q);
      Pi = y.Pi + ((kick + dPi) + half_h * M1);
    } else {
      if (const StepStatus s = flow_.advance(q, y.Pi, h, dPi); s != StepStatus::ok) return s;
      Pi = y.Pi + dPi;
    }
    // Π alone decides: q is finite whenever the flow's rotation is (a unit quaternion times a finite q),
    // and a non-finite rotation makes Π non-finite too (Π ← R(p)ᵀΠ, or the flow reports it), as does a
    // non-finite torque through the second kick (0·inf = NaN even at h = 0).
    if constexpr (std::is_arithmetic_v<T>) {  // one test: NaN and ±inf propagate through the sum
      const T sum = Pi(0) + Pi(1) + Pi(2);
      if (!(sum - sum == T(0))) return StepStatus::non_finite;
    } else if (!all_finite(q.w) || !all_finite(q.v) || !all_finite(Pi)) {
      return StepStatus::non_finite;
    }
    y.q = q;
    y.Pi = Pi;
    y.M = M1;
    return StepStatus::ok;
  }

  /// The problem, as copied at construction.
  const P& problem() const { return problem_; }
  /// The free-body flow (its principal moments and options).
  const Flow& flow() const { return flow_; }
  /// J's principal axes, the internal body frame.
  const PrincipalAxes<Scalar>& principal_axes() const { return axes_; }
  /// Newton updates (DMV flows), for the diagnostics the drivers print.
  std::int64_t newton_iterations() const {
    if constexpr (requires { flow_.counters(); })
      return flow_.counters().newton;
    else
      return 0;
  }

 private:
  static constexpr bool reduced = P::has_torque && ReducedAttitudeProblem<P>;
  /// A reduced torque that is a cross product M = Γ × v with a constant v (core/problem.hpp): the torque is
  /// then Γ_p × Qᵀv, one cross product with a vector rotated to principal axes once, where reduced_torque would
  /// (with a non-diagonal J) take Γ to the body frame and the torque back to principal axes every step.
  static constexpr bool has_lever = LeverTorqueProblem<P>;

  /// Principal-axis torque at the attitude q.
  Vec3<Scalar> torque(const Scalar& t, const Quaternion<Scalar>& q) const {
    if constexpr (!P::has_torque) {
      return Vec3<Scalar>::Zero();
    } else if constexpr (reduced) {
      // Γ_p = R(q)ᵀ A a = |a| R(q)ᵀ e3 = |a| × the third row of R(q) (unit q), 13 flops
      const Scalar x = q.v(0), y = q.v(1), z = q.v(2), w = q.w;
      if constexpr (has_lever) {
        // M_p = Γ_p × Qᵀv = G × lever_, Γ_p = 2|a| G, lever_ = 2|a| Qᵀv: 19 flops (2 fl(½ − s) = fl(1 − 2s))
        const Scalar g0 = x * z - w * y, g1 = y * z + w * x, g2 = Scalar(0.5) - (x * x + y * y);
        return Vec3<Scalar>(g1 * lever_(2) - g2 * lever_(1), g2 * lever_(0) - g0 * lever_(2),
                            g0 * lever_(1) - g1 * lever_(0));
      }
      const Vec3<Scalar> Gamma_p(two_axis_norm_ * (x * z - w * y), two_axis_norm_ * (y * z + w * x),
                                 axis_norm_ - two_axis_norm_ * (x * x + y * y));
      if (axes_.identity) return problem_.reduced_torque(Gamma_p);
      return axes_.to_principal(problem_.reduced_torque(axes_.to_body(Gamma_p)));
    } else {
      const Mat3<Scalar> Rp = quat::to_matrix(q);
      const Mat3<Scalar> R = axes_.identity ? Rp : Mat3<Scalar>(Rp * axes_.Q.transpose());
      return axes_.to_principal(body_torque(problem_, t, R));  // lab_ = 1 here
    }
  }

  P problem_;
  PrincipalAxes<Scalar> axes_;
  Flow flow_;
  /// Internal laboratory frame: R_internal = A R Q, with A = 1 unless the torque depends on R only through
  /// Γ = Rᵀa (reduced); then A is a fixed rotation with A a = |a| e3 (A = 1 exactly when a = |a| e3, the
  /// usual vertical axis), so that Γ_p = |a| R(q)ᵀ e3 is read off q in 13 flops (torque()).
  Mat3<Scalar> lab_ = Mat3<Scalar>::Identity();
  bool lab_identity_ = true;
  Scalar axis_norm_ = Scalar(1), two_axis_norm_ = Scalar(2);
  Vec3<Scalar> lever_ = Vec3<Scalar>::Zero();  ///< 2|a| Qᵀv (has_lever)
};

/// split_axes: kicks + five principal-axis rotations (explicit, symplectic, order 2).
template <AttitudeTorqueProblem P>
using SplitAxes = Splitting<AxisRotations<typename P::Scalar>, P>;
/// split_dmv: kicks + the discrete Moser–Veselov flow (the LGVI's map; symplectic, order 2).
template <AttitudeTorqueProblem P>
using SplitDmv = Splitting<Dmv<typename P::Scalar>, P>;
/// split_dmv4: kicks + the preprocessed DMV of order 4 on the free body (order 2 with a torque).
template <AttitudeTorqueProblem P>
using SplitDmv4 = Splitting<PreprocessedDmv<typename P::Scalar, 2>, P>;
/// split_dmv6: kicks + the preprocessed DMV of order 6 on the free body (order 2 with a torque).
template <AttitudeTorqueProblem P>
using SplitDmv6 = Splitting<PreprocessedDmv<typename P::Scalar, 3>, P>;
/// split_dmv8: kicks + the preprocessed DMV of order 8 on the free body (order 2 with a torque).
template <AttitudeTorqueProblem P>
using SplitDmv8 = Splitting<PreprocessedDmv<typename P::Scalar, 4>, P>;
/// split_dmv10: kicks + the preprocessed DMV of order 10 on the free body (order 2 with a torque).
template <AttitudeTorqueProblem P>
using SplitDmv10 = Splitting<PreprocessedDmv<typename P::Scalar, 5>, P>;

}  // namespace lgi
