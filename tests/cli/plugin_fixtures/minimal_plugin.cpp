// The smallest plugin: the free body under another name, with one method. Built against another version's headers,
// `lgi --plugin` must refuse it before using anything of it.
#include <lgi/app/plugin.hpp>
#include <lgi/problems/free_body.hpp>

namespace {
struct OtherFreeBody : lgi::FreeBody<double> {
  static constexpr std::string_view name = "other_free_body";
};
OtherFreeBody parse(const lgi::app::Node& p) {
  OtherFreeBody body;
  body.inertia = lgi::app::read_inertia(p.at("inertia"));
  return body;
}
}  // namespace

namespace lgi::app {
LGI_PLUGIN_PROBLEM(other_free_body, OtherFreeBody, "the free body, from a plugin", ({"type", "inertia"}), parse)
}  // namespace lgi::app

LGI_PLUGIN(other_free_body)
