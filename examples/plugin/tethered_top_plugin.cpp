// A plugin (docs/new_problem.md): the tethered top of examples/new_problem/tethered_top.hpp as a problem type of
// scenes, with its parameters read from the scene's "problem" object, and — for the tests — a copy of the heavy top
// under another name.
#include "../new_problem/tethered_top.hpp"

#include <lgi/app/plugin.hpp>
#include <lgi/problems/heavy_top.hpp>

namespace {

using lgi::app::Node;

// {"type": "tethered_top", "inertia": [...], "kappa": 20, "L0": 0.5, "b": 1, "p": [...], "anchor": [...], "k": [...],
//  "z0": [...]}: the scene's problem object; every key but type and inertia optional (TetherPotential's defaults).
tutorial::TetheredTop parse_tethered_top(const Node& p) {
  tutorial::TetheredTop top{lgi::app::read_inertia(p.at("inertia")), tutorial::TetherPotential{}};
  tutorial::TetherPotential& V = top.V;
  if (const auto n = p.find("kappa")) V.kappa = n->non_negative();
  if (const auto n = p.find("L0")) V.L0 = n->non_negative();
  if (const auto n = p.find("b")) V.b = n->non_negative();
  if (const auto n = p.find("p")) V.p = n->vec3();
  if (const auto n = p.find("anchor")) V.anchor = n->vec3();
  if (const auto n = p.find("k")) V.k = lgi::app::read_unit_vector(*n);
  if (const auto n = p.find("z0")) V.z0 = lgi::app::read_unit_vector(*n);
  return top;
}

// The built-in heavy_top's parser, for a problem type that must run exactly as heavy_top does.
struct PluginHeavyTop : lgi::HeavyTop<double> {
  static constexpr std::string_view name = "plugin_heavy_top";
};
PluginHeavyTop parse_plugin_heavy_top(const Node& p) {
  PluginHeavyTop top;
  top.inertia = lgi::app::read_inertia(p.at("inertia"));
  top.b = p.at("b").non_negative();
  if (const auto k = p.find("k")) top.k = lgi::app::read_unit_vector(*k);
  if (const auto z0 = p.find("z0")) top.z0 = lgi::app::read_unit_vector(*z0);
  return top;
}

}  // namespace

namespace lgi::app {
LGI_PLUGIN_PROBLEM(tethered_top, tutorial::TetheredTop,
                   "heavy top whose body point p is tied by a spring (kappa, L0) to a laboratory anchor",
                   ({"type", "inertia", "kappa", "L0", "b", "p", "anchor", "k", "z0"}), parse_tethered_top)
LGI_PLUGIN_PROBLEM(plugin_heavy_top, PluginHeavyTop, "the heavy top, from a plugin",
                   ({"type", "inertia", "b", "k", "z0"}), parse_plugin_heavy_top)
}  // namespace lgi::app

LGI_PLUGIN(tethered_top, plugin_heavy_top)
