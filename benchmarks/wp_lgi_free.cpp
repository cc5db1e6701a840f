// benchmarks/wp_lgi_free.cpp — lgi's methods on the torque-free cases (FreeBody<double>). split_exact is
// left out here: on a free body it is the exact solution, the same code as the reference.
#include "wp_lgi.hpp"

#include <lgi/integrators/commutator_free.hpp>
#include <lgi/integrators/composition.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/integrators/splitting.hpp>

namespace wp {

std::vector<Method> lgi_methods_free_body(const Case& c) {
  using P = lgi::FreeBody<double>;
  const P& p = c.free_body;
  return {
      lgi_method<lgi::Lgvi<P>>(p, true),
      lgi_method<lgi::SplitDmv<P>>(p, true),
      lgi_method<lgi::SplitAxes<P>>(p, true),
      lgi_method<lgi::SplitDmv4<P>>(p, true),
      lgi_method<lgi::SplitDmv6<P>>(p, true),
      lgi_method<lgi::SplitDmv8<P>>(p, true),
      lgi_method<lgi::SplitDmv10<P>>(p, true),
      lgi_method<lgi::LgviYoshida4<P>>(p, true),
      lgi_method<lgi::LgviSuzuki4<P>>(p, true),
      lgi_method<lgi::LgviYoshida6<P>>(p, true),
      lgi_method<lgi::LgviKahanLi6<P>>(p, true),
      lgi_method<lgi::LgviYoshida8<P>>(p, true),
      lgi_method<lgi::LgviKahanLi8<P>>(p, true),
      lgi_method<lgi::LgviSofroniouSpaletta10<P>>(p, true),
      lgi_method<lgi::SplitDmvYoshida4<P>>(p, true),
      lgi_method<lgi::SplitDmvSuzuki4<P>>(p, true),
      lgi_method<lgi::SplitDmvKahanLi6<P>>(p, true),
      lgi_method<lgi::SplitDmvKahanLi8<P>>(p, true),
      lgi_method<lgi::SplitDmvSofroniouSpaletta10<P>>(p, true),
      lgi_method<lgi::Rkmk4<P>>(p, true),
      lgi_method<lgi::Cf4<P>>(p, true),
      lgi_method<lgi::RkmkDp5<P>>(p, true, true),
      lgi_method<lgi::RkmkDp8<P>>(p, true, true),
      lgi_method<lgi::Rkmk4Cayley<P>>(p, true),
      lgi_method<lgi::RkmkDp5Cayley<P>>(p, true, true),
      lgi_method<lgi::RkmkDp8Cayley<P>>(p, true, true),
      lgi_method<lgi::RkmkVern9<P>>(p, true, true),
      lgi_method<lgi::RkmkVern9Cayley<P>>(p, true, true),
      lgi_method<lgi::Projected<lgi::Rkmk4<P>>>(p, true),
      lgi_method<lgi::Projected<lgi::RkmkDp8Cayley<P>>>(p, true, true),
  };
}

}  // namespace wp
