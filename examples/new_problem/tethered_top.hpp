// A new problem in lgi, defined by its potential alone (docs/new_problem.md walks through it).
// A heavy top whose body point p is tied by a spring (stiffness kappa, rest length L0) to a fixed
// laboratory anchor: V(R) = ½ κ (|R p − anchor| − L0)² + b k·(R z0). lgi derives the torque.
#pragma once

#include <lgi/core/driver.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/problems/potential_problem.hpp>

#include <string_view>

namespace tutorial {

using lgi::Mat3;
using lgi::Vec3;

struct TetherPotential {
  static constexpr std::string_view name = "tethered_top";  // its name in scenes and output
  double kappa = 20, L0 = 0.5, b = 1;
  Vec3<double> p{0, 0, 1}, anchor{0.5, 0, 1}, k{0, 0, 1}, z0{0, 0, 1};

  template <class S>  // S: double, or the dual number lgi differentiates with
  S operator()(const Mat3<S>& R) const {
    using std::sqrt;
    const Vec3<S> d = R * p.cast<S>() - anchor.cast<S>();
    const S stretch = sqrt(d.squaredNorm()) - S(L0);
    return S(0.5 * kappa) * stretch * stretch + S(b) * k.cast<S>().dot(R * z0.cast<S>());
  }
};

using TetheredTop = lgi::PotentialProblem<double, TetherPotential>;

// Integrate it with the LGVI for t_end time units; returns the final state.
inline lgi::State<double> run_tethered_top(double h, double t_end) {
  const TetheredTop top{Vec3<double>(2, 2, 1).asDiagonal(), TetherPotential{}};
  lgi::State<double> x;  // R = I
  x.Omega = {0.3, -0.2, 4.0};
  lgi::Lgvi<TetheredTop> stepper(top);
  lgi::integrate_to(stepper, x, 0.0, h, t_end);
  return x;
}

}  // namespace tutorial
