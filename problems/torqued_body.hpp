/// \file
/// lgi/problems/torqued_body.hpp — a rigid body under a sum of torque terms: uniform gravity, constant torques in the
/// body or the laboratory frame, a tabulated torque M(t), linear damping and a PD attitude controller. The body of
/// attitude-control work and of dissipative tops.
///
/// Equations (core/problem.hpp, StateTorqueProblem): J Ω' = (JΩ) × Ω + M(t, R, Ω), R' = R hat(Ω), with body-frame
/// torque
///
/// ~~~{.unparsed}
///   M = b (Rᵀk) × z0                       gravity (the heavy top's, seed paper (s4)–(s5)); b = 0: none
///     + M_body + Rᵀ M_lab                  constant torques, body and laboratory frame
///     + M_tab(t)  or  Rᵀ M_tab(t)          a tabulated torque, body or laboratory frame (problems/torque_table.hpp)
///     − C Ω                                linear damping, C symmetric positive semi-definite
///     − k_R e_R − k_Ω e_Ω                  PD control toward a constant target attitude R_d, rate Ω_d:
///        e_R = ½ vee(R_dᵀR − RᵀR_d),  e_Ω = Ω − RᵀR_d Ω_d
///     + 3n² ρ × (J ρ),  ρ = Rᵀ r̂(t)         the gravity-gradient torque of a circular orbit of rate n
///        r̂(t) = cos(nt) r̂0 + sin(nt) (ν × r̂0)   (problems/satellite.hpp's, with its equations and conventions)
/// ~~~
///
/// (the attitude and rate errors of Lee, Leok & McClamroch, "Geometric tracking control of a quadrotor UAV on
/// SE(3)", Proc. IEEE CDC 2010, 5420, §III, here with a constant R_d). Energy E = ½ Ω·JΩ + V(R) with
/// V = b k·(R z0) + k_R Ψ(R), Ψ = ½ tr(I − R_dᵀR): for R → R exp(η̂), dΨ = −½ tr(R_dᵀR η̂) = η·e_R, so the
/// proportional term is −k_R dΨ, conservative. Balance: dE/dt = Ω·M_nc with M_nc = M_body + Rᵀ M_lab + M_tab − CΩ − k_Ω e_Ω
/// + M_gg; damping alone gives dE/dt = −Ω·CΩ ≤ 0. The gravity-gradient potential (3n²/2) ρ·Jρ depends on t and is
/// not in V: its torque counts as external work (the satellite problem type reports it and the Jacobi integral). The spatial momentum m = RJΩ obeys m' = R M: no invariant in general; the
/// output columns are m and |JΩ| (the free body's), whose changes show the torques' action.
///
/// Not a ReducedAttitudeProblem (its torque reads Ω): the explicit methods take it (RKMK, commutator-free,
/// Crouch–Grossman, the baselines), with every term evaluated at each stage's (t, R, Ω), and the LGVI and its
/// compositions in their forced form (integrators/lgvi.hpp, with ∂M/∂Ω from torque_omega_jacobian); the splittings
/// do not (AttitudeTorqueProblem). Terms the scene does not ask for are skipped (their flags), so a body with only
/// damping computes nothing of the controller.
#pragma once

#include "../core/invariants.hpp"
#include "../core/problem.hpp"
#include "../core/so3.hpp"

#include "torque_table.hpp"

#include <array>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace lgi {

/// e_R = ½ vee(R_dᵀR − RᵀR_d), the attitude error of R from the target R_d (Lee, Leok & McClamroch, CDC 2010, §III).
template <class T>
Vec3<T> attitude_error(const Mat3<T>& target, const Mat3<T>& R) {
  const Mat3<T> E = target.transpose() * R;
  return Vec3<T>(E(2, 1) - E(1, 2), E(0, 2) - E(2, 0), E(1, 0) - E(0, 1)) / T(2);
}

/// A rigid body under gravity, constant torques, damping and PD control (this header's equations). The data are not
/// checked here (the scene loader checks them): k, z0 unit, b ≥ 0, C symmetric positive semi-definite, R_d ∈ SO(3),
/// k_R, k_Ω ≥ 0.
template <class T = double>
struct TorquedBody {
  using Scalar = T;                                         ///< the scalar type
  static constexpr std::string_view name = "rigid_body";    ///< the scene's problem.type
  static constexpr bool has_torque = true;                  ///< the sum of the terms below

  Mat3<T> inertia = Mat3<T>::Identity();  ///< J, body frame, symmetric positive definite
  T b = T(0);                             ///< gravity: b = weight × distance of the centre of mass (0: none)
  Vec3<T> k = Vec3<T>::UnitZ();           ///< unit laboratory vector opposite to gravity
  Vec3<T> z0 = Vec3<T>::UnitZ();          ///< unit body vector from the fixed point to the centre of mass
  Vec3<T> body_torque = Vec3<T>::Zero();  ///< M_body (has_constant)
  Vec3<T> lab_torque = Vec3<T>::Zero();   ///< M_lab (has_constant)
  Mat3<T> damping = Mat3<T>::Zero();      ///< C (has_damping)
  Mat3<T> target = Mat3<T>::Identity();   ///< R_d (has_control)
  Vec3<T> target_omega = Vec3<T>::Zero(); ///< Ω_d, the target's body angular velocity (has_control)
  T k_R = T(0);                           ///< the controller's proportional gain (has_control)
  T k_Omega = T(0);                       ///< the controller's derivative gain (has_control)
  std::shared_ptr<const TorqueTable> table;  ///< M_tab(t); null: no table term
  bool table_in_lab = false;              ///< the table's torques are laboratory-frame (else body-frame)
  bool has_constant = false;              ///< M_body, M_lab present
  bool has_damping = false;               ///< −CΩ present
  bool has_control = false;               ///< the PD law present
  T orbit_rate = T(0);                    ///< n of the gravity-gradient term (has_gravity_gradient)
  Vec3<T> radial = Vec3<T>::UnitX();      ///< r̂0, unit, the orbit's radial direction at t = 0 (has_gravity_gradient)
  Vec3<T> normal = Vec3<T>::UnitZ();      ///< ν, unit orbit normal ⊥ r̂0 (has_gravity_gradient)
  bool has_gravity_gradient = false;      ///< the gravity-gradient torque present

  /// V(R) = b k·(R z0) + k_R ½ tr(I − R_dᵀR).
  T potential(const Mat3<T>& R) const {
    T V = b * k.dot(R * z0);
    if (has_control) V += k_R * (T(3) - (target.transpose() * R).trace()) / T(2);
    return V;
  }
  /// M(t, R, Ω), body frame (this header's sum; t read by the table only). Not inlined into the steps
  /// (noinline): one call per stage, for the compile time of the 30 methods' flattened steps, each of which would
  /// carry every term's code (the cost per step: docs/performance.md, "rigid_body").
  [[gnu::noinline]] Vec3<T> torque(const T& t, const Mat3<T>& R, const Vec3<T>& Omega) const {
    Vec3<T> M = b * Vec3<T>(R.transpose() * k).cross(z0);
    if (has_constant) M += body_torque + R.transpose() * lab_torque;
    if (table) {
      const Vec3<T> Mt = (*table)(t);
      M += table_in_lab ? Vec3<T>(R.transpose() * Mt) : Mt;
    }
    if (has_damping) M -= damping * Omega;
    if (has_control) M -= k_R * attitude_error(R) + k_Omega * rate_error(R, Omega);
    if (has_gravity_gradient) [[unlikely]]
      M += gravity_gradient(t, R);
    return M;
  }
  /// 3n² ρ × (Jρ), ρ = Rᵀ r̂(t): the gravity-gradient term (problems/satellite.hpp's torque, the same operations).
  /// Out of line: torque() of a body without it only tests the flag.
  [[gnu::noinline]] Vec3<T> gravity_gradient(const T& t, const Mat3<T>& R) const {
    using std::cos;
    using std::sin;
    const T phase = orbit_rate * t;
    const Vec3<T> rho = R.transpose() * Vec3<T>(cos(phase) * radial + sin(phase) * Vec3<T>(normal.cross(radial)));
    return (T(3) * orbit_rate * orbit_rate) * Vec3<T>(rho.cross(inertia * rho));
  }
  /// D = ∂M/∂Ω = −C − k_Ω I (the terms that read Ω are linear in it): the forced LGVI's Newton (integrators/lgvi.hpp).
  Mat3<T> torque_omega_jacobian(const T&, const Mat3<T>&, const Vec3<T>&) const {
    Mat3<T> D = Mat3<T>::Zero();
    if (has_damping) D -= damping;
    if (has_control) D -= k_Omega * Mat3<T>::Identity();
    return D;
  }
  /// e_R = ½ vee(R_dᵀR − RᵀR_d).
  Vec3<T> attitude_error(const Mat3<T>& R) const { return lgi::attitude_error(target, R); }
  /// e_Ω = Ω − RᵀR_d Ω_d.
  Vec3<T> rate_error(const Mat3<T>& R, const Vec3<T>& Omega) const {
    return Omega - R.transpose() * (target * target_omega);
  }

  /// The extra output columns: the spatial momentum m = R J Ω and |JΩ| (the free body's invariants; here they
  /// change by the torques' action).
  static constexpr std::array<std::string_view, 4> invariant_names = momentum_column_names;
  /// None of them is an integral of the motion (the command does not report their drift as an error).
  static constexpr std::size_t integral_count = 0;
  /// (m1, m2, m3, |JΩ|) of x.
  std::array<T, 4> invariants(const State<T>& x) const { return momentum_columns(inertia, x); }
  /// The last time the torque is defined at: the table's last sample, +∞ without a table (the scene loader refuses
  /// a t_end beyond it).
  double time_limit() const { return table ? table->t_last() : std::numeric_limits<double>::infinity(); }
  /// The files the problem's data were read from, with a hash of their bytes (the table's; checkpoints record them
  /// so that a resume refuses a file that changed).
  std::vector<std::pair<std::string, std::uint64_t>> input_files() const {
    if (table && !table->source().empty()) return {{table->source(), table->digest()}};
    return {};
  }

  /// k (UniformGravityProblem: the sweeps' tilt and height of z0).
  Vec3<T> gravity_axis() const { return k; }
  /// z0 (UniformGravityProblem).
  Vec3<T> mass_axis() const { return z0; }

  /// The same body in scalar S (e.g. double → ceres::Jet).
  template <class S>
  TorquedBody<S> cast() const {
    TorquedBody<S> c;
    c.inertia = inertia.template cast<S>();
    c.b = S(b);
    c.k = k.template cast<S>();
    c.z0 = z0.template cast<S>();
    c.body_torque = body_torque.template cast<S>();
    c.lab_torque = lab_torque.template cast<S>();
    c.damping = damping.template cast<S>();
    c.target = target.template cast<S>();
    c.target_omega = target_omega.template cast<S>();
    c.k_R = S(k_R);
    c.k_Omega = S(k_Omega);
    c.table = table;
    c.table_in_lab = table_in_lab;
    c.has_constant = has_constant;
    c.has_damping = has_damping;
    c.has_control = has_control;
    c.orbit_rate = S(orbit_rate);
    c.radial = radial.template cast<S>();
    c.normal = normal.template cast<S>();
    c.has_gravity_gradient = has_gravity_gradient;
    return c;
  }
};

}  // namespace lgi
