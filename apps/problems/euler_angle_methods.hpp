// lgi/apps/problems/euler_angle_methods.hpp — which methods apply to the seed paper's Euler-angle top.
//
// lagrange_top_euler_angles (problems/euler_angle_top.hpp) has its state in R^8, not on SO(3): SO(3) methods do not
// apply to it. The methods that do are the RKMK methods with a Butcher tableau, run as that tableau's plain
// Runge–Kutta method on the angles (integrators/euclidean_rk.hpp: RKMK on the additive group R^n is exactly that
// method), so a scene names them as for any problem ("rkmk4" is then classical RK4 on the Euler angles). They run
// with fixed steps and take no integrator options (rtol, atol, projection, ...).
#pragma once

#include <lgi/integrators/euclidean_rk.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/problems/euler_angle_top.hpp>
#include <lgi/problems/free_body.hpp>

#include <type_traits>

namespace lgi::app {

// The Butcher tableau behind a method: set for Rkmk<Tableau, P>, absent otherwise.
template <class S>
struct rkmk_tableau : std::false_type {};
template <const auto& Tab, RigidBodyProblem P>
struct rkmk_tableau<Rkmk<Tab, P>> : std::true_type {
  static constexpr const auto& tableau = Tab;
};

// A method applies to the Euler-angle top when it is an RKMK method with a tableau.
template <template <class> class M>
inline constexpr bool method_applies_v<M, EulerAngleTop<double>> = [] {
  if constexpr (requires { typename M<FreeBody<double>>; })
    return rkmk_tableau<M<FreeBody<double>>>::value && method_enabled(M<FreeBody<double>>::traits.name);
  else
    return false;
}();

}  // namespace lgi::app
