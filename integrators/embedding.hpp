/// \file
/// lgi/integrators/embedding.hpp — non-geometric baselines inside the framework: classical Runge–Kutta
/// methods (RK4, DOP853) on an embedding of SO(3) × R³ in a vector space, with and without renormalisation.
///
/// They are here so that comparisons are honest: same problems, drivers, outputs and tests as the Lie-group
/// methods, and no claim they do not earn. Two embeddings:
///
/// ~~~{.unparsed}
///   quaternion  y = (q, Ω) ∈ R⁴ × R³, q = (s, v):  q' = ½ q ⊗ (0, Ω) = ½ (−v·Ω, sΩ + v × Ω),
///               R(q) = I + 2s hat(v) + 2 hat(v)²  (a rotation only when |q| = 1)
///   matrix      y = (R, Ω) ∈ R⁹ × R³ (all nine entries of R):  R' = R hat(Ω)
/// ~~~
///
/// and in both Ω' = J⁻¹((JΩ) × Ω + M(t, R)), the torque taken at the (not exactly orthogonal) R of the stage
/// — for a ReducedAttitudeProblem through Γ = Rᵀa = a − 2s v × a + 2 v × (v × a) (quaternion) or Rᵀa
/// (matrix). The method is the explicit Runge–Kutta method of the tableau applied to y as a vector.
///
/// Renormalisation (the "_renorm" variants), after every step and every dense output:
/// ~~~{.unparsed}
///   quaternion  q ← q/|q|
///   matrix      R ← the orthogonal polar factor of R (the nearest orthogonal matrix in the Frobenius norm,
///               Higham, SIAM J. Sci. Stat. Comput. 7 (1986) 1160), by the Newton–Schulz iteration
///               X ← ½ X (3I − XᵀX) (the first-order member of Björck & Bowie, SIAM J. Numer. Anal. 8 (1971)
///               358; quadratically convergent for ‖XᵀX − I‖ < 1; equation numbers not confirmed), until
///               ‖XᵀX − I‖_max ≤ 4ε (one or two iterations; at most 8; Jets one more). No SVD: Jets.
/// ~~~
///
/// Traits. Order: the tableau's. Not symplectic, not symmetric, energy and momentum drift like any RK method.
/// exact_on_group = false for all, renormalised or not: the stages leave SO(3) (the torque is evaluated at
/// non-orthogonal attitudes) and the step's result is off the group by its local error before the projection
/// puts it back; the renormalised variants keep ‖RᵀR − I‖ at round-off after each step, which the tests
/// measure and report, but that is a property of the post-processing, not of the method. The non-renormalised
/// variants leave the group by the accumulated truncation error (|q| ≠ 1, RᵀR ≠ I) — the measured contrast.
/// The DOP853 variants have its embedded error estimate and dense output (adaptive with rtol/atol: the error
/// norm is Hairer's, over the 7 or 12 components of y, sc_i = atol + rtol·max(|y_i|, |y1_i|)).
/// References: the methods, Hairer, Nørsett, Wanner, Solving ODEs I, 2nd ed., §II.1 and §II.5 (DOP853);
/// quaternion kinematics, e.g. Solà, arXiv:1711.02508, eq. (111) (not confirmed).
#pragma once

#include "../core/state_io.hpp"
#include "../core/inertia.hpp"
#include "../core/integrator.hpp"
#include "../core/problem.hpp"
#include "../core/so3.hpp"
#include "../core/state.hpp"
#include "butcher_tableaus.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string_view>
#include <type_traits>
#include <utility>

namespace lgi {

/// The quaternion embedding's coordinates: q = (s, v1, v2, v3) and Ω.
template <class T>
struct QuatState {
  Eigen::Matrix<T, 4, 1> q;  ///< (s, v), not necessarily unit
  Vec3<T> Omega;             ///< body angular velocity
  LGI_NUMBERS(q, Omega)
};

/// The embedding baselines' helpers (quaternion and polar-factor maps) and names.
namespace embedding {

/// I + 2s hat(v) + 2 hat(v)² (a rotation when |q| = 1).
template <class T>
Mat3<T> rotation_of(const Eigen::Matrix<T, 4, 1>& q) {
  const Vec3<T> v = q.template tail<3>();
  return so3::rodrigues(v, T(2) * q(0), T(2));
}

/// Rᵀa for R = rotation_of(q): a − 2s v × a + 2 v × (v × a).
template <class T>
Vec3<T> rotate_back(const Eigen::Matrix<T, 4, 1>& q, const Vec3<T>& a) {
  const Vec3<T> v = q.template tail<3>();
  const Vec3<T> va = v.cross(a);
  return a - T(2) * q(0) * va + T(2) * v.cross(va);
}

/// The unit quaternion of a rotation (Shepperd's method: the largest of 1 + tr R, 1 + 2R_ii − tr R chosen by
/// value), with s ≥ 0.
template <class T>
Eigen::Matrix<T, 4, 1> quaternion_of(const Mat3<T>& R) {
  using std::sqrt;
  const T tr = R.trace();
  const double c[4] = {static_cast<double>(value_of(tr)), static_cast<double>(value_of(R(0, 0))),
                       static_cast<double>(value_of(R(1, 1))), static_cast<double>(value_of(R(2, 2)))};
  int k = 0;
  for (int i = 1; i < 4; ++i)
    if (c[i] > c[k]) k = i;
  Eigen::Matrix<T, 4, 1> q;
  if (k == 0) {
    const T r = sqrt(T(1) + tr);  // 2s
    q << r / T(2), (R(2, 1) - R(1, 2)) / (T(2) * r), (R(0, 2) - R(2, 0)) / (T(2) * r), (R(1, 0) - R(0, 1)) / (T(2) * r);
  } else {
    const int i = k - 1, j = (i + 1) % 3, l = (i + 2) % 3;
    const T r = sqrt(T(1) + R(i, i) - R(j, j) - R(l, l));  // 2|v_i|
    q(0) = (R(l, j) - R(j, l)) / (T(2) * r);
    q(1 + i) = r / T(2);
    q(1 + j) = (R(j, i) + R(i, j)) / (T(2) * r);
    q(1 + l) = (R(l, i) + R(i, l)) / (T(2) * r);
    if (value_of(q(0)) < 0) q = -q;
  }
  return q;
}

/// X ← the orthogonal polar factor of X, Newton–Schulz iteration (see the header). Returns false, X
/// unchanged, when the iteration does not reach a rotation: max |XᵀX − I| ≥ 1 (or NaN) at some iterate,
/// where it need not converge, or still above 1e-12 after its 8 updates. No rotation is produced then, and
/// the caller must not pretend otherwise (the steps report StepStatus::not_converged).
template <class T>
bool polar_factor(Mat3<T>& X) {
  const auto deviation = [](const Mat3<T>& Y, Mat3<T>& E) {
    E = Y.transpose() * Y;
    E.diagonal().array() -= T(1);  // YᵀY − I
    return static_cast<double>(value_of(E.cwiseAbs().maxCoeff()));
  };
  Mat3<T> Y = X, E;
  int extra = is_dual_v<T> ? 1 : 0;
  for (int k = 0; k < 8 + extra; ++k) {
    const double size = deviation(Y, E);
    if (!(size < 1)) return false;
    if (size <= 4 * std::numeric_limits<double>::epsilon()) {
      if (extra == 0) {
        X = Y;
        return true;
      }
      --extra;
    }
    Y -= T(0.5) * (Y * E);  // ½ Y (3I − YᵀY) = Y − ½ Y (YᵀY − I)
  }
  if (!(deviation(Y, E) < 1e-12)) return false;
  X = Y;
  return true;
}

/// The orthogonal polar factor of X, which must satisfy max |XᵀX − I| < 1 (else X is returned unchanged).
template <class T>
Mat3<T> nearest_rotation(const Mat3<T>& X0) {
  Mat3<T> X = X0;
  polar_factor(X);
  return X;
}

/// The embedding a baseline steps in (the header): quaternion, y = (q, Ω) ∈ R⁷; matrix, y = (R, Ω) ∈ R¹².
enum class Chart { quaternion, matrix };

/// A baseline's scene name and title.
struct Info {
  std::string_view name;   ///< the scene name
  std::string_view title;  ///< a one-line description
};
/// The names and titles of the eight baselines (the aliases at the end of this header).
///@{
inline constexpr Info rk4_quat{"rk4_quat", "Baseline: classical RK4 on the quaternion + omega (not renormalised)"};
inline constexpr Info rk4_quat_renorm{"rk4_quat_renorm",
                                      "Baseline: classical RK4 on the quaternion + omega, q normalised each step"};
inline constexpr Info rk4_mat{"rk4_mat", "Baseline: classical RK4 on the 9 entries of R + omega (not renormalised)"};
inline constexpr Info rk4_mat_renorm{"rk4_mat_renorm",
                                     "Baseline: classical RK4 on the 9 entries of R + omega, polar factor each step"};
inline constexpr Info dop853_quat{"dop853_quat", "Baseline: DOP853 on the quaternion + omega (not renormalised)"};
inline constexpr Info dop853_quat_renorm{"dop853_quat_renorm",
                                         "Baseline: DOP853 on the quaternion + omega, q normalised each step"};
inline constexpr Info dop853_mat{"dop853_mat", "Baseline: DOP853 on the 9 entries of R + omega (not renormalised)"};
inline constexpr Info dop853_mat_renorm{"dop853_mat_renorm",
                                        "Baseline: DOP853 on the 9 entries of R + omega, polar factor each step"};

///@}

}  // namespace embedding

/// The explicit Runge–Kutta method of Tableau on the embedding C of SO(3) × R³ as a Stepper on problem P (this
/// header), renormalised after every step or not: a non-geometric baseline, not exact on the group.
template <embedding::Chart C, const auto& Tableau, bool Renormalise, const embedding::Info& Name, RigidBodyProblem P>
class EmbeddedRk {
 public:
  using Problem = P;                  ///< the problem type
  using Scalar = typename P::Scalar;  ///< its scalar
  /// (q, Ω) or (R, Ω), the embedding's coordinates.
  using Internal = std::conditional_t<C == embedding::Chart::quaternion, QuatState<Scalar>, State<Scalar>>;
  static constexpr bool embedded = tableaus::is_embedded_v<std::remove_cvref_t<decltype(Tableau)>>;  ///< an embedded pair: adaptive steps

 private:
  static constexpr int N = C == embedding::Chart::quaternion ? 7 : 12;
  using Vec = Eigen::Matrix<Scalar, N, 1>;
  static constexpr bool reduced = P::has_torque && ReducedAttitudeProblem<P>;
  static constexpr int dense_stages = tableaus::dense_stages(Tableau);
  static constexpr bool has_second_estimate = tableaus::has_second_estimate(Tableau);
  static constexpr int update_stages = tableaus::update_stages(Tableau);  // the stages a fixed step needs
  using Weights = tableaus::Weights;

 public:
  /// The method's traits: the tableau's order; not symplectic, not symmetric, not exact on the group.
  static constexpr MethodTraits traits{
      .name = Name.name,
      .title = Name.title,
      .order = Tableau.order,
      .symplectic = false,
      .symmetric = false,
      .explicit_method = true,
      .exact_on_group = false,
      .preserves_momentum = false,
      .reference = "Runge-Kutta on the embedding (baseline); Hairer-Norsett-Wanner I, sec. II.1, II.5",
      .options = embedded ? std::array<std::string_view, 6>{"rtol", "atol", "projection"}
                          : std::array<std::string_view, 6>{"projection"},
  };
  /// The embedded pair's control order (0 for a tableau without one).
  static constexpr int control_order = [] {
    if constexpr (embedded) return Tableau.control_order; else return 0;
  }();

  /// Copies the problem; options: rtol and atol of adaptive steps (std::invalid_argument from StepperOptions::check).
  explicit EmbeddedRk(const P& problem, const StepperOptions& options = {})
      : problem_(problem), J_(problem.inertia), rtol_(options.rtol), atol_(options.atol) {
    options.check();
  }

  /// x in the embedding's coordinates (the quaternion of R with s ≥ 0, or R itself).
  Internal to_internal(const State<Scalar>& x, const Scalar&) const {
    if constexpr (C == embedding::Chart::quaternion)
      return {embedding::quaternion_of(x.R), x.Omega};
    else
      return x;
  }
  /// (R, Ω) of y: R(q) for the quaternion (a rotation only when |q| = 1), the nine entries as they are otherwise.
  State<Scalar> to_state(const Internal& y) const {
    if constexpr (C == embedding::Chart::quaternion)
      return {embedding::rotation_of(y.q), y.Omega};
    else
      return y;
  }

  /// One step from t to t + h: ok, non_finite, or (renormalised matrix chart) not_converged when the result is too
  /// far from SO(3) for its polar factor; y untouched unless ok. Cost: one torque per stage; no allocation.
  LGI_FLATTEN StepStatus step(Internal& y, const Scalar& t, const Scalar& h) {
    std::array<Vec, Tableau.stages> k;
    const Vec y0 = pack(y);
    [&]<int... I>(std::integer_sequence<int, I...>) {
      (stage<I>(y0, t, h, k), ...);
    }(std::make_integer_sequence<int, update_stages>{});
    Vec y1 = y0 + h * weighted<Weights::b, update_stages>(k);
    return finish(y1, y);
  }

  /// What a step leaves for its dense output: its start, time, size and stage derivatives.
  struct Dense {
    Vec y0;                           ///< the step's start
    ///@{
    /// Its time and size.
    Scalar t, h;
    ///@}
    std::array<Vec, dense_stages> k;  ///< the stage derivatives (the dense-only ones once extended)
    bool extended = false;            ///< the dense-only stages have been computed
  };

  /// One trial step (embedded pairs): y1 and the pair's scaled error norm (≤ 1: accept); status as step.
  LGI_FLATTEN StepStatus attempt(const Internal& y, const Scalar& t, const Scalar& h, Internal& y1, double& error,
                                 Dense& d) const
    requires embedded
  {
    d.y0 = pack(y);
    d.t = t;
    d.h = h;
    d.extended = false;
    [&]<int... I>(std::integer_sequence<int, I...>) {
      (stage<I>(d.y0, t, h, d.k), ...);
    }(std::make_integer_sequence<int, Tableau.stages>{});
    const Vec yn = d.y0 + h * weighted<Weights::b, Tableau.stages>(d.k);
    const Vec err5 = h * weighted<Weights::e, Tableau.stages>(d.k);
    const auto scaled = [&](const Vec& e) {
      double s = 0;
      for (int i = 0; i < N; ++i) {
        const double sc = atol_ + rtol_ * std::max(std::abs(static_cast<double>(value_of(d.y0[i]))),
                                                   std::abs(static_cast<double>(value_of(yn[i]))));
        const double r = static_cast<double>(value_of(e[i])) / sc;
        s += r * r;
      }
      return s;
    };
    const double s5 = scaled(err5);
    if constexpr (has_second_estimate) {
      const double deno = s5 + 0.01 * scaled(Vec(h * weighted<Weights::e3, Tableau.stages>(d.k)));
      error = deno > 0 ? s5 / std::sqrt(N * deno) : 0.0;
    } else {
      error = std::sqrt(s5 / N);
    }
    if (!std::isfinite(error)) error = std::numeric_limits<double>::infinity();
    const StepStatus status = finish(yn, y1);
    if (status != StepStatus::ok) error = std::numeric_limits<double>::infinity();
    return status;
  }

  /// The state at t + θh of the step that filled d (θ ∈ [0, 1]), renormalised in the _renorm variants.
  LGI_FLATTEN Internal dense_output(Dense& d, const Scalar& theta) const
    requires embedded
  {
    if (!d.extended) {
      [&]<int... I>(std::integer_sequence<int, I...>) {
        (stage<Tableau.stages + I>(d.y0, d.t, d.h, d.k), ...);
      }(std::make_integer_sequence<int, dense_stages - Tableau.stages>{});
      d.extended = true;
    }
    Vec sum = Vec::Zero();
    for (int i = 0; i < dense_stages; ++i) {
      Scalar p = Scalar(Tableau.dense[i][Tableau.dense_degree - 1]);
      for (int m = Tableau.dense_degree - 2; m >= 0; --m) p = p * theta + Scalar(Tableau.dense[i][m]);
      sum += (p * theta) * d.k[i];
    }
    Vec y = d.y0 + d.h * sum;
    // Within an accepted step the interpolant stays near SO(3); were it not, y is returned unprojected and
    // the caller's finiteness/orthogonality figures show it.
    if constexpr (Renormalise) static_cast<void>(renormalise(y));
    return unpack(y);
  }

  /// The relative error tolerance of adaptive steps.
  double rtol() const { return rtol_; }
  /// The absolute error tolerance of adaptive steps.
  double atol() const { return atol_; }
  /// The problem, as copied at construction.
  const P& problem() const { return problem_; }

 private:
  static Vec pack(const Internal& y) {
    Vec v;
    if constexpr (C == embedding::Chart::quaternion) {
      v.template head<4>() = y.q;
      v.template tail<3>() = y.Omega;
    } else {
      v.template head<9>() = Eigen::Map<const Eigen::Matrix<Scalar, 9, 1>>(y.R.data());
      v.template tail<3>() = y.Omega;
    }
    return v;
  }
  static Internal unpack(const Vec& v) {
    Internal y;
    if constexpr (C == embedding::Chart::quaternion) {
      y.q = v.template head<4>();
    } else {
      Eigen::Map<Eigen::Matrix<Scalar, 9, 1>>(y.R.data()) = v.template head<9>();
    }
    y.Omega = v.template tail<3>();
    return y;
  }
  /// false: the matrix is too far from SO(3) for its polar factor (the step failed; see polar_factor).
  static bool renormalise(Vec& v) {
    if constexpr (C == embedding::Chart::quaternion) {
      v.template head<4>() /= v.template head<4>().norm();  // |q| = 0 gives NaN: finish() reports it
      return true;
    } else {
      Mat3<Scalar> R = Eigen::Map<const Mat3<Scalar>>(v.data());
      if (!embedding::polar_factor(R)) return false;
      Eigen::Map<Mat3<Scalar>>(v.data()) = R;
      return true;
    }
  }
  static StepStatus finish(Vec y1, Internal& y) {
    if constexpr (Renormalise) {
      if (!renormalise(y1)) return all_finite(y1) ? StepStatus::not_converged : StepStatus::non_finite;
    }
    if (!all_finite(y1)) return StepStatus::non_finite;
    y = unpack(y1);
    return StepStatus::ok;
  }

  template <Weights W, int M, std::size_t K>
  static Vec weighted(const std::array<Vec, K>& k) {
    return tableaus::weighted_sum<Tableau, W, M>(k);
  }

  /// The vector field on the embedding.
  Vec field(const Scalar& t, const Vec& y) const {
    Vec d;
    const Vec3<Scalar> W = y.template tail<3>();
    Vec3<Scalar> M = Vec3<Scalar>::Zero();
    if constexpr (C == embedding::Chart::quaternion) {
      const Eigen::Matrix<Scalar, 4, 1> q = y.template head<4>();
      const Vec3<Scalar> v = q.template tail<3>();
      d(0) = Scalar(-0.5) * v.dot(W);
      d.template segment<3>(1) = Scalar(0.5) * (q(0) * W + v.cross(W));
      if constexpr (reduced)
        M = problem_.reduced_torque(embedding::rotate_back(q, Vec3<Scalar>(problem_.reduced_axis())));
      else if constexpr (P::has_torque)
        M = body_torque(problem_, t, embedding::rotation_of(q), W);
    } else {
      const Mat3<Scalar> R = Eigen::Map<const Mat3<Scalar>>(y.data());
      Eigen::Map<Mat3<Scalar>>(d.data()) = R * so3::hat(W);
      if constexpr (reduced)
        M = problem_.reduced_torque(Vec3<Scalar>(R.transpose() * problem_.reduced_axis()));
      else if constexpr (P::has_torque)
        M = body_torque(problem_, t, R, W);
    }
    d.template tail<3>() = J_.solve(Vec3<Scalar>(J_.apply(W).cross(W) + M));
    return d;
  }

  template <int I, std::size_t K>
  void stage(const Vec& y0, const Scalar& t, const Scalar& h, std::array<Vec, K>& k) const {
    if constexpr (I == 0) {
      k[0] = field(t, y0);
    } else {
      Vec s = Vec::Zero();
      [&]<int... J>(std::integer_sequence<int, J...>) {
        ([&] {
          if constexpr (Tableau.a[I][J] != 0) s += Scalar(Tableau.a[I][J]) * k[J];
        }(), ...);
      }(std::make_integer_sequence<int, I>{});
      k[I] = field(t + Scalar(Tableau.c[I]) * h, Vec(y0 + h * s));
    }
  }

  P problem_;
  Inertia<Scalar> J_;
  double rtol_, atol_;
};

/// rk4_quat: classical RK4 on (q, Ω), not renormalised.
template <RigidBodyProblem P>
using Rk4Quat = EmbeddedRk<embedding::Chart::quaternion, tableaus::classical_rk4, false, embedding::rk4_quat, P>;
/// rk4_quat_renorm: classical RK4 on (q, Ω), q ← q/|q| after every step.
template <RigidBodyProblem P>
using Rk4QuatRenorm = EmbeddedRk<embedding::Chart::quaternion, tableaus::classical_rk4, true, embedding::rk4_quat_renorm, P>;
/// rk4_mat: classical RK4 on the nine entries of R and Ω, not renormalised.
template <RigidBodyProblem P>
using Rk4Mat = EmbeddedRk<embedding::Chart::matrix, tableaus::classical_rk4, false, embedding::rk4_mat, P>;
/// rk4_mat_renorm: classical RK4 on (R, Ω), R ← its polar factor after every step.
template <RigidBodyProblem P>
using Rk4MatRenorm = EmbeddedRk<embedding::Chart::matrix, tableaus::classical_rk4, true, embedding::rk4_mat_renorm, P>;
/// dop853_quat: DOP853 on (q, Ω), not renormalised; adaptive with dense output.
template <RigidBodyProblem P>
using Dop853Quat = EmbeddedRk<embedding::Chart::quaternion, tableaus::dop853, false, embedding::dop853_quat, P>;
/// dop853_quat_renorm: DOP853 on (q, Ω), renormalised; adaptive with dense output.
template <RigidBodyProblem P>
using Dop853QuatRenorm = EmbeddedRk<embedding::Chart::quaternion, tableaus::dop853, true, embedding::dop853_quat_renorm, P>;
/// dop853_mat: DOP853 on (R, Ω), not renormalised; adaptive with dense output.
template <RigidBodyProblem P>
using Dop853Mat = EmbeddedRk<embedding::Chart::matrix, tableaus::dop853, false, embedding::dop853_mat, P>;
/// dop853_mat_renorm: DOP853 on (R, Ω), renormalised; adaptive with dense output.
template <RigidBodyProblem P>
using Dop853MatRenorm = EmbeddedRk<embedding::Chart::matrix, tableaus::dop853, true, embedding::dop853_mat_renorm, P>;

}  // namespace lgi
