// lgi/apps/problems/heavy_top.cpp — the `heavy_top` problem type of scenes: its parser and its registration (every method
// that applies to it is compiled here, problem_model.hpp).
#include "../problem_model.hpp"

#include <lgi/problems/heavy_top.hpp>

namespace lgi::app {
namespace {

HeavyTop<double> parse(const Node& p) {
  HeavyTop<double> top;
  top.inertia = read_inertia(p.at("inertia"));
  top.b = p.at("b").non_negative();
  if (auto k = p.find("k")) top.k = read_unit_vector(*k);
  if (auto z0 = p.find("z0")) top.z0 = read_unit_vector(*z0);
  return top;
}

}  // namespace

LGI_DEFINE_PROBLEM(heavy_top, HeavyTop<double>, "heavy top, seed paper eqs. (s4)-(s5): torque b (R^T k) x z0", ({"type", "inertia", "b", "k", "z0"}), parse)

// The heavy top's integrators, for the problem types that move as one (runner_impl.hpp, integrator_of).
template std::unique_ptr<Integrator> runner_detail::integrator_of<HeavyTop<double>>(const HeavyTop<double>&,
                                                                                    const Scene&);

}  // namespace lgi::app
