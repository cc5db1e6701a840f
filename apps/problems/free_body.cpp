// lgi/apps/problems/free_body.cpp — the `free_body` problem type of scenes: its parser and its registration (every method
// that applies to it is compiled here, problem_model.hpp).
#include "../problem_model.hpp"

#include <lgi/problems/free_body.hpp>

namespace lgi::app {
namespace {

FreeBody<double> parse(const Node& p) { return FreeBody<double>{read_inertia(p.at("inertia"))}; }

}  // namespace

LGI_DEFINE_PROBLEM(free_body, FreeBody<double>, "free rigid body (Euler-Poinsot), J Omega' = (J Omega) x Omega", ({"type", "inertia"}), parse)

}  // namespace lgi::app
