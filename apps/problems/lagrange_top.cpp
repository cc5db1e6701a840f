// lgi/apps/problems/lagrange_top.cpp — the `lagrange_top` problem type of scenes: its parser and its registration. Its
// motion is a heavy top's: the methods the heavy top takes are those compiled in heavy_top.cpp, the splittings for
// axisymmetric tops are compiled here (runner_impl.hpp, integrator_of).
#include "../problem_model.hpp"

#include <lgi/problems/lagrange_top.hpp>

#include <cmath>
#include <string>

namespace lgi::app {

// Its motion is the heavy top's (LagrangeTop::as_heavy_top): those integrators, compiled in heavy_top.cpp.
extern template std::unique_ptr<Integrator> runner_detail::integrator_of<HeavyTop<double>>(const HeavyTop<double>&,
                                                                                           const Scene&);

namespace {

LagrangeTop<double> parse(const Node& p) {
  const Node inertia = p.at("inertia");
  const Vec3<double> I = read_principal_inertia(inertia, "principal axes, symmetry axis e3");
  if (!nearly_equal(I(0), I(1)))
    inertia.fail("a Lagrange top has I1 = I2 (symmetry axis e3), got I1 = " + format_number(I(0)) +
                 ", I2 = " + format_number(I(1)));
  LagrangeTop<double> top = LagrangeTop<double>::make(0.5 * (I(0) + I(1)), I(2), p.at("b").non_negative());
  if (auto k = p.find("k")) top.k = read_unit_vector(*k);
  return top;
}


}  // namespace

LGI_DEFINE_PROBLEM(lagrange_top, LagrangeTop<double>, "Lagrange top: J = diag(I1, I1, I3), centre of mass on the symmetry axis e3; invariants m.k, m_psi = I3 Omega3", ({"type", "inertia", "b", "k"}), parse)

}  // namespace lgi::app
