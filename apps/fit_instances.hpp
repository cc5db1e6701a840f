// apps/fit_instances.hpp — the fit templates `lgi fit` and the test_fit* executables use, instantiated once.
//
// Compile time, not behaviour: fit_observations, fit_periodic and Model (with its cost functions) for each
// (method, problem, Jet size N) that `lgi fit` offers or a test uses are instantiated in fit_instances_*.cpp
// (one OBJECT library, lgi_fit_instances, linked into the command and every test_fit* executable) and
// declared `extern template` here, so a TU that includes this header does not instantiate the integrators
// in double and Jet<N> again. Each (method, problem) costs tens of seconds of compile CPU (docs/performance.md),
// which is why `lgi fit` offers the pairs of LGI_FIT_OBSERVATION_FITS rather than every method × problem. Model's
// in-class (inline) members a test calls directly may still be instantiated there ([temp.explicit]: an explicit
// instantiation declaration does not suppress inline functions; g++ 12 leaves the constructor out of line); its
// cost functions — observation_cost and periodic_cost, defined out of class — and all they reach are not.
//
// A (method, problem, N) a test uses but these lists lack still compiles and links (implicit instantiation in
// that TU); it only costs compile time. Add it to the lists below.
#pragma once

#include <lgi/fit/fit.hpp>
#include <lgi/integrators/gyrostat.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/integrators/splitting.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/gyrostat.hpp>
#include <lgi/problems/heavy_top.hpp>
#include <lgi/problems/torqued_body.hpp>

// One Jet size, N = 8, for every fit of the tests (8 covers Ω0, R0 and two moments in one pass; the gradient
// test's 12 tangent coordinates take two): each (method, problem) is instantiated once, not once per N.
// X(part, method, problem, N): Model and its cost functions; `part` the fit_instances_<part>.cpp that defines it.
#define LGI_FIT_MODELS(X)        \
  X(1, Lgvi, HeavyTop<double>, 8)     \
  X(1, Lgvi, FreeBody<double>, 8)     \
  X(1, Rkmk4, FreeBody<double>, 8)    \
  X(2, Rkmk4, HeavyTop<double>, 8)    \
  X(2, SplitDmv, HeavyTop<double>, 8) \
  X(2, SplitAxes, HeavyTop<double>, 8) \
  X(2, Lgvi, TorquedBody<double>, 8) \
  X(1, GyrostatLgvi, Gyrostat<double>, 8)
// fit_observations (`lgi fit`; test_fit_omega, _observations, _inertia):
#define LGI_FIT_OBSERVATION_FITS(X) \
  X(1, Lgvi, HeavyTop<double>, 8)        \
  X(1, Lgvi, FreeBody<double>, 8)        \
  X(1, Rkmk4, FreeBody<double>, 8)       \
  X(2, Rkmk4, HeavyTop<double>, 8)       \
  X(2, Lgvi, TorquedBody<double>, 8)     \
  X(1, GyrostatLgvi, Gyrostat<double>, 8)
// fit_periodic (`lgi fit`; test_fit_periodic):
#define LGI_FIT_PERIODIC_FITS(X) \
  X(1, Lgvi, HeavyTop<double>, 8)     \
  X(1, Lgvi, FreeBody<double>, 8)     \
  X(1, Rkmk4, FreeBody<double>, 8)    \
  X(2, Rkmk4, HeavyTop<double>, 8)

// `prefix` is `extern template` (declaration, here) or `template` (definition, fit_instances_<part>.cpp).
#define LGI_FIT_MODEL(prefix, Method, P, N) prefix class Model<Method, P, N>;
#define LGI_FIT_OBSERVATION_FIT(prefix, Method, P, N)                                                          \
  prefix FitResult<P> fit_observations<Method, N, P>(const P&, const State<double>&, std::span<const Unknown>, \
                                                     std::span<const Observation>, const FitOptions&);
#define LGI_FIT_PERIODIC_FIT(prefix, Method, P, N)                                                                \
  prefix FitResult<P> fit_periodic<Method, N, P>(const P&, const State<double>&, double, std::span<const Unknown>, \
                                                 const PeriodicOptions&, double);

#define LGI_FIT_EXTERN_MODEL(part, Method, P, N) LGI_FIT_MODEL(extern template, Method, P, N)
#define LGI_FIT_EXTERN_OBSERVATION_FIT(part, Method, P, N) LGI_FIT_OBSERVATION_FIT(extern template, Method, P, N)
#define LGI_FIT_EXTERN_PERIODIC_FIT(part, Method, P, N) LGI_FIT_PERIODIC_FIT(extern template, Method, P, N)

namespace lgi::fit {
LGI_FIT_MODELS(LGI_FIT_EXTERN_MODEL)
LGI_FIT_OBSERVATION_FITS(LGI_FIT_EXTERN_OBSERVATION_FIT)
LGI_FIT_PERIODIC_FITS(LGI_FIT_EXTERN_PERIODIC_FIT)
}  // namespace lgi::fit

// For fit_instances_<this>.cpp: LGI_FIT_IN_PART_<this>_<part>(x) is x when part == this, else nothing.
#define LGI_FIT_IN_PART_1_1(x) x
#define LGI_FIT_IN_PART_1_2(x)
#define LGI_FIT_IN_PART_2_1(x)
#define LGI_FIT_IN_PART_2_2(x) x
