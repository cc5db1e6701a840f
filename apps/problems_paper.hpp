// Problems: the seed paper's Euler-angle formulation (see registry.hpp).
//
// lagrange_top_euler_angles (problems/euler_angle_top.hpp) has its state in R^6, not on SO(3): SO(3)
// methods do not apply to it, and apps/runner.cpp runs it through its own path. The methods that do
// apply are the RKMK methods with a Butcher tableau, run as that tableau's plain Runge–Kutta method on the
// angles (integrators/euclidean_rk.hpp: RKMK on the additive group R^n is exactly that method), so a
// scene names them as for any problem ("rkmk4" is then classical RK4 on the Euler angles).
#pragma once

#include <lgi/integrators/euclidean_rk.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/problems/euler_angle_top.hpp>
#include <lgi/problems/free_body.hpp>

#include <string_view>
#include <type_traits>

namespace lgi::app {

using PaperProblems = ProblemList<EulerAngleTop<double>>;

// True for the problems of this family whose state is not on SO(3): they take no integrator options
// (rtol, atol, projection, ...), only the method's tableau with fixed steps (apps/scene.cpp).
inline bool runs_off_group(std::string_view type) { return type == EulerAngleTop<double>::name; }

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
    return rkmk_tableau<M<FreeBody<double>>>::value;
  else
    return false;
}();

}  // namespace lgi::app
