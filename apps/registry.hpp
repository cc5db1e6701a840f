// lgi/apps/registry.hpp — the one place where scene names meet C++ types.
//
// Adding a problem: a header in problems/, one alternative in AnyProblem, one entry (name, keys, parse)
// in registry.cpp. Adding a method: one template name in Methods. Name lookup happens once, when a
// scene is loaded; after that everything is compiled for the concrete problem and method.
#pragma once

#include "json_reader.hpp"

#include <lgi/core/integrator.hpp>
#include <lgi/integrators/lgvi.hpp>
#include <lgi/integrators/rkmk.hpp>
#include <lgi/problems/free_body.hpp>
#include <lgi/problems/heavy_top.hpp>

#include <span>
#include <string_view>
#include <variant>
#include <vector>

namespace lgi::app {

using AnyProblem = std::variant<FreeBody<double>, HeavyTop<double>>;

template <template <class> class... Ms>
struct MethodList {};
using Methods = MethodList<Lgvi, Rkmk4, LieEuler>;

struct ProblemInfo {
  std::string_view name;
  std::string_view summary;
  std::vector<std::string_view> keys;  // the keys its "problem" object takes
  AnyProblem (*parse)(const Node& problem);
};

struct MethodInfo {
  MethodTraits traits;
};

std::span<const ProblemInfo> problem_registry();
std::span<const MethodInfo> method_registry();
const ProblemInfo* find_problem(std::string_view name);
const MethodInfo* find_method(std::string_view name);
// "lgvi, rkmk4, lie_euler"
std::string known_methods();
std::string known_problems();

}  // namespace lgi::app
