// lgi/apps/plugin.hpp — problem types from shared libraries: a user's problem, compiled in their own project against
// the installed package, run by `lgi run`, `lgi sweep`, `lgi list` without forking lgi.
//
// A plugin is a shared library (lgi_add_plugin in lgiConfig.cmake builds one) that exports
//     extern "C" const lgi::app::PluginInfo* lgi_plugin_v1();
// which LGI_PLUGIN below defines from the problem types its file defines with LGI_PLUGIN_PROBLEM (the same form as a
// built-in problem's LGI_DEFINE_PROBLEM, problem_model.hpp). `lgi run|sweep|fit|list --plugin FILE` loads it
// (plugin_loader.hpp): before any of its C++ objects is touched, load_plugin checks
// that it is an lgi plugin (the symbol, a magic number) and that it was built for this lgi — the same version,
// compiler and C++ ABI (plugin_build_id) — and refuses it otherwise with one line naming the file and the reason.
// Its problem types then join the registry: scenes name them, `lgi list` lists them, and every method the plugin was
// built with (all, or lgi_add_plugin's METHODS) applies as to a built-in problem, with checkpoints and sweeps
// (`lgi fit` fits the built-in types only: it needs the problem for its Jet scalar). The plugin's code resolves lgi's
// own functions (the JSON readers, read_inertia, …) from the `lgi` executable, which exports them.
#pragma once

#include "plugin_loader.hpp"
#include "problem_model.hpp"

// In a plugin's source: one problem type, as LGI_DEFINE_PROBLEM (problem_model.hpp).
#define LGI_PLUGIN_PROBLEM(id, P, summary, keys, parse) LGI_DEFINE_PROBLEM(id, P, summary, keys, parse)

// Once in a plugin: the exported entry listing its problem types (their ids, as given to LGI_PLUGIN_PROBLEM).
#define LGI_PLUGIN_ENTRY_ONE(id) &::lgi::app::problem_info_##id(),
#define LGI_PLUGIN(...)                                                                                        \
  extern "C" __attribute__((visibility("default"))) const ::lgi::app::PluginInfo* lgi_plugin_v1() {           \
    static const ::lgi::app::ProblemInfo* const problems[] = {LGI_PLUGIN_FOR_EACH(LGI_PLUGIN_ENTRY_ONE, __VA_ARGS__)}; \
    static const ::lgi::app::PluginInfo info{::lgi::app::plugin_magic, LGI_PLUGIN_BUILD_ID,                   \
                                            sizeof problems / sizeof problems[0], problems};                  \
    return &info;                                                                                              \
  }
// (up to eight problem types a plugin)
#define LGI_PLUGIN_FE_1(m, a) m(a)
#define LGI_PLUGIN_FE_2(m, a, ...) m(a) LGI_PLUGIN_FE_1(m, __VA_ARGS__)
#define LGI_PLUGIN_FE_3(m, a, ...) m(a) LGI_PLUGIN_FE_2(m, __VA_ARGS__)
#define LGI_PLUGIN_FE_4(m, a, ...) m(a) LGI_PLUGIN_FE_3(m, __VA_ARGS__)
#define LGI_PLUGIN_FE_5(m, a, ...) m(a) LGI_PLUGIN_FE_4(m, __VA_ARGS__)
#define LGI_PLUGIN_FE_6(m, a, ...) m(a) LGI_PLUGIN_FE_5(m, __VA_ARGS__)
#define LGI_PLUGIN_FE_7(m, a, ...) m(a) LGI_PLUGIN_FE_6(m, __VA_ARGS__)
#define LGI_PLUGIN_FE_8(m, a, ...) m(a) LGI_PLUGIN_FE_7(m, __VA_ARGS__)
#define LGI_PLUGIN_FE_N(_1, _2, _3, _4, _5, _6, _7, _8, N, ...) LGI_PLUGIN_FE_##N
#define LGI_PLUGIN_FOR_EACH(m, ...) LGI_PLUGIN_FE_N(__VA_ARGS__, 8, 7, 6, 5, 4, 3, 2, 1, 0)(m, __VA_ARGS__)
