// benchmarks/wp_lgi_top.cpp — lgi's methods on the cases with gravity (HeavyTop<double>; a lagrange_top
// case runs them on the same body as a heavy top with z0 = e3, plus lagrange_split and its compositions on
// the LagrangeTop). The preprocessed DMV (split_dmv4 … 10) is order 2 with a torque and is run on
// torque-free cases only.
#include "wp_lgi.hpp"

#include <lgi/integrators/commutator_free.hpp>
#include <lgi/integrators/composition.hpp>
#include <lgi/integrators/lagrange_split.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/integrators/split_exact.hpp>
#include <lgi/integrators/splitting.hpp>

namespace wp {

std::vector<Method> lgi_methods_top(const Case& c) {
  using P = lgi::HeavyTop<double>;
  const P& p = c.heavy_top;
  std::vector<Method> m{
      lgi_method<lgi::Lgvi<P>>(p, false),
      lgi_method<lgi::SplitDmv<P>>(p, false),
      lgi_method<lgi::SplitAxes<P>>(p, false),
      lgi_method<lgi::SplitExact<P>>(p, false),
      lgi_method<lgi::LgviYoshida4<P>>(p, false),
      lgi_method<lgi::LgviSuzuki4<P>>(p, false),
      lgi_method<lgi::LgviYoshida6<P>>(p, false),
      lgi_method<lgi::LgviKahanLi6<P>>(p, false),
      lgi_method<lgi::LgviYoshida8<P>>(p, false),
      lgi_method<lgi::LgviKahanLi8<P>>(p, false),
      lgi_method<lgi::LgviSofroniouSpaletta10<P>>(p, false),
      lgi_method<lgi::SplitDmvYoshida4<P>>(p, false),
      lgi_method<lgi::SplitDmvSuzuki4<P>>(p, false),
      lgi_method<lgi::SplitDmvKahanLi6<P>>(p, false),
      lgi_method<lgi::SplitDmvKahanLi8<P>>(p, false),
      lgi_method<lgi::SplitDmvSofroniouSpaletta10<P>>(p, false),
      lgi_method<lgi::Rkmk4<P>>(p, false),
      lgi_method<lgi::Cf4<P>>(p, false),
      lgi_method<lgi::RkmkDp5<P>>(p, false, true),
      lgi_method<lgi::RkmkDp8<P>>(p, false, true),
      lgi_method<lgi::Rkmk4Cayley<P>>(p, false),
      lgi_method<lgi::RkmkDp5Cayley<P>>(p, false, true),
      lgi_method<lgi::RkmkDp8Cayley<P>>(p, false, true),
      lgi_method<lgi::RkmkVern9<P>>(p, false, true),
      lgi_method<lgi::RkmkVern9Cayley<P>>(p, false, true),
      lgi_method<lgi::Projected<lgi::Rkmk4<P>>>(p, false),
      lgi_method<lgi::Projected<lgi::RkmkDp8Cayley<P>>>(p, false, true),
  };
  if (c.kind == Kind::lagrange_top)
  {
    using LT = lgi::LagrangeTop<double>;
    m.push_back(lgi_method<lgi::LagrangeSplit<LT>>(c.lagrange_top, false));
    m.push_back(lgi_method<lgi::LagrangeSplitYoshida4<LT>>(c.lagrange_top, false));
    m.push_back(lgi_method<lgi::LagrangeSplitKahanLi6<LT>>(c.lagrange_top, false));
    m.push_back(lgi_method<lgi::LagrangeSplitKahanLi8<LT>>(c.lagrange_top, false));
    m.push_back(lgi_method<lgi::LagrangeSplitSofroniouSpaletta10<LT>>(c.lagrange_top, false));
  }
  return m;
}

std::vector<Method> lgi_methods(const Case& c) {
  return c.kind == Kind::free_body ? lgi_methods_free_body(c) : lgi_methods_top(c);
}

}  // namespace wp
