// Problems: the problem library: Lagrange, Kovalevskaya, satellite, potential-defined (see registry.hpp).
#pragma once

#include <lgi/problems/kovalevskaya_top.hpp>
#include <lgi/problems/lagrange_top.hpp>
#include <lgi/problems/potential_problem.hpp>
#include <lgi/problems/satellite.hpp>

namespace lgi::app {
using LibraryProblems =
    ProblemList<LagrangeTop<double>, KovalevskayaTop<double>, Satellite<double>, FieldPotentialBody<double>>;
}  // namespace lgi::app
