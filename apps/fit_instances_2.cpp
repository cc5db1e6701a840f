// apps/fit_instances_2.cpp — explicit instantiations of the fit templates `lgi fit` and the tests use, part 2
// (RKMK4 on the heavy top, the two splittings; see fit_instances.hpp). Two parts: two TUs of similar cost,
// built in parallel.
#include "fit_instances.hpp"

#define LGI_FIT_DEF_MODEL(part, Method, P, N) LGI_FIT_IN_PART_2_##part(LGI_FIT_MODEL(template, Method, P, N))
#define LGI_FIT_DEF_OBSERVATION_FIT(part, Method, P, N) \
  LGI_FIT_IN_PART_2_##part(LGI_FIT_OBSERVATION_FIT(template, Method, P, N))
#define LGI_FIT_DEF_PERIODIC_FIT(part, Method, P, N) \
  LGI_FIT_IN_PART_2_##part(LGI_FIT_PERIODIC_FIT(template, Method, P, N))

namespace lgi::fit {
LGI_FIT_MODELS(LGI_FIT_DEF_MODEL)
LGI_FIT_OBSERVATION_FITS(LGI_FIT_DEF_OBSERVATION_FIT)
LGI_FIT_PERIODIC_FITS(LGI_FIT_DEF_PERIODIC_FIT)
}  // namespace lgi::fit
