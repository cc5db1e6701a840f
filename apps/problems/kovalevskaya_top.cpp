// lgi/apps/problems/kovalevskaya_top.cpp — the `kovalevskaya_top` problem type of scenes: its parser and its registration. Its
// motion is a heavy top's: the methods are those compiled in heavy_top.cpp (runner_impl.hpp, integrator_of).
#include "../problem_model.hpp"

#include <lgi/problems/kovalevskaya_top.hpp>

#include <cmath>
#include <string>

namespace lgi::app {

// Its motion is the heavy top's (KovalevskayaTop::as_heavy_top): those integrators, compiled in heavy_top.cpp.
extern template std::unique_ptr<Integrator> runner_detail::integrator_of<HeavyTop<double>>(const HeavyTop<double>&,
                                                                                           const Scene&);

namespace {

KovalevskayaTop<double> parse(const Node& p) {
  const Node inertia = p.at("inertia");
  const Vec3<double> I = read_principal_inertia(inertia, "principal axes");
  if (!nearly_equal(I(0), I(1)) || !nearly_equal(I(0), 2 * I(2)))
    inertia.fail("a Kovalevskaya top has I1 = I2 = 2 I3, got " + format_number(I(0)) + ", " + format_number(I(1)) +
                 ", " + format_number(I(2)));
  KovalevskayaTop<double> top = KovalevskayaTop<double>::make((I(0) + I(1) + 2 * I(2)) / 6, p.at("b").non_negative());
  if (auto k = p.find("k")) top.k = read_unit_vector(*k);
  if (auto z0 = p.find("z0")) {
    Vec3<double> z = read_unit_vector(*z0);
    if (!(std::abs(z.z()) <= 1e-9))
      z0->fail("the centre of mass of a Kovalevskaya top lies in the equatorial plane: z0[2] must be 0 (to 1e-9), "
               "got " + format_number(z.z()));
    z.z() = 0;
    top.z0 = z.normalized();
  }
  return top;
}


}  // namespace

LGI_DEFINE_PROBLEM(kovalevskaya_top, KovalevskayaTop<double>, "Kovalevskaya top: J = diag(2 I3, 2 I3, I3), centre of mass z0 in the equatorial plane; Kovalevskaya's integral", ({"type", "inertia", "b", "k", "z0"}), parse)

}  // namespace lgi::app
