// lgi/apps/auto_method.hpp — `"integrator": {"method": "auto", "tolerance": ε}`: the method and its settings chosen
// from the problem's structure, the tolerance and the horizon.
//
// The tolerance ε bounds the global error at every output time, measured as `lgi run --error-estimate` measures it:
// the rotation angle between the computed and the true attitude, |log(R_trueᵀ R)| (radians), plus |Ω − Ω_true| /
// max(|Ω|, |Ω0|).
// The choice, in this order (each from the first method of the list this build offers for the problem):
//
//   1. A free body (the method `exact` applies): the exact solution, one evaluation per output time; dt = t_end (it
//      only spaces the states). Error ≈ 1e-16 × the state's sensitivity to its initial data, whatever ε.
//   2. An axisymmetric top with its centre of mass on the axis (`lagrange_split_*` apply): the composition of the
//      spin-frame splitting of order 8 (Kahan–Li, ε ≥ 1e-8) or 10 (Sofroniou–Spaletta, ε < 1e-8), fixed steps.
//   3. A problem an embedded pair applies to: `rkmk_vern9_cayley` (Verner's 9(8) pair in Cayley coordinates),
//      adaptive with rtol = atol = ε / (1 + T·ω / 20), ω = |Ω0| + (the gravity's frequency scale √(b / min J_ii)), the first
//      step 0.1 / ω; with `"projection": true` on a conservative problem whose horizon exceeds 10⁴ radians of
//      rotation (T·ω), where the controller's local error would otherwise let the energy drift.
//   4. Otherwise (a build without the embedded pairs: LGI_METHODS): `rkmk4` or `lgvi` with fixed steps.
//
// The fixed steps (2 and 4) come from probes of the method's local error at the initial state: one step of h against
// two of h/2 gives the local error l(h) = C h^(p+1) (p the method's order on the problem); the global error after
// T/h steps, assumed to grow linearly in time, is then T·C·h^p, and h = (ε / (2 T C))^(1/p), rounded so that a whole
// number of steps ends at t_end. The probe is repeated at that step until two successive constants C agree within a
// factor 3 (at most 6 probes, 3 steps each); h is capped at T and, for methods that integrate the whole rotation (4),
// at 1 / |Ω0|. The probes' steps and wall time are reported with the choice.
//
// Not offered for a problem whose state is not on SO(3) × R³ (the Euler-angle top). The assumptions — error growing
// linearly in time, the local error at the initial state representative of the orbit, the pair's global error
// within (1 + T·ω / 20) of its tolerance — hold on regular motions; chaotic motion amplifies every error
// exponentially, and no choice of method bounds the global error there. `lgi run` therefore estimates the global
// error of every `auto` run (runner.hpp, estimate_error) and warns when the estimate exceeds 10 ε.
#pragma once

#include "scene.hpp"

namespace lgi::app {

// The smallest and largest tolerances "auto" accepts: below 1e-13 the double-precision methods' round-off, which
// grows with the number of steps, dominates; above 1e-1 no error estimate is meaningful.
inline constexpr double auto_min_tolerance = 1e-13, auto_max_tolerance = 1e-1;

// Sets scene.method, dt and options for "auto" at `tolerance` (scene.auto_choice says what and why), from the
// scene's problem, initial state and t_end (output times are not needed). Throws std::invalid_argument with the
// reason when no method applies (a problem not on SO(3) × R³) — the caller names the scene path.
void choose_auto(Scene& scene, double tolerance);

}  // namespace lgi::app
