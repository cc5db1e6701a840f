// lgi/apps/problem_model.hpp — a scene's problem behind an interface, and how a problem type joins the command.
//
// A problem type (a RigidBodyProblem of problems/, or one of a user's, compiled into a plugin) joins `lgi` as a
// ProblemInfo: its scene name, summary and keys, the methods that apply to it, and a parser that turns a scene's
// "problem" object into a ProblemModel — the problem with its parameters, whose runner (runner_detail.hpp) makes
// the scene's method into an lgi::Integrator. ProblemModelOf<P> implements the interface for any P; making a
// ProblemInfo for P (problem_info<P, parse>) compiles every method that applies to P, once, in the translation unit
// that does it. Built-in problems: one file each in apps/problems/ and one line in apps/problems/list.def;
// plugins: apps/plugin.hpp.
#pragma once

#include "json_reader.hpp"
#include "registry.hpp"
#include "runner_impl.hpp"

#include <lgi/core/problem.hpp>
#include <lgi/integrators/projection.hpp>

#include <cstdint>
#include <limits>
#include <memory>
#include <string>
#include <string_view>
#include <typeinfo>
#include <utility>
#include <vector>

namespace lgi::app {

template <class P>
class ProblemModelOf final : public ProblemModel {
 public:
  explicit ProblemModelOf(P problem) : problem_(std::move(problem)) {}
  const P& problem() const { return problem_; }

  std::string_view type_name() const override { return P::name; }
  std::vector<std::string_view> invariant_names() const override {
    return {P::invariant_names.begin(), P::invariant_names.end()};
  }
  std::size_t integral_count() const override { return runner_detail::integral_count<P>(); }
  bool on_group() const override { return RigidBodyProblem<P>; }
  std::string coordinates() const override {
    return RigidBodyProblem<P> ? std::string() : std::string(", Runge-Kutta on the Euler angles");
  }
  bool torque_free() const override {
    if constexpr (RigidBodyProblem<P>) return !P::has_torque;
    else return false;
  }
  bool reads_omega() const override { return StateTorqueProblem<P>; }
  bool projectable() const override { return ProjectableProblem<P>; }
  BodyData body() const override {
    if constexpr (CoordinateProblem<P>) return body_of(problem_.heavy_top());  // the same top on SO(3)
    else return body_of(problem_);
  }
  double time_limit() const override {
    if constexpr (requires { problem_.time_limit(); }) return problem_.time_limit();
    else return std::numeric_limits<double>::infinity();
  }
  std::vector<std::pair<std::string, std::uint64_t>> input_files() const override {
    if constexpr (requires { problem_.input_files(); }) return problem_.input_files();
    else return {};
  }
  std::unique_ptr<runner_detail::ProblemRunner> runner() const override {
    return runner_detail::make_problem_runner(problem_);
  }
  void state_columns(double t, const State<double>& x, std::vector<double>& out) const override {
    if constexpr (RigidBodyProblem<P>) {
      runner_detail::append_state_columns(problem_, t, x, out);
    } else {
      throw std::logic_error("lgi: state_columns of a problem not on SO(3)");
    }
  }
  const void* get(const std::type_info& type) const override { return type == typeid(P) ? &problem_ : nullptr; }

 private:
  template <class Q>
  static BodyData body_of(const Q& q) {
    BodyData d;
    d.J = q.inertia;
    if constexpr (UniformGravityProblem<Q>) {
      d.has_gravity = true;
      d.k = q.gravity_axis();
      d.z0 = q.mass_axis();
      if constexpr (requires { q.b; }) d.b = static_cast<double>(q.b);
      else d.b = std::numeric_limits<double>::quiet_NaN();
    }
    return d;
  }
  P problem_;
};

// The names of the methods that apply to P, in the method table's order.
template <class P>
std::vector<std::string_view> applicable_methods() {
  std::vector<std::string_view> names;
  const auto add = [&]<template <class> class M>() {
    if constexpr (method_applies_v<M, P>) names.push_back(M<FreeBody<double>>::traits.name);
  };
  [&]<template <class> class... Ms>(MethodList<Ms...>) { (add.template operator()<Ms>(), ...); }(Methods{});
  return names;
}

// P's entry in the registry: `parse` reads P from a scene's "problem" object (its errors name the JSON path through
// Node::fail); keys are the keys that object takes ("type" included).
template <class P, P (*Parse)(const Node&)>
ProblemInfo problem_info(std::string_view summary, std::vector<std::string_view> keys) {
  return ProblemInfo{P::name,
                     summary,
                     std::move(keys),
                     [](const Node& node) -> std::shared_ptr<const ProblemModel> {
                       return std::make_shared<ProblemModelOf<P>>(Parse(node));
                     },
                     applicable_methods<P>(),
                     RigidBodyProblem<P>};
}

}  // namespace lgi::app

// In a built-in problem's file (apps/problems/ID.cpp): defines the ProblemInfo that apps/problems/list.def names.
#define LGI_DEFINE_PROBLEM(id, P, summary, keys, parse)                       \
  const ::lgi::app::ProblemInfo& problem_info_##id() {                       \
    static const ::lgi::app::ProblemInfo info =                              \
        ::lgi::app::problem_info<P, parse>(summary, std::vector<std::string_view> keys); \
    return info;                                                             \
  }
