// benchmarks/bench_cases.hpp — the problems, initial states and stepping loop shared by bench_steps
// (Google Benchmark, ns/step) and lgi_step_count (callgrind, instructions/step), plus the hand-written
// quaternion RK4 baseline that measures lgi's abstraction penalty. Not part of the library.
//
// Cases (h = 0.01, R0 = 1, m0 = JΩ0 = (1.8, 0.4, −0.9), the Hairer–Vilmart momentum; NUMERICS.md):
//   heavy_top        Hairer–Vilmart heavy top: J = diag(0.6, 0.8, 1.0), b = 1, k = z0 = e3.
//   heavy_top_tilted non-diagonal J = [0.8 0.1 −0.05; 0.1 0.7 0.05; −0.05 0.05 0.9] (principal moments
//                    ≈ 0.63, 0.80, 0.97), b = 1, k = e3, z0 = (0.48, 0.6, 0.64) off every principal axis:
//                    the general code path (full 3×3 J and J⁻¹ products, general Γ × z0).
//   free_body        Hairer–Vilmart free body: J = diag(0.6, 0.8, 1.0).
// Every run steps in periods of `period_steps` = 1000 steps (T = 10, the HV horizon), restarting from
// the initial state each period, so that timed and counted runs follow the same bounded trajectory
// segment (Lie–Euler is not stable over long runs) whatever the number of steps.
#pragma once

#include <lgi/core/inertia.hpp>
#include <lgi/core/integrator.hpp>
#include <lgi/core/state.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <Eigen/Core>

#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace bench {

inline constexpr double h = 0.01;
inline constexpr int period_steps = 1000;

inline lgi::Vec3<double> hv_momentum() { return {1.8, 0.4, -0.9}; }

template <class P>
lgi::State<double> initial_state(const P& p) {
  return {lgi::Mat3<double>::Identity(), p.inertia.inverse() * hv_momentum()};
}

inline lgi::HeavyTop<double> heavy_top_hv() { return lgi::HeavyTop<double>::hairer_vilmart(); }
inline lgi::FreeBody<double> free_body_hv() { return lgi::FreeBody<double>::hairer_vilmart(); }

inline lgi::HeavyTop<double> heavy_top_tilted() {
  lgi::HeavyTop<double> p;
  p.inertia << 0.8, 0.1, -0.05,  //
      0.1, 0.7, 0.05,            //
      -0.05, 0.05, 0.9;
  p.b = 1.0;
  p.k = lgi::Vec3<double>::UnitZ();
  p.z0 = lgi::Vec3<double>(0.48, 0.6, 0.64);  // unit: 0.2304 + 0.36 + 0.4096 = 1
  if (const auto defect = lgi::inertia_defect(p.inertia)) {
    std::fprintf(stderr, "heavy_top_tilted: %s\n", defect->c_str());
    std::abort();
  }
  return p;
}

// Hand-written reference, no lgi abstractions: classical RK4 on the unit quaternion q = (s, v) and the
// body angular velocity Ω of the HV heavy top (diagonal J as a 3-vector), q renormalised after each
// step. q' = ½ q ⊗ (0, Ω) = ½ (−v·Ω, sΩ + v × Ω); Γ = Rᵀk = k − 2s v × k + 2 v × (v × k);
// Ω' = J⁻¹((JΩ) × Ω + b Γ × z0). Not geometric: energy drifts like RK4, q leaves S³ between
// renormalisations. No finiteness check (lgi's steppers check every step).
struct QuatRk4 {
  struct Internal {
    Eigen::Vector4d q;  // (s, v1, v2, v3)
    Eigen::Vector3d w;  // body angular velocity Ω
  };
  Eigen::Vector3d I, I_inv, k, z0;
  double b;

  explicit QuatRk4(const lgi::HeavyTop<double>& p)
      : I(p.inertia.diagonal()), I_inv(I.cwiseInverse()), k(p.k), z0(p.z0), b(p.b) {
    if (!lgi::Inertia<double>::is_diagonal(p.inertia)) {
      std::fprintf(stderr, "QuatRk4: needs a diagonal inertia tensor\n");
      std::abort();
    }
  }

  Internal to_internal(const lgi::State<double>& x, double /*t*/) const {
    const Eigen::Quaterniond q(x.R);
    return {Eigen::Vector4d(q.w(), q.x(), q.y(), q.z()), x.Omega};
  }

  void rhs(const Internal& y, Internal& d) const {
    const double s = y.q(0);
    const Eigen::Vector3d v = y.q.tail<3>();
    d.q(0) = -0.5 * v.dot(y.w);
    d.q.tail<3>() = 0.5 * (s * y.w + v.cross(y.w));
    const Eigen::Vector3d vk = v.cross(k);
    const Eigen::Vector3d Gamma = k - 2 * s * vk + 2 * v.cross(vk);
    d.w = I_inv.cwiseProduct(I.cwiseProduct(y.w).cross(y.w) + b * Gamma.cross(z0));
  }

  lgi::StepStatus step(Internal& y, double /*t*/, double dt) const {
    Internal k1, k2, k3, k4, z;
    rhs(y, k1);
    z = {y.q + 0.5 * dt * k1.q, y.w + 0.5 * dt * k1.w};
    rhs(z, k2);
    z = {y.q + 0.5 * dt * k2.q, y.w + 0.5 * dt * k2.w};
    rhs(z, k3);
    z = {y.q + dt * k3.q, y.w + dt * k3.w};
    rhs(z, k4);
    y.q += (dt / 6) * (k1.q + 2 * k2.q + 2 * k3.q + k4.q);
    y.w += (dt / 6) * (k1.w + 2 * k2.w + 2 * k3.w + k4.w);
    y.q /= y.q.norm();
    return lgi::StepStatus::ok;
  }
};

// One period: `n` steps from y0 into y. False when a step fails (y then holds the last good state).
template <class S, class Y, class Sink>
bool run_period(S& stepper, const Y& y0, Y& y, int n, Sink&& sink) {
  y = y0;
  for (int i = 0; i < n; ++i) {
    if (stepper.step(y, i * h, h) != lgi::StepStatus::ok) return false;
    sink(y);
  }
  return true;
}

}  // namespace bench
