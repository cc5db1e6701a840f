/// \file
/// lgi/integrators/exact.hpp — the exact solution of the free rigid body as a method: every step evaluates the
/// motion from the run's initial state at the step's end time.
///
/// Update (x0 = (R0, Ω0) the state given at t0, the start of the run or the last state set from outside):
///
/// ~~~{.unparsed}
///   (R_{n+1}, Ω_{n+1}) = Φ_{t_n + h − t0}(R0, Ω0)
/// ~~~
///
/// with Φ_τ the Euler–Poinsot flow by Jacobi elliptic functions and Π(n; ϕ, κ) (problems/free_body_exact.hpp:
/// Celledoni, Fassò, Säfström & Zanna, SIAM J. Sci. Comput. 30 (2008) 2084, §2.2, with Leroy's corrections).
/// Not a composition of steps: the state at each step's end is one evaluation of the closed form from x0, so dt
/// is only the spacing of the states computed (the output times) and no error accumulates from step to step.
///
/// Exact: no truncation error (order ∞, MethodTraits::exact_solution); round-off only. The constants and every
/// evaluation are in double (FreeBodyExact<T, T>): their relative rounding, a few ε, becomes a phase error that
/// grows linearly in t — the same growth as the state's own sensitivity to its initial data, so the error
/// stays a few ε × that sensitivity at any t (measured against the same formulas in 113-bit arithmetic for
/// t = 10 … 10⁴: tests/problems/test_free_body_exact.cpp, ExactMethod.*; docs/free_body_exact.md). Preserves what the flow does: R
/// on SO(3) to round-off, the energy, |JΩ| and the spatial momentum R J Ω to round-off at every t, without
/// growth or drift (each state is computed from x0, not from the previous one); symplectic and symmetric as
/// the flow itself.
///
/// Applies to torque-free problems (P::has_torque false: the free body, any symmetric positive-definite J)
/// with floating-point scalars (no ceres::Jet).
/// Cost: the first step solves (one Carlson duplication for R_F and R_J, and K, Π(n | κ) once: one AGM); each
/// step then costs one evaluation (a Landen descent, one duplication, one 3 × 3 frame), independent of t and of dt.
#pragma once

#include "../core/integrator.hpp"
#include "../core/problem.hpp"
#include "../core/state.hpp"
#include "../core/state_io.hpp"
#include "../problems/free_body_exact.hpp"

#include <cstring>
#include <type_traits>

namespace lgi {

/// The free body's exact solution (this header) as a Stepper on a torque-free problem P: explicit, exact,
/// symplectic and symmetric. Floating-point scalars only.
template <AttitudeTorqueProblem P>
  requires(!P::has_torque && std::is_floating_point_v<typename P::Scalar>)
class ExactFreeBody {
 public:
  using Problem = P;                  ///< the problem type
  using Scalar = typename P::Scalar;  ///< its scalar (floating point: no Jets)
  /// The initial state and its time, and the current state: each step evaluates the motion from (R0, Ω0, t0).
  struct Internal {
    Mat3<Scalar> R0;      ///< attitude at t0
    Vec3<Scalar> Omega0;  ///< body angular velocity at t0
    Scalar t0;            ///< the time of (R0, Ω0)
    Mat3<Scalar> R;       ///< attitude at the current time
    Vec3<Scalar> Omega;   ///< body angular velocity at the current time
    LGI_NUMBERS(R0, Omega0, t0, R, Omega)
  };

  /// The method's traits.
  static constexpr MethodTraits traits{
      .name = "exact",
      .title = "Exact solution of the free rigid body (Jacobi elliptic functions), one evaluation per output time",
      .order = 0,
      .symplectic = true,
      .symmetric = true,
      .explicit_method = true,
      .exact_on_group = true,
      .preserves_momentum = true,
      .reference = "Celledoni, Fasso, Safstrom, Zanna, SIAM J. Sci. Comput. 30 (2008) 2084, Sect. 2.2",
      .exact_solution = true,
  };

  /// Copies the problem and diagonalises J (FreeBodyExact: std::invalid_argument unless J is finite, symmetric and
  /// positive definite); std::invalid_argument from StepperOptions::check (no option is read).
  explicit ExactFreeBody(const P& problem, const StepperOptions& options = {})
      : problem_(problem), exact_(problem.inertia) {
    options.check();
  }

  /// x as the initial state at t (and as the current state). The next step solves the motion anew (a state set from
  /// outside starts a run: its solve belongs to it, also in timings).
  Internal to_internal(const State<Scalar>& x, const Scalar& t) const {
    solved_ = false;
    return {x.R, x.Omega, t, x.R, x.Omega};
  }
  /// The current state of y.
  State<Scalar> to_state(const Internal& y) const { return {y.R, y.Omega}; }

  /// The state at t + h, evaluated from (y.R0, y.Omega0) at y.t0: ok, or non_finite (y untouched) when it is not
  /// finite. Solves the motion when y's initial state is not the one solved last (the first step; a state set from
  /// outside), then one evaluation; allocates nothing. The result depends on (y, t, h) only.
  StepStatus step(Internal& y, const Scalar& t, const Scalar& h) {
    // The cache's key compared bit for bit (−0 and +0 differ; a NaN never matches, and is solved again).
    if (!solved_ || std::memcmp(y.R0.data(), R0_.data(), sizeof(R0_)) != 0 ||
        std::memcmp(y.Omega0.data(), Omega0_.data(), sizeof(Omega0_)) != 0) {
      solution_ = exact_.solve(State<Scalar>{y.R0, y.Omega0});
      solution_.precompute_periods();
      R0_ = y.R0;
      Omega0_ = y.Omega0;
      solved_ = true;
    }
    const State<Scalar> x = solution_.state(Scalar(t + h - y.t0));
    if (!is_finite(x)) return StepStatus::non_finite;
    y.R = x.R;
    y.Omega = x.Omega;
    return StepStatus::ok;
  }

  /// The problem, as copied at construction.
  const P& problem() const { return problem_; }

 private:
  using Exact = FreeBodyExact<Scalar, Scalar>;
  P problem_;
  Exact exact_;
  // The motion of the last initial state solved (a cache: a function of (R0_, Omega0_) alone).
  typename Exact::Solution solution_{};
  Mat3<Scalar> R0_ = Mat3<Scalar>::Zero();
  Vec3<Scalar> Omega0_ = Vec3<Scalar>::Zero();
  mutable bool solved_ = false;  // to_internal clears it: a new run solves anew
};

}  // namespace lgi
