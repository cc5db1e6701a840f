// lgi/apps/registry.hpp — the one place where scene names meet C++ types.
//
// Methods come in families, one header each (methods_<family>.hpp), concatenated here; adding a method is its
// template name in its family's MethodList. A method applies to a problem when Method<Problem> is a Stepper (a
// method whose template constraints reject a problem is not offered for it).
// Problems: one file each in apps/problems/ (its parser and LGI_DEFINE_PROBLEM, problem_model.hpp) and one line in
// apps/problems/list.def, whose order is `lgi list`'s; plugins add theirs at run time (plugin.hpp). Name lookup
// happens once, when a scene is loaded; the scene then holds its problem as a ProblemModel.
#pragma once

#include "json_reader.hpp"

#ifdef LGI_ENABLED_METHODS_HEADER
#include LGI_ENABLED_METHODS_HEADER
#endif

#include <lgi/core/integrator.hpp>
#include <lgi/core/state.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace lgi::app {

template <template <class> class... Ms>
struct MethodList {};

namespace detail {
template <class... Lists>
struct concat;
template <class L>
struct concat<L> {
  using type = L;
};
template <template <class> class... A, template <class> class... B, class... Rest>
struct concat<MethodList<A...>, MethodList<B...>, Rest...> : concat<MethodList<A..., B...>, Rest...> {};
}  // namespace detail

// A build may offer a subset of the methods: LGI_METHODS in lgi's CMake, METHODS of lgi_add_plugin (a generated
// header defining LGI_ENABLED_METHODS as a list of names). True for every method otherwise.
constexpr bool method_enabled(std::string_view name) {
#ifdef LGI_ENABLED_METHODS
  for (const std::string_view m : {LGI_ENABLED_METHODS})
    if (m == name) return true;
  return false;
#else
  (void)name;
  return true;
#endif
}

// Method<P> exists (its constraints accept P), is a Stepper, and this build offers it.
template <template <class> class Method, class P>
inline constexpr bool method_applies_v = [] {
  if constexpr (requires { typename Method<P>; }) {
    if constexpr (Stepper<Method<P>>) return method_enabled(Method<P>::traits.name);
  }
  return false;
}();

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
#include "problems/euler_angle_methods.hpp"

#include <memory>
#include <typeinfo>

namespace lgi::app {

using Methods =
    typename detail::concat<FoundationMethods, RkmkFamilyMethods, SplittingMethods, CompositionMethods, LibraryMethods>::type;

namespace runner_detail {
class ProblemRunner;
}

// What a problem says of its body (the sweeps' state functions, auto's frequency scale, lgi view's drawing): J; for
// a problem with uniform gravity (has_gravity) k, z0 and its strength b — the problem's member b, NaN where the type
// names none (a plugin's), 0 without gravity; a gyrostat's rotor axes.
struct BodyData {
  Mat3<double> J = Mat3<double>::Identity();
  bool has_gravity = false;
  Vec3<double> k = Vec3<double>::UnitZ(), z0 = Vec3<double>::UnitZ();
  double b = 0;
  std::vector<Vec3<double>> rotor_axes;  // unit, body frame
};

// A scene's problem with its parameters, behind an interface (problem_model.hpp implements it for any problem type).
class ProblemModel {
 public:
  virtual ~ProblemModel() = default;
  virtual std::string_view type_name() const = 0;
  // The problem's own CSV columns after orthogonality_error; the first integral_count() of them are integrals of
  // the motion (the Euler-angle top's last ones are coordinates).
  virtual std::vector<std::string_view> invariant_names() const = 0;
  virtual std::size_t integral_count() const = 0;
  virtual bool on_group() const = 0;     // its state is on SO(3) × R³ (integrator options apply)
  // What the summary says of the coordinates a problem not on SO(3) × R³ is stepped in (", Runge-Kutta on the Euler
  // angles"); empty for one on SO(3) × R³.
  virtual std::string coordinates() const { return {}; }
  // Why a method of the registry does not apply, where the problem says more than its torque's kind (" (...)"; empty:
  // the scene loader's reason).
  virtual std::string methods_note() const { return {}; }
  virtual bool torque_free() const = 0;  // no torque: methods of higher order on free bodies show that order
  virtual bool reads_omega() const = 0;  // its torque reads Ω (damping, control): the energy changes by their work
  virtual bool projectable() const = 0;  // "projection": true is accepted (integrators/projection.hpp)
  virtual BodyData body() const = 0;
  // The last time the problem's data define its torque at (a torque table's last row; +inf: no limit; the scene
  // refuses a t_end beyond it).
  virtual double time_limit() const = 0;
  // The files the problem's data were read from, with the FNV-1a 64 hash of their bytes (checkpoints record them).
  virtual std::vector<std::pair<std::string, std::uint64_t>> input_files() const = 0;
  // The scene's method on this problem and its rows (runner_detail.hpp).
  virtual std::unique_ptr<runner_detail::ProblemRunner> runner() const = 0;
  // The columns of a row (csv_header) for a state on SO(3) (std::logic_error for a problem not on SO(3)).
  virtual void state_columns(double t, const State<double>& x, std::vector<double>& out) const = 0;
  // The problem object when it is of that type, else nullptr (problem_as below).
  virtual const void* get(const std::type_info& type) const = 0;
};

// The problem of type P a model holds, or nullptr (the batched sweep and lgi fit take some types).
template <class P>
const P* problem_as(const ProblemModel& model) {
  return static_cast<const P*>(model.get(typeid(P)));
}

// A problem type the command knows (problem_model.hpp, problem_info).
struct ProblemInfo {
  std::string_view name;
  std::string_view summary;
  std::vector<std::string_view> keys;  // the keys its "problem" object takes
  std::shared_ptr<const ProblemModel> (*parse)(const Node& problem);
  std::vector<std::string_view> methods;  // the methods that apply to it, in the method table's order
  bool on_group = true;                   // its state is on SO(3) × R³
};

struct MethodInfo {
  MethodTraits traits;
};

// The problem types: those of apps/problems/list.def, in its order, then those plugins added.
std::span<const ProblemInfo> problem_registry();
// Adds a problem type (a plugin's); false when its name is taken.
bool add_problem(const ProblemInfo& info);
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
//
// Rotations, unit vectors and quaternions as people have them — typed to 3 or 4 decimals, stored in float32 —
// are accepted when their defect (‖RᵀR − I‖_F, ||v| − 1|, ||q| − 1|) is at most input_defect_bound, and made
// exact: the nearest rotation (the polar factor), the vector or quaternion over its length. Rounding every entry
// of a rotation to d decimals leaves a defect of about 2·10^-d, so 3 decimals pass; a wrong entry (a sign, a
// swapped digit of the first two decimals) leaves 1e-2 or more and is refused with the value. A defect above
// input_note_defect is recorded (Node::adjusted: the run's summary lists it), above input_warn_defect it is
// also a warning (lgi run prints it): more than the rounding of single precision.
inline constexpr double input_defect_bound = 1e-2;
inline constexpr double input_note_defect = 1e-12;
inline constexpr double input_warn_defect = 1e-6;
// The rotation nearest to M in the Frobenius norm: U Vᵀ of M's SVD (the polar factor; det M > 0).
Mat3<double> nearest_rotation(const Mat3<double>& M);
// A defect for a message: two significant digits ("6.2e-05").
std::string format_defect(double x);
// A unit vector (see above), returned normalised.
Vec3<double> read_unit_vector(const Node& node);
// A rotation matrix (see above; det > 0), returned as the nearest rotation.
Mat3<double> read_rotation(const Node& node);
// A quaternion [w, x, y, z] (see above), returned as its rotation (core/attitude.hpp).
Mat3<double> read_quaternion(const Node& node);
// "unit" of an angle: "rad" (the default) or "deg"; returns the factor to radians.
double read_angle_unit(const std::optional<Node>& unit);
// {"axis": [x, y, z] (any length but 0), "angle": θ, "unit": "rad" | "deg"}, returned as its rotation.
Mat3<double> read_axis_angle(const Node& node);
// A body-frame inertia tensor that must be diagonal (principal axes: the library's tops are written in them);
// `why` is said when it is not. Returns the principal moments.
Vec3<double> read_principal_inertia(const Node& node, std::string_view why);
// a = b to a relative 1e-12.
bool nearly_equal(double a, double b);

}  // namespace lgi::app
