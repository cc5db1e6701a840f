/// \file
/// lgi/problems/gyrostat.hpp — a rigid body carrying rotors (momentum and reaction wheels, a spinning damper): the
/// gyrostat, in the formulation of Hughes, *Spacecraft Attitude Dynamics* (Wiley 1986; Dover 2004), §3.5 and §7.
///
/// N ≤ max_rotors axisymmetric rotors with unit body axes a_i, axial inertias I_s,i and spin rates ω_s,i relative to
/// the body; J is the system's inertia with the rotors locked, A = [a_1 … a_N] (3 × N), I_s = diag(I_s,i). The state is
/// (R, m, h): R ∈ SO(3) the body's attitude, m = R H the system's angular momentum in the laboratory frame (H in the
/// body's) and h_i = I_s,i (a_i·Ω + ω_s,i) the rotors' absolute axial momenta:
///
/// ~~~{.unparsed}
///   J_b = J − A I_s Aᵀ                     the inertia without the rotors' axial parts (positive definite)
///   Ω   = J_b⁻¹ (H − A h),  H = Rᵀ m       the body's angular velocity
///   R'  = R hat(Ω)
///   m'  = R M(t, R, Ω)                     M: the external torque terms, body frame (problems/torqued_body.hpp);
///                                          in the body frame H' = H × Ω + M
///   h_i' = g_i                             g_i: the torque the body's motor applies to rotor i:
///   g_i = g0_i + g_tab,i(t) − c_i ω_s,i      a commanded constant, a commanded profile (problems/torque_table.hpp),
///         + (A⁺ u)_i                         friction (c_i ≥ 0), and the wheels' share of the
///                                            PD law u = k_R e_R + k_Ω e_Ω (A⁺ = Aᵀ(AAᵀ)⁻¹: the least-norm wheel torques
///                                            whose reaction on the body, −A g, is −u)
/// ~~~
///
/// with ω_s,i = h_i / I_s,i − a_i·Ω. Energy (kinetic of body and rotors, and the external potential):
/// E = ½ Ω·J_bΩ + Σ h_i² / (2 I_s,i) + V(R) = ½ Ω·JΩ + Σ (I_s,i ω_s,i a_i·Ω + ½ I_s,i ω_s,i²) + V(R).
/// Invariants: without external torque the spatial momentum m = R H is constant (the motors' torques are internal);
/// without motor torques also each h_i, and E. Friction alone: dE/dt = −Σ c_i ω_s,i² ≤ 0 with R H constant, so the
/// body ends spinning about its major axis with the rotors locked to it (Explorer 1's flat spin, with a damper for
/// the rotor): T → |H|² / (2 I_max), I_max the largest principal moment of J. With the wheel PD law toward a
/// constant attitude at rest (Ω_d = 0), W = ½ Ω·J_bΩ + k_R Ψ(R) has dW/dt = −k_Ω |Ω|² ≤ 0 (the gyroscopic term
/// Ω·((A h) × Ω) vanishes): the attitude converges to the target.
///
/// At fixed (t, R) every term of R M and g is affine in (m, h) (integrators/gyrostat.hpp uses this: an implicit
/// kick is one linear solve). Keeping m rather than H in the state makes m exactly constant wherever no external torque
/// acts: the steps that only turn the body change R alone. Not a RigidBodyProblem (its state is larger than (R, Ω)): the methods of
/// integrators/gyrostat.hpp step it.
#pragma once

#include "torqued_body.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace lgi {

/// One rotor of a gyrostat (this header); not checked here (the scene loader checks it): axis unit, inertia > 0,
/// friction ≥ 0.
template <class T = double>
struct Rotor {
  Vec3<T> axis = Vec3<T>::UnitZ();  ///< a_i, unit, body frame
  T inertia = T(1);                 ///< I_s,i, axial moment of inertia
  T friction = T(0);                ///< c_i ≥ 0: g_i gets −c_i ω_s,i
  T motor = T(0);                   ///< g0_i, a constant commanded motor torque
  T rate = T(0);                    ///< ω_s,i at t = 0, relative to the body (the initial state's rotor part)
};

/// A rigid body with rotors under the torque terms of TorquedBody (this header's equations).
template <class T = double>
struct Gyrostat {
  using Scalar = T;                                     ///< the scalar type
  static constexpr std::string_view name = "gyrostat";  ///< the scene's problem.type
  static constexpr int max_rotors = 6;                  ///< rotors a gyrostat may carry (the state's fixed size)

  TorquedBody<T> body;                  ///< J (rotors locked) in body.inertia, and the external torque terms
  std::array<Rotor<T>, max_rotors> rotors{};  ///< the first rotor_count are present
  int rotor_count = 0;                  ///< N, 1 … max_rotors
  bool wheel_control = false;           ///< the PD law below drives the rotors (u through A⁺)
  Mat3<T> target = Mat3<T>::Identity();    ///< R_d of the wheel PD law
  Vec3<T> target_omega = Vec3<T>::Zero();  ///< Ω_d of the wheel PD law (body frame of the target)
  T k_R = T(0);                         ///< the wheel PD law's proportional gain
  T k_Omega = T(0);                     ///< the wheel PD law's derivative gain
  /// g_tab(t), the rotors' commanded motor torques as a table (component i for rotor i, 0 beyond rotor_count); null:
  /// none.
  std::shared_ptr<const SampleTable<max_rotors>> motor_table;

  /// J_b = J − Σ I_s,i a_i a_iᵀ.
  Mat3<T> body_inertia() const {
    Mat3<T> Jb = body.inertia;
    for (int i = 0; i < rotor_count; ++i) Jb -= rotors[i].inertia * rotors[i].axis * rotors[i].axis.transpose();
    return Jb;
  }

  /// The last time the torques are defined at: the earlier of the body's torque table's and the motor table's last
  /// samples, +∞ without tables (the scene loader refuses a t_end beyond it).
  double time_limit() const {
    return std::min(body.time_limit(), motor_table ? motor_table->t_last() : std::numeric_limits<double>::infinity());
  }
  /// The files the tables were read from, with hashes of their bytes (checkpoints record them); the one that ends
  /// first (time_limit's) first.
  std::vector<std::pair<std::string, std::uint64_t>> input_files() const {
    std::vector<std::pair<std::string, std::uint64_t>> files = body.input_files();
    if (motor_table && !motor_table->source().empty()) {
      const bool first = motor_table->t_last() < body.time_limit();
      files.emplace(first ? files.begin() : files.end(), motor_table->source(), motor_table->digest());
    }
    return files;
  }

  /// The same gyrostat in scalar S (double → ceres::Jet).
  template <class S>
  Gyrostat<S> cast() const {
    Gyrostat<S> c;
    c.body = body.template cast<S>();
    for (int i = 0; i < max_rotors; ++i) {
      c.rotors[i].axis = rotors[i].axis.template cast<S>();
      c.rotors[i].inertia = S(rotors[i].inertia);
      c.rotors[i].friction = S(rotors[i].friction);
      c.rotors[i].motor = S(rotors[i].motor);
      c.rotors[i].rate = S(rotors[i].rate);
    }
    c.rotor_count = rotor_count;
    c.wheel_control = wheel_control;
    c.target = target.template cast<S>();
    c.target_omega = target_omega.template cast<S>();
    c.k_R = S(k_R);
    c.k_Omega = S(k_Omega);
    c.motor_table = motor_table;
    return c;
  }
};

/// A gyrostat's state (this header): attitude R, laboratory-frame system momentum m, rotor momenta h (the first N
/// entries; the rest stay 0).
template <class T>
struct GyrostatState {
  Mat3<T> R = Mat3<T>::Identity();  ///< attitude, body → laboratory
  Vec3<T> m = Vec3<T>::Zero();      ///< m = R (J_b Ω + A h), laboratory frame
  Eigen::Matrix<T, Gyrostat<T>::max_rotors, 1> h =
      Eigen::Matrix<T, Gyrostat<T>::max_rotors, 1>::Zero();  ///< h_i = I_s,i (a_i·Ω + ω_s,i)
  LGI_NUMBERS(R, m, h)
};

/// What the integrators need of a gyrostat, computed once: J_b⁻¹, A, A⁺, and the right-hand side with its
/// (m, h)-Jacobian. z = (m, h) stacked is the part of the state that the kicks change.
template <class T>
class GyrostatDynamics {
 public:
  static constexpr int N = Gyrostat<T>::max_rotors;  ///< rotor slots
  static constexpr int Z = 3 + N;                     ///< size of (m, h)
  using VecN = Eigen::Matrix<T, N, 1>;                ///< rotor quantities
  using VecZ = Eigen::Matrix<T, Z, 1>;                ///< (m, h)
  using MatZ = Eigen::Matrix<T, Z, Z>;                ///< ∂(m', h')/∂(m, h)

  /// Precomputes J_b⁻¹, A and A⁺ (A⁺ only with wheel control, which the loader allows only for axes spanning R³).
  explicit GyrostatDynamics(const Gyrostat<T>& g) : g_(g), A_(Eigen::Matrix<T, 3, N>::Zero()) {
    Jb_inv_ = g.body_inertia().inverse();
    for (int i = 0; i < g.rotor_count; ++i) {
      A_.col(i) = g.rotors[i].axis;
      inv_Is_(i) = T(1) / g.rotors[i].inertia;
      c_(i) = g.rotors[i].friction;
      g0_(i) = g.rotors[i].motor;
    }
    if (g.wheel_control) {
      const Mat3<T> AAt = A_ * A_.transpose();
      pinv_ = A_.transpose() * AAt.inverse();
    }
    Jb_inv_A_ = -Jb_inv_ * A_;
    dg_dOmega_ = c_.asDiagonal() * A_.transpose();
    if (g.wheel_control) dg_dOmega_ += g.k_Omega * pinv_;
    c_over_Is_ = c_.cwiseProduct(inv_Is_);
    const TorquedBody<T>& b = g.body;
    has_external_ =
        value_of(b.b) != 0 || b.has_constant || b.table || b.has_damping || b.has_control || b.has_gravity_gradient;
    bool friction = false;
    for (int i = 0; i < g.rotor_count; ++i) friction = friction || value_of(g.rotors[i].friction) != 0;
    reads_state_ = b.has_damping || b.has_control || g.wheel_control || friction;
  }

  /// The problem.
  const Gyrostat<T>& problem() const { return g_; }
  /// Ω = J_b⁻¹(H − A h) with H = Rᵀm.
  Vec3<T> omega(const Mat3<T>& R, const Vec3<T>& m, const VecN& h) const {
    return Jb_inv_ * (R.transpose() * m - A_ * h);
  }
  /// w = J_b⁻¹ A h, the body's angular velocity that the rotors' momenta take away: Ω = J_b⁻¹H − w.
  Vec3<T> rotor_drift(const VecN& h) const { return Jb_inv_ * (A_ * h); }
  /// ω_s,i = h_i / I_s,i − a_i·Ω (zero beyond the rotor count).
  VecN rotor_rates(const VecN& h, const Vec3<T>& Omega) const {
    return (h.cwiseProduct(inv_Is_) - A_.transpose() * Omega);
  }
  /// The state of (R, Ω) with the rotors at their initial relative rates (Rotor::rate).
  GyrostatState<T> state(const Mat3<T>& R, const Vec3<T>& Omega) const {
    GyrostatState<T> y;
    y.R = R;
    for (int i = 0; i < g_.rotor_count; ++i)
      y.h(i) = g_.rotors[i].inertia * (g_.rotors[i].axis.dot(Omega) + g_.rotors[i].rate);
    Vec3<T> H = g_.body.inertia * Omega;  // J Ω + Σ I_s,i ω_s,i a_i: = J_bΩ + A h without its cancellation
    for (int i = 0; i < g_.rotor_count; ++i) H += g_.rotors[i].inertia * g_.rotors[i].rate * g_.rotors[i].axis;
    y.m = R * H;
    return y;
  }
  /// True when a term of M or g reads (m, h) (damping, control, friction): the implicit kick needs its solve.
  bool reads_state() const { return reads_state_; }
  /// True when M is not zero (some external term present).
  bool has_external() const { return has_external_; }

  /// (m', h') at (t, R, m, h): (R M(t, R, Ω), g).
  VecZ forcing(const T& t, const Mat3<T>& R, const Vec3<T>& m, const VecN& h) const {
    const Vec3<T> Omega = omega(R, m, h);
    VecZ f;
    if (has_external()) f.template head<3>() = R * g_.body.torque(t, R, Omega);
    else f.template head<3>().setZero();
    VecN g = g0_ - c_.cwiseProduct(rotor_rates(h, Omega));
    if (g_.motor_table) g += (*g_.motor_table)(t);
    if (g_.wheel_control) {
      const Vec3<T> u = g_.k_R * lgi::attitude_error(g_.target, R) + g_.k_Omega * (Omega - R.transpose() * (g_.target * g_.target_omega));
      g += pinv_ * u;
    }
    f.template tail<N>() = g;
    return f;
  }
  /// ∂forcing/∂(m, h) at (t, R): constant in (m, h) (the terms are affine in them).
  MatZ forcing_jacobian(const T& t, const Mat3<T>& R) const {
    // dΩ/d(m, h) = J_b⁻¹ [Rᵀ, −A]
    Eigen::Matrix<T, 3, Z> dOmega;
    dOmega.template leftCols<3>() = Jb_inv_ * R.transpose();
    dOmega.template rightCols<N>() = Jb_inv_A_;
    MatZ D = MatZ::Zero();
    const Vec3<T> zero = Vec3<T>::Zero();
    D.template topRows<3>() = R * g_.body.torque_omega_jacobian(t, R, zero) * dOmega;
    // g: −c ∘ (h / I_s − Aᵀ Ω) + A⁺ k_Ω Ω
    D.template bottomRows<N>() = dg_dOmega_ * dOmega;
    D.template bottomRightCorner<N, N>() -= Eigen::Matrix<T, N, N>(c_over_Is_.asDiagonal());
    return D;
  }
  /// E = ½ Ω·J_bΩ + Σ h_i² / (2 I_s,i) + V(R) (V: the external terms' potential, TorquedBody::potential).
  T energy(const GyrostatState<T>& y) const {
    const Vec3<T> Pb = y.R.transpose() * y.m - A_ * y.h;
    const Vec3<T> Omega = Jb_inv_ * Pb;
    return (Omega.dot(Pb) + y.h.cwiseProduct(inv_Is_).dot(y.h)) / T(2) + g_.body.potential(y.R);
  }

 private:
  Gyrostat<T> g_;
  Mat3<T> Jb_inv_;
  Eigen::Matrix<T, 3, N> A_;
  Eigen::Matrix<T, N, 3> pinv_ = Eigen::Matrix<T, N, 3>::Zero();
  VecN inv_Is_ = VecN::Zero(), c_ = VecN::Zero(), g0_ = VecN::Zero();
  Eigen::Matrix<T, 3, N> Jb_inv_A_;   ///< −J_b⁻¹ A: ∂Ω/∂h
  Eigen::Matrix<T, N, 3> dg_dOmega_;  ///< ∂g/∂Ω = diag(c) Aᵀ + k_Ω A⁺
  VecN c_over_Is_;                    ///< c_i / I_s,i: −∂g_i/∂h_i beyond the Ω terms
  bool has_external_ = false, reads_state_ = false;
};

}  // namespace lgi
