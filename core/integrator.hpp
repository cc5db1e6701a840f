/// \file
/// lgi/core/integrator.hpp — what an integrator (a one-step method on SO(3) × R³) is.
///
/// A stepper is a small class constructed from a problem (and StepperOptions), with its method's traits
/// as compile-time data, the coordinates it steps in, and one step function:
///
/// ~~~{.unparsed}
///   using Problem = P;  using Scalar = typename P::Scalar;
///   using Internal = …;                                  // State<T> (R, Ω) or MomentumState<T> (R, Π), …
///   static constexpr MethodTraits traits;
///   Internal to_internal(const State<Scalar>&, const Scalar& t) const;   // at the start of a run
///   State<Scalar> to_state(const Internal&) const;       // at output times only
///   StepStatus step(Internal& y, const Scalar& t, const Scalar& h);
/// ~~~
///
/// step advances y from time t to t + h. On any status other than `ok` it leaves y untouched, so the
/// caller always holds the last good state. Steppers allocate nothing and keep no state between steps
/// that changes their result (counters only): the same (y, t, h) always gives the same bits.
#pragma once

#include "problem.hpp"
#include "state.hpp"

#include <array>
#include <concepts>
#include <cstdint>
#include <stdexcept>
#include <string_view>

namespace lgi {

/// What a method is and what it preserves; `lgi list` and the README's method table print these.
struct MethodTraits {
  std::string_view name;         ///< scene name, e.g. "lgvi"
  std::string_view title;        ///< e.g. "Lie group variational integrator"
  int order;                     ///< classical order of convergence, on every problem the method applies to (0: exact_solution)
  int free_body_order = 0;       ///< order on torque-free problems where it is higher (0: same as order)
  bool symplectic;               ///< the step is a symplectic map of T*SO(3)
  bool symmetric;                ///< step(h) ∘ step(−h) = id (time-reversible)
  bool explicit_method;          ///< no nonlinear solve
  bool exact_on_group;           ///< R stays on SO(3) to round-off by construction
  bool preserves_momentum;       ///< the spatial momentum components conserved by the problem (m, m·k)
  std::string_view reference;    ///< paper and equation numbers
  /// The scene keys of "integrator" this method reads besides "method" and "dt" (StepperOptions fields).
  std::array<std::string_view, 6> options{};
  /// The exact solution (to round-off) of every problem the method applies to: no truncation error, dt only spaces
  /// the states computed; `order` is then 0.
  bool exact_solution = false;
};

/// The outcome of one step; anything but `ok` leaves the state y untouched.
enum class StepStatus : std::uint8_t {
  ok = 0,         ///< the step was taken and its state is finite
  not_converged,  ///< the implicit equation's Newton iteration did not converge within its limits
  non_finite,     ///< the step produced a non-finite number (torque NaN, overflow)
  step_size_underflow,  ///< adaptive: the error test failed down to the smallest step allowed
};

/// A short English description of s (for messages); "?" for a value outside the enumeration.
constexpr std::string_view to_string(StepStatus s) {
  switch (s) {
    case StepStatus::ok: return "ok";
    case StepStatus::not_converged: return "Newton iteration did not converge";
    case StepStatus::non_finite: return "non-finite state";
    case StepStatus::step_size_underflow: return "step size underflow (the error tolerance cannot be met)";
  }
  return "?";
}

/// Options of implicit steps (explicit ones ignore them).
struct StepperOptions {
  double tolerance = 1e-14;  ///< Newton: stop when the update is below tolerance · |solution|
  int max_iterations = 20;   ///< Newton: give up (StepStatus::not_converged) after this many updates
  ///@{
  /// Embedded pairs: relative and absolute error tolerances of adaptive steps; 0 = fixed steps.
  double rtol = 0, atol = 0;
  ///@}
  /// Non-symplectic methods: restore the invariants after every step (integrators/projection.hpp).
  bool projection = false;
  /// Axis-rotation splittings: the principal axes (1, 2, 3) in the order outer, middle, inner of the
  /// symmetric composition a(h/2) b(h/2) c(h) b(h/2) a(h/2); {0, 0, 0}: chosen from the moments.
  std::array<int, 3> axis_order{0, 0, 0};

  /// Throws std::invalid_argument unless 0 < tolerance < 1e-2, max_iterations ≥ 1, rtol and atol are finite
  /// and either both 0 (fixed steps) or both > 0 (integrate_adaptive also requires rtol ≥ 10 ε).
  void check() const {
    if (!(tolerance > 0 && tolerance < 1e-2))
      throw std::invalid_argument("lgi::StepperOptions: tolerance must be in (0, 0.01)");
    if (max_iterations < 1) throw std::invalid_argument("lgi::StepperOptions: max_iterations must be >= 1");
    if (!(rtol >= 0 && atol >= 0 && std::isfinite(rtol) && std::isfinite(atol)) || (rtol > 0) != (atol > 0))
      throw std::invalid_argument("lgi::StepperOptions: rtol and atol must be finite and both 0 or both > 0");
    const bool automatic = axis_order[0] == 0 && axis_order[1] == 0 && axis_order[2] == 0;
    bool permutation = true;  // {1, 2, 3} in some order
    for (int i = 0; i < 3; ++i)
      permutation = permutation && axis_order[i] >= 1 && axis_order[i] <= 3 && axis_order[i] != axis_order[(i + 1) % 3];
    if (!automatic && !permutation)
      throw std::invalid_argument("lgi::StepperOptions: axis_order must be a permutation of 1, 2, 3");
  }
};

/// What the drivers (core/driver.hpp) need of a stepper: its scalar, the coordinates it steps, and the step, which
/// leaves y untouched unless it returns ok. Every Stepper is one; so are the Euclidean steppers of
/// integrators/euclidean_rk.hpp.
template <class S>
concept StepFunction = requires(S& s, typename S::Internal& y, const typename S::Scalar& t) {
  typename S::Scalar;
  typename S::Internal;
  { s.step(y, t, t) } -> std::same_as<StepStatus>;
};

/// A one-step method whose state maps to and from a rigid body's (R, Ω): a StepFunction with its Problem, its
/// MethodTraits and the conversions to_internal / to_state. Its problem may carry more state than (R, Ω) (the
/// gyrostat's rotors, integrators/gyrostat.hpp: to_internal completes it from the problem).
template <class S>
concept StateStepper = requires(S& s, const State<typename S::Scalar>& x, typename S::Internal& y,
                                const typename S::Scalar& t) {
  typename S::Problem;
  typename S::Scalar;
  typename S::Internal;
  { S::traits } -> std::convertible_to<MethodTraits>;
  { s.to_internal(x, t) } -> std::same_as<typename S::Internal>;
  { s.to_state(y) } -> std::same_as<State<typename S::Scalar>>;
  { s.step(y, t, t) } -> std::same_as<StepStatus>;
};

/// A one-step method on SO(3) × R³: a StateStepper on a RigidBodyProblem (the contract of this header: step leaves y
/// untouched unless ok, allocates nothing, gives the same bits for the same (y, t, h)). One thread at a time per
/// stepper object (step updates its counters); copies are independent.
template <class S>
concept Stepper = StateStepper<S> && RigidBodyProblem<typename S::Problem>;

/// Writes the new attitude and velocity (or momentum) into y when all of it is finite; the steppers'
/// common last line.
template <class T>
StepStatus commit(State<T>& y, const Mat3<T>& R, const Vec3<T>& Omega) {
  if (!all_finite(R) || !all_finite(Omega)) return StepStatus::non_finite;
  y.R = R;
  y.Omega = Omega;
  return StepStatus::ok;
}
/// The same for the momentum form (R, Π): writes both into y and returns ok when all of them are finite, else
/// returns non_finite and leaves y untouched.
template <class T>
StepStatus commit(MomentumState<T>& y, const Mat3<T>& R, const Vec3<T>& Pi) {
  if (!all_finite(R) || !all_finite(Pi)) return StepStatus::non_finite;
  y.R = R;
  y.Pi = Pi;
  return StepStatus::ok;
}

#if defined(LGI_DISPATCH_CLONES)
namespace detail {
/// True when this CPU runs the AVX2 copies (core/scalar.hpp); asked once per process.
inline bool cpu_has_avx2() {
  static const bool has = [] {
    __builtin_cpu_init();  // may run before the constructors that would have called it
    return __builtin_cpu_supports("avx2") != 0;
  }();
  return has;
}
// A stepper's step in double compiled for AVX2: s.step_inline<true>, the step itself with the 4-wide code it may
// have for that copy (integrators/rkmk.hpp); results equal to the baseline's to the last bit
// (tests/core/test_dispatch.cpp).
template <class S>
[[gnu::target("avx2"), gnu::flatten]] StepStatus avx2_step(S& s, typename S::Internal& y, double t, double h) {
  return s.template step_inline<true>(y, t, h);
}
// The splittings' and RKMK's step() in double: the AVX2 copy where this CPU has AVX2, else the baseline step.
template <class S>
StepStatus dispatched_step(S& s, typename S::Internal& y, double t, double h) {
  if (cpu_has_avx2()) return avx2_step(s, y, t, h);
  return s.step_inline(y, t, h);
}
}  // namespace detail
#endif

}  // namespace lgi
