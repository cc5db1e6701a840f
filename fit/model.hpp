/// \file
/// lgi/fit/model.hpp — the unknowns of a fit, their derivatives through the integrator, and the ceres cost
/// functions.
///
/// Unknowns (scene names; a fit lists any subset, the rest keep the base scene's values):
/// ~~~{.unparsed}
///   initial.omega    Ω0 ∈ R³                      Euclidean; components may be fixed or bounded
///   initial.R        R0 ∈ SO(3)                   SO3Manifold, R0 ⊞ δ = R0 Exp(δ), δ ∈ R³ (fit/manifolds.hpp)
///   problem.inertia  principal moments I_k > 0    stored as ℓ_k = log I_k about principal axes Q that stay those
///                                                 of the base scene's tensor: J = Q diag(e^ℓ) Qᵀ
///   problem.b        b ≥ 0                        Euclidean, lower bound 0 unless a bound is given
///   problem.z0       z0 ∈ S²                      S2Manifold
///   period           T (periodic orbits)          the step is T/N for a fixed N
///   phase            φ (periodic orbits, heavy top): R(T) = Exp(φ k) R0
///   problem.damping      c ≥ 0 of C = c I         a problem with damping (problems/torqued_body.hpp); the base
///                                                 scene's C must be c I (or absent: c starts at 0)
///   problem.body_torque  M_body ∈ R³              a constant body-frame torque (a disturbance), Euclidean
///   problem.lab_torque   M_lab ∈ R³               a constant laboratory-frame torque, Euclidean
///   problem.k_R          k_R ≥ 0                  the attitude controller's gains (the scene's attitude_control)
///   problem.k_Omega      k_Ω ≥ 0
///   problem.rotor_friction  c_i ≥ 0, one per rotor    a gyrostat's (problems/gyrostat.hpp) rotor friction
///   problem.wheel_k_R       k_R ≥ 0                  a gyrostat's wheel PD law's gains (the scene's wheel_control)
///   problem.wheel_k_Omega   k_Ω ≥ 0
/// ~~~
///
/// Problems: every RigidBodyProblem, and the gyrostat (problems/gyrostat.hpp), whose body terms (inertia with the
/// rotors locked, b, z0, damping, constant torques, attitude_control gains) are its `body`'s and whose initial state
/// (R0, Ω0) takes the rotors at their scene rates; its steppers (integrators/gyrostat.hpp) map (R, Ω) to (R, m, h).
///
/// Derivatives. Ceres asks for ∂r/∂x in the ambient coordinates x of each parameter block (9 for R0, 3 for z0)
/// and multiplies them by the manifold's PlusJacobian P. Here the derivatives are carried by ceres::Jet in the
/// tangent coordinates instead (R0 Exp(δ) with δ a Jet of value 0; fewer Jet components: 3 instead of 9 for R0)
/// and handed to ceres as J_amb = J_tan (PᵀP)⁻¹ Pᵀ, which gives J_amb P = J_tan exactly (P has full column rank).
/// Jets are of a fixed size N (explicitly instantiated; compile time) and the free tangent coordinates are
/// covered in passes of N when there are more.
///
/// One integration per trajectory. Every observation is its own residual block (so that robust losses act on
/// each one), but all of them read one integration of the trajectory through every observation time, cached by
/// the parameter values (bit for bit): a new point of the solver costs one run in double, plus one run in
/// `Jet<N>` per pass when derivatives are asked for. A run that fails — a step status other than ok (Newton not
/// converged, non-finite state), or any non-finite value or derivative (lgi::all_finite checks the derivative
/// parts, which ceres::isfinite does not) — makes the cost functions return false, so Ceres rejects the step.
#pragma once

#include <lgi/core/driver.hpp>
#include <lgi/core/integrator.hpp>
#include <lgi/core/problem.hpp>
#include <lgi/core/so3.hpp>
#include <lgi/core/state.hpp>

#include "manifolds.hpp"
#include "observations.hpp"

#include <ceres/cost_function.h>
#include <ceres/jet.h>
#include <ceres/manifold.h>
#include <ceres/problem.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace lgi::fit {

/// One unknown of a fit (see the header for the names).
struct Unknown {
  /// An unnamed unknown (Model rejects it: the name must be one of block_info's).
  Unknown() = default;
  /// The unknown `name_` with its fixed components and bounds (checked by Model, FitInputError naming unknowns[i]).
  Unknown(std::string name_, std::vector<int> fixed_ = {}, std::vector<double> lower_ = {}, std::vector<double> upper_ = {})
      : name(std::move(name_)), fixed(std::move(fixed_)), lower(std::move(lower_)), upper(std::move(upper_)) {}

  std::string name;                  ///< a scene name of the header's table, e.g. "initial.omega"
  std::vector<int> fixed;            ///< components held at their initial value (initial.omega, problem.inertia)
  ///@{
  /// Bounds, empty or one per component (problem.inertia: on the moments); ±infinity for none. Not for initial.R,
  /// problem.z0.
  std::vector<double> lower, upper;
  ///@}
};

/// The parameter blocks of a fit, one per unknown of the header's table, in this order.
enum class Block : int {
  omega = 0, R, inertia, b, z0, period, phase, damping, body_torque, lab_torque, k_R, k_Omega,
  rotor_friction, wheel_k_R, wheel_k_Omega
};
/// The number of Block values.
inline constexpr int block_count = 15;
/// The most components a block has in the tangent space (problem.rotor_friction: one per rotor slot).
inline constexpr int max_block_components = 6;

/// A parameter block's scene name and sizes.
struct BlockInfo {
  std::string_view name;  ///< the unknown's scene name
  int ambient;  ///< doubles ceres stores
  int tangent;  ///< dimension of the manifold
  bool euclidean;  ///< R^n with the identity as its manifold (components may be fixed, bounds allowed)
};
/// BlockInfo of every Block, indexed by the Block's value.
inline constexpr std::array<BlockInfo, block_count> block_info{{
    {"initial.omega", 3, 3, true},
    {"initial.R", 9, 3, false},
    {"problem.inertia", 3, 3, true},
    {"problem.b", 1, 1, true},
    {"problem.z0", 3, 2, false},
    {"period", 1, 1, true},
    {"phase", 1, 1, true},
    {"problem.damping", 1, 1, true},
    {"problem.body_torque", 3, 3, true},
    {"problem.lab_torque", 3, 3, true},
    {"problem.k_R", 1, 1, true},
    {"problem.k_Omega", 1, 1, true},
    {"problem.rotor_friction", max_block_components, max_block_components, true},
    {"problem.wheel_k_R", 1, 1, true},
    {"problem.wheel_k_Omega", 1, 1, true},
}};

/// The unknowns' names, comma-separated (for messages).
inline std::string known_unknowns() {
  std::string s;
  for (const BlockInfo& b : block_info) s += (s.empty() ? "" : ", ") + std::string(b.name);
  return s;
}

/// Periodic orbits: what "returns to itself" means (the symmetry of the problem).
enum class PeriodicSymmetry {
  automatic,   ///< body_omega for a torque-free problem, about_k for a problem with a vertical k, else none
  none,        ///< R(T) = R0, Ω(T) = Ω0
  about_k,     ///< R(T) = Exp(φ k) R0, Ω(T) = Ω0 (heavy tops: rotations about the vertical k are a symmetry)
  body_omega,  ///< Ω(T) = Ω0 only (free body: every rotation of the laboratory is a symmetry)
};

/// True when P is a body with rotors (problems/gyrostat.hpp): its body terms are its member `body`'s, and its rotors'
/// friction and wheel gains can be unknowns.
template <class P>
inline constexpr bool is_gyrostat_v = requires(P p) { p.body; p.rotors; p.rotor_count; p.wheel_control; };
/// The body whose terms the unknowns set: a gyrostat's `body`, else the problem itself.
template <class P>
constexpr auto& body_of(P& problem) {
  if constexpr (is_gyrostat_v<std::remove_const_t<P>>) return problem.body;
  else return problem;
}
/// The type of body_of(P&).
template <class P>
using body_t = std::remove_cvref_t<decltype(body_of(std::declval<P&>()))>;
/// The problems a fit integrates: the RigidBodyProblems, and the gyrostat.
template <class P>
concept FitProblem = RigidBodyProblem<P> || is_gyrostat_v<P>;

/// True when problem P's body has a member b (then problem.b can be an unknown).
template <class P>
inline constexpr bool has_b_v = requires(body_t<P> p) { p.b; };
/// True when problem P's body has a member z0 (then problem.z0 can be an unknown).
template <class P>
inline constexpr bool has_z0_v = requires(body_t<P> p) { p.z0; };
/// True when problem P's body has a damping matrix C with its flag (then problem.damping can be an unknown).
template <class P>
inline constexpr bool has_damping_v = requires(body_t<P> p) { p.damping; p.has_damping; };
/// True when problem P's body has constant body- and laboratory-frame torques with their flag (problem.body_torque,
/// problem.lab_torque).
template <class P>
inline constexpr bool has_constant_torque_v = requires(body_t<P> p) { p.body_torque; p.lab_torque; p.has_constant; };
/// True when problem P's body has an attitude controller's gains with its flag (problem.k_R, problem.k_Omega).
template <class P>
inline constexpr bool has_gains_v = requires(body_t<P> p) { p.k_R; p.k_Omega; p.has_control; };
/// True when problem P has a vertical k (the about_k symmetry of periodic orbits; not a gyrostat's).
template <class P>
inline constexpr bool has_k_v = requires(P p) { p.k; };
/// True when P declares itself torque-free (a periodic orbit's automatic symmetry is then body_omega).
template <class P>
inline constexpr bool torque_free_v = [] {
  if constexpr (requires { P::has_torque; }) return !P::has_torque;
  else return false;
}();

/// What a Model fits: observations (residuals at the observation times) or a periodic orbit (one residual).
enum class Mode { observations, periodic };

/// The integration and the kind of a fit.
struct ModelOptions {
  Mode mode = Mode::observations;  ///< observations or periodic
  double dt = 0;                ///< observations: the fixed step
  double t_end = -1;            ///< observations: times must lie in [0, t_end] (< 0: no upper limit but the data's)
  int steps = 0;                ///< periodic: the number of steps over the period
  StepperOptions stepper;       ///< the method's options (fixed steps: rtol = atol = 0)
  PeriodicSymmetry symmetry = PeriodicSymmetry::automatic;  ///< periodic: what "returns to itself" means
  /// After this instant every integration stops at its next monitor call (every 1024 steps) and its residual
  /// evaluation fails: a wall-clock budget that a long arc cannot overrun by more than 1024 steps.
  std::chrono::steady_clock::time_point deadline = std::chrono::steady_clock::time_point::max();
};

/// A fit of problem P integrated by Method (a Stepper template, fixed steps) with Jets of N derivative components:
/// the unknowns' values, their manifolds and bounds, and the cost functions (the header). It owns its parameter
/// values, manifolds and the cached trajectory; not copyable. The cost functions refer to it: it must outlive the
/// ceres::Problem. Concurrent evaluations of the observation costs serialise on mutex().
template <template <class> class Method, FitProblem P, int N>
class Model {
 public:
  using Jet = ceres::Jet<double, N>;     ///< the Jet of a derivative pass (N tangent coordinates)
  using Jet12 = ceres::Jet<double, 12>;  ///< the Jet of an observation residual: d/d(vec R, Ω)
  static_assert(N >= 1);

  /// The problem, initial state, period and phase of a point of the fit, in scalar T.
  template <class T>
  struct Seeded {
    rebind_problem_t<P, T> problem;  ///< the base problem with the unknowns' values
    State<T> x0;                     ///< the initial state
    T period;                        ///< periodic: T (else the stored 0)
    T phase;                         ///< periodic, about_k: φ (else the stored 0)
  };

  /// Validates everything (FitInputError naming the field); period and phase are the periodic guesses.
  Model(const P& problem, const State<double>& initial, std::span<const Unknown> unknowns,
        std::span<const Observation> observations, const ModelOptions& options, double period = 0, double phase = 0)
      : base_(problem), options_(options), observations_(observations.begin(), observations.end()) {
    check_options();
    if (!initial.Omega.allFinite()) throw FitInputError("initial.omega", "entries must be finite numbers");
    if (!detail::is_rotation(initial.R))
      throw FitInputError("initial.R", "not a rotation matrix (|R^T R - I| > 1e-9 or det R <= 0)");
    // The nearest rotation (polar factor), as the scene loader does.
    const Eigen::JacobiSVD<Mat3<double>> svd(initial.R, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Mat3<double> R0 = svd.matrixU() * svd.matrixV().transpose();
    values_[idx(Block::omega)].assign(initial.Omega.data(), initial.Omega.data() + 3);
    values_[idx(Block::R)].assign(R0.data(), R0.data() + 9);
    // Principal axes of the base inertia: kept exactly when it is diagonal (the moments keep the scene's order).
    const auto& body = body_of(problem);
    const Mat3<double>& J = body.inertia;
    const bool diagonal = J(0, 1) == 0 && J(0, 2) == 0 && J(1, 2) == 0 && J(1, 0) == 0 && J(2, 0) == 0 && J(2, 1) == 0;
    Vec3<double> moments;
    if (diagonal) {
      axes_ = Mat3<double>::Identity();
      moments = J.diagonal();
    } else {
      const Eigen::SelfAdjointEigenSolver<Mat3<double>> eig(Mat3<double>(0.5 * (J + J.transpose())));
      axes_ = eig.eigenvectors();
      if (axes_.determinant() < 0) axes_.col(2) = -axes_.col(2);
      moments = eig.eigenvalues();
    }
    axes_identity_ = diagonal;
    values_[idx(Block::inertia)] = {std::log(moments(0)), std::log(moments(1)), std::log(moments(2))};
    if constexpr (has_b_v<P>) values_[idx(Block::b)] = {static_cast<double>(body.b)};
    else values_[idx(Block::b)] = {0.0};
    if constexpr (has_z0_v<P>) values_[idx(Block::z0)] = {body.z0(0), body.z0(1), body.z0(2)};
    else values_[idx(Block::z0)] = {0.0, 0.0, 1.0};
    values_[idx(Block::period)] = {period};
    values_[idx(Block::phase)] = {phase};
    values_[idx(Block::damping)] = {0.0};
    if constexpr (has_damping_v<P>) {
      // C = c I: its diagonal's first entry; any other C is flagged (an error if problem.damping is an unknown).
      const Mat3<double> C = body.has_damping ? Mat3<double>(body.damping) : Mat3<double>::Zero();
      values_[idx(Block::damping)] = {C(0, 0)};
      isotropic_damping_ = C == C(0, 0) * Mat3<double>::Identity();
    }
    values_[idx(Block::body_torque)] = {0.0, 0.0, 0.0};
    values_[idx(Block::lab_torque)] = {0.0, 0.0, 0.0};
    if constexpr (has_constant_torque_v<P>) {
      if (body.has_constant) {
        values_[idx(Block::body_torque)] = {body.body_torque(0), body.body_torque(1), body.body_torque(2)};
        values_[idx(Block::lab_torque)] = {body.lab_torque(0), body.lab_torque(1), body.lab_torque(2)};
      }
    }
    values_[idx(Block::k_R)] = {0.0};
    values_[idx(Block::k_Omega)] = {0.0};
    if constexpr (has_gains_v<P>) {
      values_[idx(Block::k_R)] = {static_cast<double>(body.k_R)};
      values_[idx(Block::k_Omega)] = {static_cast<double>(body.k_Omega)};
      has_controller_ = body.has_control;
    }
    values_[idx(Block::rotor_friction)].assign(max_block_components, 0.0);
    values_[idx(Block::wheel_k_R)] = {0.0};
    values_[idx(Block::wheel_k_Omega)] = {0.0};
    if constexpr (is_gyrostat_v<P>) {
      rotor_count_ = problem.rotor_count;
      for (int i = 0; i < problem.rotor_count; ++i)
        values_[idx(Block::rotor_friction)][static_cast<std::size_t>(i)] = static_cast<double>(problem.rotors[i].friction);
      values_[idx(Block::wheel_k_R)] = {static_cast<double>(problem.k_R)};
      values_[idx(Block::wheel_k_Omega)] = {static_cast<double>(problem.k_Omega)};
      has_wheel_control_ = problem.wheel_control;
    }
    if (options_.mode == Mode::periodic) {
      if (!(period > 0) || !std::isfinite(period)) throw FitInputError("period", "must be a finite number > 0");
      resolve_symmetry();
    }
    read_unknowns(unknowns);
    if (options_.mode == Mode::observations) {
      check_observations(observations_, options_.t_end < 0 ? std::numeric_limits<double>::max() : options_.t_end);
      for (std::size_t i = 0; i < observations_.size(); ++i) {
        if (times_.empty() || observations_[i].t != times_.back()) times_.push_back(observations_[i].t);
        time_index_.push_back(static_cast<int>(times_.size()) - 1);
      }
    }
  }

  Model(const Model&) = delete;             ///< not copyable (cost functions refer to it)
  Model& operator=(const Model&) = delete;  ///< not copyable

  // ---- layout ----
  /// The number of free tangent coordinates (the columns of the tangent-space Jacobian).
  int tangent_size() const { return n_tangent_; }
  /// The blocks with a free component, in Block order (the order of the cost functions' parameter blocks).
  const std::vector<Block>& active_blocks() const { return active_; }
  /// Pointers to the active blocks' values (ambient coordinates), in active_blocks() order: ceres writes there.
  std::vector<double*> parameter_blocks() {
    std::vector<double*> p;
    for (Block b : active_) p.push_back(values_[idx(b)].data());
    return p;
  }
  /// The manifold of each active block (nullptr: Euclidean with nothing fixed), for ceres::GradientChecker.
  std::vector<const ceres::Manifold*> manifolds() const {
    std::vector<const ceres::Manifold*> m;
    for (Block b : active_) m.push_back(manifolds_[idx(b)].get());
    return m;
  }
  /// Block b's current values in ambient coordinates (problem.inertia: the log-moments ℓ_k).
  const std::vector<double>& value(Block b) const { return values_[idx(b)]; }
  /// The tangent coordinate of component k of block b, −1 when it is fixed or b is not an unknown.
  int tangent_index(Block b, int k) const { return tangent_index_[idx(b)][k]; }
  /// True when block b has a free component.
  bool is_active(Block b) const {
    return std::any_of(tangent_index_[idx(b)].begin(), tangent_index_[idx(b)].end(), [](int g) { return g >= 0; });
  }
  /// The components of block b a user sees (tangent coordinates; problem.rotor_friction: one per rotor of the problem,
  /// its slots beyond them held at 0).
  int components(Block b) const { return b == Block::rotor_friction ? rotor_count_ : block_info[idx(b)].tangent; }
  /// Q, the principal axes the moments are fitted about (the base tensor's; 1 for a diagonal one).
  const Mat3<double>& principal_axes() const { return axes_; }
  /// The periodic symmetry, resolved (never automatic after construction in periodic mode).
  PeriodicSymmetry symmetry() const { return options_.symmetry; }
  /// The observations, as given (observations mode).
  const std::vector<Observation>& observations() const { return observations_; }

  /// Adds the parameter blocks, manifolds, bounds and residual blocks to a ceres problem created with
  /// manifold_ownership = DO_NOT_TAKE_OWNERSHIP (the model owns its manifolds and must outlive the problem).
  void add_to(ceres::Problem& problem) {
    std::vector<double*> blocks = parameter_blocks();
    for (std::size_t i = 0; i < active_.size(); ++i) {
      const Block b = active_[i];
      problem.AddParameterBlock(blocks[i], block_info[idx(b)].ambient, manifolds_[idx(b)].get());
      for (int k = 0; k < block_info[idx(b)].ambient && block_info[idx(b)].euclidean; ++k) {
        if (std::isfinite(lower_[idx(b)][k])) problem.SetParameterLowerBound(blocks[i], k, lower_[idx(b)][k]);
        if (std::isfinite(upper_[idx(b)][k])) problem.SetParameterUpperBound(blocks[i], k, upper_[idx(b)][k]);
      }
    }
    if (options_.mode == Mode::observations) {
      for (std::size_t i = 0; i < observations_.size(); ++i)
        problem.AddResidualBlock(observation_cost(i).release(), make_loss(observations_[i]), blocks);
    } else {
      problem.AddResidualBlock(periodic_cost().release(), nullptr, blocks);
    }
  }

  /// The residual block of observation i (an ObservationCost referring to this model).
  std::unique_ptr<ceres::CostFunction> observation_cost(std::size_t i);
  /// The periodicity residual block (a PeriodicCost referring to this model).
  std::unique_ptr<ceres::CostFunction> periodic_cost();

  // ---- evaluation ----

  /// The problem, initial state, period and phase at the parameter values `params` (one pointer per active
  /// block, in order; nullptr: the stored values), with Jet derivative j = tangent coordinate chunk_begin + j.
  template <class T>
  Seeded<T> seed(double const* const* params, int chunk_begin) const {
    const auto var = [&](double v, int g) {
      T x(v);
      if constexpr (is_dual_v<T>)
        if (g >= chunk_begin && g < chunk_begin + N) x.v[g - chunk_begin] = 1;
      return x;
    };
    const auto p = [&](Block b) -> const double* {
      if (params)
        for (std::size_t i = 0; i < active_.size(); ++i)
          if (active_[i] == b) return params[i];
      return values_[idx(b)].data();
    };
    const auto& ti = tangent_index_;
    Seeded<T> s{base_.template cast<T>(), {}, T(0), T(0)};
    const double* w = p(Block::omega);
    for (int i = 0; i < 3; ++i) s.x0.Omega(i) = var(w[i], ti[idx(Block::omega)][i]);
    const Mat3<T> R0 = Mat3<double>(Eigen::Map<const Mat3<double>>(p(Block::R))).template cast<T>();
    if (is_active(Block::R)) {
      Vec3<T> d;
      for (int k = 0; k < 3; ++k) d(k) = var(0.0, ti[idx(Block::R)][k]);
      s.x0.R = so3_plus(R0, d);
    } else {
      s.x0.R = R0;
    }
    auto& body = body_of(s.problem);
    if (is_active(Block::inertia)) {
      using std::exp;
      const double* l = p(Block::inertia);
      Vec3<T> m;
      for (int k = 0; k < 3; ++k) m(k) = exp(var(l[k], ti[idx(Block::inertia)][k]));
      if (axes_identity_) {
        body.inertia = m.asDiagonal();
      } else {
        const Mat3<T> Q = axes_.template cast<T>();
        body.inertia = Q * m.asDiagonal() * Q.transpose();
      }
    }
    if constexpr (has_b_v<P>)
      if (is_active(Block::b)) body.b = var(p(Block::b)[0], ti[idx(Block::b)][0]);
    if constexpr (has_z0_v<P>) {
      if (is_active(Block::z0)) {
        const double* z = p(Block::z0);
        const Vec3<double> zd(z[0], z[1], z[2]);
        Eigen::Matrix<T, 2, 1> d;
        for (int k = 0; k < 2; ++k) d(k) = var(0.0, ti[idx(Block::z0)][k]);
        body.z0 = s2_plus(Vec3<T>(zd.template cast<T>()), Eigen::Matrix<T, 3, 2>(s2_basis(zd).template cast<T>()), d);
      }
    }
    if constexpr (has_damping_v<P>) {
      if (is_active(Block::damping)) {
        body.damping = var(p(Block::damping)[0], ti[idx(Block::damping)][0]) * Mat3<T>::Identity();
        body.has_damping = true;
      }
    }
    if constexpr (has_constant_torque_v<P>) {
      for (const Block b : {Block::body_torque, Block::lab_torque}) {
        if (!is_active(b)) continue;
        Vec3<T>& M = b == Block::body_torque ? body.body_torque : body.lab_torque;
        for (int k = 0; k < 3; ++k) M(k) = var(p(b)[k], ti[idx(b)][k]);
        body.has_constant = true;
      }
    }
    if constexpr (has_gains_v<P>) {
      if (is_active(Block::k_R)) body.k_R = var(p(Block::k_R)[0], ti[idx(Block::k_R)][0]);
      if (is_active(Block::k_Omega)) body.k_Omega = var(p(Block::k_Omega)[0], ti[idx(Block::k_Omega)][0]);
    }
    if constexpr (is_gyrostat_v<P>) {
      if (is_active(Block::rotor_friction))
        for (int k = 0; k < rotor_count_; ++k)
          s.problem.rotors[k].friction = var(p(Block::rotor_friction)[k], ti[idx(Block::rotor_friction)][k]);
      if (is_active(Block::wheel_k_R)) s.problem.k_R = var(p(Block::wheel_k_R)[0], ti[idx(Block::wheel_k_R)][0]);
      if (is_active(Block::wheel_k_Omega))
        s.problem.k_Omega = var(p(Block::wheel_k_Omega)[0], ti[idx(Block::wheel_k_Omega)][0]);
    }
    s.period = var(p(Block::period)[0], ti[idx(Block::period)][0]);
    s.phase = var(p(Block::phase)[0], ti[idx(Block::phase)][0]);
    return s;
  }

  /// The monitor of every integration: false (stop) once the deadline has passed.
  auto in_time() const {
    return [deadline = options_.deadline](std::int64_t) { return std::chrono::steady_clock::now() < deadline; };
  }

  /// The states at the observation times (one run from t = 0); false when the run failed or left a
  /// non-finite value or derivative.
  template <class T>
  bool run_observed(const Seeded<T>& s, std::vector<State<T>>& out) const {
    Method<rebind_problem_t<P, T>> stepper(s.problem, options_.stepper);
    State<T> x = s.x0;
    std::vector<T> times(times_.size());
    for (std::size_t i = 0; i < times_.size(); ++i) times[i] = T(times_[i]);
    out.clear();
    out.reserve(times_.size() + 1);
    const IntegrationSummary summary =
        integrate_times(stepper, x, T(0), T(options_.dt), std::span<const T>(times),
                        [&](const T&, const State<T>& xs) { out.push_back(xs); }, in_time());
    if (summary.status != RunStatus::completed) return false;
    if (times_.front() != 0) out.erase(out.begin());  // t = 0 is always observed
    if (out.size() != times_.size()) return false;
    for (const State<T>& xs : out)
      if (!is_finite(xs)) return false;
    return true;
  }

  /// The periodicity residual (3 or 6 entries, see PeriodicSymmetry); false when the run failed.
  template <class T>
  bool periodic_residual(const Seeded<T>& s, T* r) const {
    ++runs_;
    Method<rebind_problem_t<P, T>> stepper(s.problem, options_.stepper);
    State<T> x = s.x0;
    const T h = s.period / T(static_cast<double>(options_.steps));
    const IntegrationSummary summary = integrate_to(stepper, x, T(0), h, s.period, NoObserver{}, in_time());
    if (summary.status != RunStatus::completed || !is_finite(x)) return false;
    int n = 0;
    if (options_.symmetry != PeriodicSymmetry::body_omega) {
      Mat3<T> target = s.x0.R;
      if constexpr (has_k_v<P>)
        if (options_.symmetry == PeriodicSymmetry::about_k)
          target = so3::exp(Vec3<T>(s.phase * s.problem.k)) * s.x0.R;
      const Vec3<T> e = so3::log(Mat3<T>(target.transpose() * x.R));
      for (int i = 0; i < 3; ++i) r[n++] = e(i);
    }
    for (int i = 0; i < 3; ++i) r[n++] = x.Omega(i) - s.x0.Omega(i);
    for (int i = 0; i < n; ++i)
      if (!all_finite(r[i])) return false;
    return true;
  }
  /// 3 for body_omega, 6 otherwise.
  int periodic_residual_size() const { return options_.symmetry == PeriodicSymmetry::body_omega ? 3 : 6; }

  /// The cached trajectory at `params`: states at the unique observation times and, when asked, their
  /// derivatives d(vec R, Ω)/d(tangent coordinates) (12 × n). nullptr when the integration failed.
  struct Trajectory {
    std::vector<double> key;    ///< the parameter values it was computed at (bit for bit)
    bool ok = false;            ///< the integration succeeded
    bool has_jacobian = false;  ///< dx is computed
    std::vector<State<double>> x;  ///< the states at the unique observation times
    std::vector<Eigen::Matrix<double, 12, Eigen::Dynamic>> dx;  ///< their derivatives (12 × tangent_size())
  };
  /// The trajectory at params (see Trajectory): one run in double when params changed, plus the Jet passes when
  /// `jacobian` and they are not cached; nullptr when a run failed. Not thread-safe: hold mutex().
  const Trajectory* trajectory(double const* const* params, bool jacobian) const {
    std::vector<double> key;
    for (std::size_t i = 0; i < active_.size(); ++i)
      key.insert(key.end(), params[i], params[i] + block_info[idx(active_[i])].ambient);
    if (key != cache_.key) {
      cache_.key = key;
      cache_.has_jacobian = false;
      cache_.ok = run_observed(seed<double>(params, 0), cache_.x);
      ++runs_;
    }
    if (!cache_.ok) return nullptr;
    if (jacobian && !cache_.has_jacobian) {
      cache_.dx.assign(times_.size(), Eigen::Matrix<double, 12, Eigen::Dynamic>::Zero(12, n_tangent_));
      std::vector<State<Jet>> xs;
      for (int c = 0; c < n_tangent_; c += N) {
        ++runs_;
        if (!run_observed(seed<Jet>(params, c), xs)) {
          cache_.ok = false;
          return nullptr;
        }
        for (std::size_t k = 0; k < xs.size(); ++k)
          for (int j = 0; j < N && c + j < n_tangent_; ++j) {
            for (int a = 0; a < 9; ++a) cache_.dx[k](a, c + j) = xs[k].R.data()[a].v[j];
            for (int i = 0; i < 3; ++i) cache_.dx[k](9 + i, c + j) = xs[k].Omega(i).v[j];
          }
      }
      cache_.has_jacobian = true;
    }
    return &cache_;
  }
  /// The lock of the cached trajectory.
  std::mutex& mutex() const { return mutex_; }
  /// The index of an observation's time among the unique observation times.
  int time_index(std::size_t observation) const { return time_index_[observation]; }
  /// Integrations done (a Jet pass counts one).
  long runs() const { return runs_; }

  /// Ceres' ambient Jacobians from tangent-space ones (m × n_tangent, see the header).
  void to_ambient(const Eigen::MatrixXd& J_tan, double const* const* params, double** jacobians) const {
    const auto m = J_tan.rows();
    for (std::size_t i = 0; i < active_.size(); ++i) {
      if (!jacobians[i]) continue;
      const Block b = active_[i];
      const BlockInfo& info = block_info[idx(b)];
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(jacobians[i], m, info.ambient);
      if (info.euclidean) {
        for (int k = 0; k < info.ambient; ++k) {
          const int g = tangent_index_[idx(b)][k];
          if (g >= 0) J.col(k) = J_tan.col(g);
          else J.col(k).setZero();
        }
        continue;
      }
      Eigen::MatrixXd Pj;  // the manifold's PlusJacobian
      if (b == Block::R) Pj = so3_plus_jacobian(Mat3<double>(Eigen::Map<const Mat3<double>>(params[i])));
      else Pj = s2_plus_jacobian(Vec3<double>(params[i][0], params[i][1], params[i][2]));
      Eigen::MatrixXd Jt(m, info.tangent);
      for (int k = 0; k < info.tangent; ++k) Jt.col(k) = J_tan.col(tangent_index_[idx(b)][k]);
      J = Jt * (Pj.transpose() * Pj).inverse() * Pj.transpose();
    }
  }

 private:
  static constexpr int idx(Block b) { return static_cast<int>(b); }

  void check_options() {
    if (options_.mode == Mode::observations && (!(options_.dt > 0) || !std::isfinite(options_.dt)))
      throw FitInputError("integrator.dt", "the step must be a finite number > 0");
    if (options_.mode == Mode::periodic && options_.steps < 1)
      throw FitInputError("steps", "the number of steps over the period must be >= 1");
    try {
      options_.stepper.check();
    } catch (const std::invalid_argument& e) {
      throw FitInputError("integrator", e.what());
    }
    if (options_.stepper.rtol != 0 || options_.stepper.atol != 0)
      throw FitInputError("integrator.rtol", "the fit integrates with fixed steps; rtol/atol are not supported");
  }

  void resolve_symmetry() {
    if (options_.symmetry == PeriodicSymmetry::automatic) {
      if (torque_free_v<P>) options_.symmetry = PeriodicSymmetry::body_omega;
      else if (has_k_v<P>) options_.symmetry = PeriodicSymmetry::about_k;
      else options_.symmetry = PeriodicSymmetry::none;
    }
    if (options_.symmetry == PeriodicSymmetry::about_k && !has_k_v<P>)
      throw FitInputError("symmetry", "about_k needs a problem with a vertical k");
  }

  void read_unknowns(std::span<const Unknown> unknowns) {
    for (auto& t : tangent_index_) t.fill(-1);
    for (auto& l : lower_) l.fill(-std::numeric_limits<double>::infinity());
    for (auto& u : upper_) u.fill(std::numeric_limits<double>::infinity());
    if constexpr (has_b_v<P>) lower_[idx(Block::b)][0] = 0;  // b ≥ 0
    for (const Block b : {Block::damping, Block::k_R, Block::k_Omega, Block::wheel_k_R, Block::wheel_k_Omega})
      lower_[idx(b)][0] = 0;  // c, k_R, k_Ω ≥ 0
    lower_[idx(Block::rotor_friction)].fill(0);  // c_i ≥ 0
    std::array<bool, block_count> listed{};
    std::array<std::array<bool, max_block_components>, block_count> free{};
    for (std::size_t u = 0; u < unknowns.size(); ++u) {
      const Unknown& un = unknowns[u];
      const std::string at = "unknowns[" + std::to_string(u) + "]";
      int b = -1;
      for (int i = 0; i < block_count; ++i)
        if (block_info[i].name == un.name) b = i;
      if (b < 0)
        throw FitInputError(at + ".name", "unknown unknown '" + un.name + "' (known: " + known_unknowns() + ")");
      const Block block = static_cast<Block>(b);
      if (listed[b]) throw FitInputError(at + ".name", "'" + un.name + "' is listed twice");
      listed[b] = true;
      if ((block == Block::b && !has_b_v<P>) || (block == Block::z0 && !has_z0_v<P>) ||
          (block == Block::damping && !has_damping_v<P>) ||
          ((block == Block::body_torque || block == Block::lab_torque) && !has_constant_torque_v<P>) ||
          ((block == Block::k_R || block == Block::k_Omega) && !has_gains_v<P>) ||
          ((block == Block::rotor_friction || block == Block::wheel_k_R || block == Block::wheel_k_Omega) &&
           !is_gyrostat_v<P>))
        throw FitInputError(at + ".name", "'" + un.name + "' does not apply to problem " + std::string(P::name));
      if (block == Block::damping && !isotropic_damping_)
        throw FitInputError(at + ".name", "'problem.damping' fits c of C = c I; the scene's damping matrix is not a "
                                          "multiple of I");
      if ((block == Block::k_R || block == Block::k_Omega) && !has_controller_)
        throw FitInputError(at + ".name", "'" + un.name + "' needs the scene's attitude_control term (its target)");
      if ((block == Block::wheel_k_R || block == Block::wheel_k_Omega) && !has_wheel_control_)
        throw FitInputError(at + ".name", "'" + un.name + "' needs the scene's wheel_control (its target)");
      if (block == Block::period && options_.mode != Mode::periodic)
        throw FitInputError(at + ".name", "'period' is an unknown of periodic-orbit fits only");
      if (block == Block::phase && (options_.mode != Mode::periodic || options_.symmetry != PeriodicSymmetry::about_k))
        throw FitInputError(at + ".name", "'phase' is an unknown of periodic orbits with the about_k symmetry only");
      const BlockInfo& info = block_info[b];
      const int comps = components(block);  // what the user sees (rotor_friction: the rotors present)
      for (int k = 0; k < comps; ++k) free[b][k] = true;
      for (const int k : un.fixed) {
        if (!info.euclidean) throw FitInputError(at + ".fixed", "components of " + un.name + " cannot be fixed separately");
        if (k < 0 || k >= comps)
          throw FitInputError(at + ".fixed", "component " + std::to_string(k) + " out of range [0, " + std::to_string(comps - 1) + "]");
        free[b][k] = false;
      }
      for (int side = 0; side < 2; ++side) {
        const std::vector<double>& bound = side == 0 ? un.lower : un.upper;
        if (bound.empty()) continue;
        const std::string f = at + (side == 0 ? ".lower" : ".upper");
        if (!info.euclidean) throw FitInputError(f, un.name + " takes no bounds");
        if (static_cast<int>(bound.size()) != comps)
          throw FitInputError(f, "expected " + std::to_string(comps) + " values, got " + std::to_string(bound.size()));
        for (int k = 0; k < comps; ++k) {
          double v = bound[static_cast<std::size_t>(k)];
          if (std::isnan(v)) throw FitInputError(f, "a bound is NaN");
          if (block == Block::inertia) {
            if (side == 0 && v <= 0) continue;  // moments are positive by construction
            if (!(v > 0)) throw FitInputError(f, "an upper bound on a moment must be > 0");
            v = std::log(v);
          }
          (side == 0 ? lower_ : upper_)[b][k] = v;
        }
      }
      for (int k = 0; k < comps; ++k) {
        if (lower_[b][k] > upper_[b][k])
          throw FitInputError(at + ".lower", "lower bound above the upper bound for component " + std::to_string(k));
        const double v = values_[b][static_cast<std::size_t>(k)];
        if (info.euclidean && free[b][k] && (v < lower_[b][k] || v > upper_[b][k]))
          throw FitInputError(at + ".lower", "the initial value of component " + std::to_string(k) + " is outside its bounds");
      }
    }
    // A free period is kept in [T/2, 3T/2] unless bounded otherwise: T = 0 (and 2T) would also "return".
    if (free[idx(Block::period)][0]) {
      const double T = values_[idx(Block::period)][0];
      if (!std::isfinite(lower_[idx(Block::period)][0])) lower_[idx(Block::period)][0] = 0.5 * T;
      if (!std::isfinite(upper_[idx(Block::period)][0])) upper_[idx(Block::period)][0] = 1.5 * T;
    }
    n_tangent_ = 0;
    for (int b = 0; b < block_count; ++b) {
      const BlockInfo& info = block_info[b];
      const int comps = info.euclidean ? info.ambient : info.tangent;
      std::vector<int> fixed_components;
      bool any = false;
      for (int k = 0; k < comps; ++k) {
        if (free[b][k]) {
          tangent_index_[b][k] = n_tangent_++;
          any = true;
        } else {
          fixed_components.push_back(k);
        }
      }
      if (!any) continue;
      active_.push_back(static_cast<Block>(b));
      if (static_cast<Block>(b) == Block::R) manifolds_[b] = std::make_unique<SO3Manifold>();
      else if (static_cast<Block>(b) == Block::z0) manifolds_[b] = std::make_unique<S2Manifold>();
      else if (!fixed_components.empty()) manifolds_[b] = std::make_unique<ceres::SubsetManifold>(comps, fixed_components);
    }
    if (n_tangent_ == 0) throw FitInputError("unknowns", "nothing to fit: no unknown has a free component");
  }

  P base_;
  ModelOptions options_;
  std::vector<Observation> observations_;
  std::vector<double> times_;     ///< unique observation times, increasing
  std::vector<int> time_index_;   ///< observation → index in times_
  std::array<std::vector<double>, block_count> values_;
  std::array<std::array<int, max_block_components>, block_count> tangent_index_{};
  bool isotropic_damping_ = true;  ///< the base C is c I (problem.damping may be an unknown)
  bool has_controller_ = false;    ///< the base problem has an attitude controller (problem.k_R, k_Omega)
  bool has_wheel_control_ = false; ///< a gyrostat with the wheel PD law (problem.wheel_k_R, wheel_k_Omega)
  int rotor_count_ = 0;            ///< a gyrostat's rotors (problem.rotor_friction's components)
  std::array<std::array<double, 9>, block_count> lower_{}, upper_{};
  std::array<std::unique_ptr<ceres::Manifold>, block_count> manifolds_;
  std::vector<Block> active_;
  int n_tangent_ = 0;
  Mat3<double> axes_ = Mat3<double>::Identity();
  bool axes_identity_ = true;
  mutable Trajectory cache_;
  mutable std::mutex mutex_;
  mutable long runs_ = 0;
};

/// One observation's residual block: reads the model's cached trajectory.
template <template <class> class Method, FitProblem P, int N>
class ObservationCost final : public ceres::CostFunction {
 public:
  using M = Model<Method, P, N>;  ///< the model
  /// The residual of model.observations()[i]; model must outlive this object.
  ObservationCost(const M& model, std::size_t i) : model_(model), i_(i) {
    set_num_residuals(model.observations()[i].residual_size());
    for (const Block b : model.active_blocks()) mutable_parameter_block_sizes()->push_back(block_info[static_cast<int>(b)].ambient);
  }

  /// ceres::CostFunction::Evaluate: r/σ and, when asked, its ambient Jacobians; false when the integration failed
  /// or a value or derivative is not finite. Serialised on the model's mutex.
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const std::lock_guard<std::mutex> lock(model_.mutex());
    const auto* trajectory = model_.trajectory(parameters, jacobians != nullptr);
    if (!trajectory) return false;
    const Observation& o = model_.observations()[i_];
    const int k = model_.time_index(i_);
    const int m = num_residuals();
    if (!jacobians) {
      observation_residual(o, trajectory->x[static_cast<std::size_t>(k)], residuals);
      for (int r = 0; r < m; ++r)
        if (!std::isfinite(residuals[r])) return false;
      return true;
    }
    using Jet12 = ceres::Jet<double, 12>;
    const State<double>& x = trajectory->x[static_cast<std::size_t>(k)];
    State<Jet12> xs;
    for (int a = 0; a < 9; ++a) xs.R.data()[a] = Jet12(x.R.data()[a], a);
    for (int i = 0; i < 3; ++i) xs.Omega(i) = Jet12(x.Omega(i), 9 + i);
    Jet12 r[3];
    observation_residual(o, xs, r);
    Eigen::Matrix<double, Eigen::Dynamic, 12> D(m, 12);
    for (int i = 0; i < m; ++i) {
      if (!all_finite(r[i])) return false;
      residuals[i] = r[i].a;
      D.row(i) = r[i].v.transpose();
    }
    model_.to_ambient(D * trajectory->dx[static_cast<std::size_t>(k)], parameters, jacobians);
    return true;
  }

 private:
  const M& model_;
  std::size_t i_;
};

/// The periodicity residual: one integration over [0, T] per evaluation (and per Jet pass).
template <template <class> class Method, FitProblem P, int N>
class PeriodicCost final : public ceres::CostFunction {
 public:
  using M = Model<Method, P, N>;  ///< the model
  /// The periodicity residual of model; model must outlive this object.
  explicit PeriodicCost(const M& model) : model_(model) {
    set_num_residuals(model.periodic_residual_size());
    for (const Block b : model.active_blocks()) mutable_parameter_block_sizes()->push_back(block_info[static_cast<int>(b)].ambient);
  }

  /// ceres::CostFunction::Evaluate: the periodicity residual and, when asked, its ambient Jacobians (one Jet run
  /// per N tangent coordinates); false when a run failed or left a non-finite value or derivative.
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const int m = num_residuals();
    if (!model_.periodic_residual(model_.template seed<double>(parameters, 0), residuals)) return false;
    if (!jacobians) return true;
    using Jet = ceres::Jet<double, N>;
    const int n = model_.tangent_size();
    Eigen::MatrixXd J_tan(m, n);
    Jet r[6];
    for (int c = 0; c < n; c += N) {
      if (!model_.periodic_residual(model_.template seed<Jet>(parameters, c), r)) return false;
      for (int i = 0; i < m; ++i)
        for (int j = 0; j < N && c + j < n; ++j) J_tan(i, c + j) = r[i].v[j];
    }
    model_.to_ambient(J_tan, parameters, jacobians);
    return true;
  }

 private:
  const M& model_;
};

template <template <class> class Method, FitProblem P, int N>
std::unique_ptr<ceres::CostFunction> Model<Method, P, N>::observation_cost(std::size_t i) {
  return std::make_unique<ObservationCost<Method, P, N>>(*this, i);
}
template <template <class> class Method, FitProblem P, int N>
std::unique_ptr<ceres::CostFunction> Model<Method, P, N>::periodic_cost() {
  return std::make_unique<PeriodicCost<Method, P, N>>(*this);
}

}  // namespace lgi::fit
