// lgi/apps/registry.hpp — the one place where scene names meet C++ types.
//
// Methods and problems come in families, one header each (methods_<family>.hpp, problems_<family>.hpp,
// the latter with a .cpp holding the scene parsers), concatenated here:
//   adding a method:  its template name in its family's MethodList;
//   adding a problem: its type in its family's ProblemList and one ProblemInfo (name, keys, parser) in
//                     the family's table.
// Name lookup happens once, when a scene is loaded; after that everything is compiled for the concrete
// problem and method. A method applies to a problem when Method<Problem> is a Stepper (a method whose
// template constraints reject a problem is not offered for it).
#pragma once

#include "json_reader.hpp"

#include <lgi/core/integrator.hpp>
#include <lgi/core/state.hpp>

#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace lgi::app {

template <template <class> class... Ms>
struct MethodList {};
template <class... Ps>
struct ProblemList {};

namespace detail {
template <class... Lists>
struct concat;
template <class L>
struct concat<L> {
  using type = L;
};
template <template <class> class... A, template <class> class... B, class... Rest>
struct concat<MethodList<A...>, MethodList<B...>, Rest...> : concat<MethodList<A..., B...>, Rest...> {};
template <class... A, class... B, class... Rest>
struct concat<ProblemList<A...>, ProblemList<B...>, Rest...> : concat<ProblemList<A..., B...>, Rest...> {};
template <class L>
struct variant_of;
template <class... Ps>
struct variant_of<ProblemList<Ps...>> {
  using type = std::variant<Ps...>;
};
}  // namespace detail

// Method<P> exists (its constraints accept P) and is a Stepper.
template <template <class> class Method, class P>
inline constexpr bool method_applies_v = requires { typename Method<P>; } && Stepper<Method<P>>;

// f.template operator()<M>() for every method M of the list that applies to P, in the list's order.
template <class P, template <class> class... Ms, class F>
void for_each_method(MethodList<Ms...>, F&& f) {
  const auto one = [&]<template <class> class M>() {
    if constexpr (method_applies_v<M, P>) f.template operator()<M>();
  };
  (one.template operator()<Ms>(), ...);
}

}  // namespace lgi::app

#include "methods_composition.hpp"
#include "methods_foundation.hpp"
#include "methods_library.hpp"
#include "methods_rkmk.hpp"
#include "methods_splitting.hpp"
#include "problems_foundation.hpp"
#include "problems_library.hpp"
#include "problems_paper.hpp"

namespace lgi::app {

using Methods =
    typename detail::concat<FoundationMethods, RkmkFamilyMethods, SplittingMethods, CompositionMethods, LibraryMethods>::type;
using Problems = typename detail::concat<FoundationProblems, LibraryProblems, PaperProblems>::type;
using AnyProblem = typename detail::variant_of<Problems>::type;

struct ProblemInfo {
  std::string_view name;
  std::string_view summary;
  std::vector<std::string_view> keys;  // the keys its "problem" object takes
  AnyProblem (*parse)(const Node& problem);
};

struct MethodInfo {
  MethodTraits traits;
};

// Each problem family's table (problems_<family>.cpp).
std::vector<ProblemInfo> foundation_problem_infos();
std::vector<ProblemInfo> library_problem_infos();
std::vector<ProblemInfo> paper_problem_infos();

std::span<const ProblemInfo> problem_registry();
std::span<const MethodInfo> method_registry();
const ProblemInfo* find_problem(std::string_view name);
const MethodInfo* find_method(std::string_view name);
bool method_applies(std::string_view method, std::string_view problem);
// "lgvi, rkmk4, lie_euler" (all methods, or those that apply to `problem`)
std::string known_methods(std::string_view problem = {});
std::string known_problems();

// Readers shared by the problem parsers.
// "inertia": a symmetric 3×3 array, or [I1, I2, I3] for a diagonal tensor; checked to be physical
// (core/inertia.hpp, inertia_defect) and returned symmetrised exactly.
Mat3<double> read_inertia(const Node& node);
// A unit vector, accepted within 1e-9 and returned normalised exactly.
Vec3<double> read_unit_vector(const Node& node);
// A rotation matrix, accepted within 1e-9 (‖RᵀR − I‖_F, det > 0) and returned as the nearest rotation.
Mat3<double> read_rotation(const Node& node);

}  // namespace lgi::app
