// lgi/apps/plugin_loader.hpp — what a plugin is to the `lgi` command, and loading one (plugin.hpp: writing one).
#pragma once

#include "registry.hpp"
#include "version.hpp"

#include <cstddef>
#include <cstdint>
#include <string>

// The build this code is compiled for: lgi's version, the revision of the plugin interface (ProblemInfo and
// ProblemModel in registry.hpp: raise LGI_PLUGIN_INTERFACE whenever either changes, so that a plugin built before
// is refused instead of called through another layout), the compiler, the C++ library's ABI, and FMA contraction (a
// plugin compiled with -march=native would contract a·b + c and change the last bits).
#define LGI_STRINGIZE2(x) #x
#define LGI_STRINGIZE(x) LGI_STRINGIZE2(x)
#ifdef __FMA__
#define LGI_BUILD_FMA "fma"
#else
#define LGI_BUILD_FMA "no-fma"
#endif
#define LGI_PLUGIN_INTERFACE 4
#ifndef LGI_PLUGIN_BUILD_ID
#define LGI_PLUGIN_BUILD_ID                                                                                      \
  "lgi " LGI_VERSION_STRING "; plugin interface " LGI_STRINGIZE(LGI_PLUGIN_INTERFACE) "; " __VERSION__          \
  "; cxx11-abi " LGI_STRINGIZE(_GLIBCXX_USE_CXX11_ABI) "; " LGI_BUILD_FMA
#endif

namespace lgi::app {

inline constexpr std::uint32_t plugin_magic = 0x6c676950;  // "Pigl"

struct PluginInfo {
  std::uint32_t magic;     // plugin_magic
  const char* build_id;    // LGI_PLUGIN_BUILD_ID of the plugin's build
  std::size_t count;       // its problem types
  const ProblemInfo* const* problems;
};

// This build's id (what a plugin's must equal).
inline const char* plugin_build_id() { return LGI_PLUGIN_BUILD_ID; }

// Loads the plugin at `path` (once per path in a process) and adds its problem types; throws InputError naming the
// file and the reason: it cannot be loaded (the system's message), it is not an lgi plugin, it was built for another
// lgi, or a problem type of its is defined already. `where` prefixes the message (a scene file and JSON path, or "").
void load_plugin(const std::string& path, const std::string& where = {});

}  // namespace lgi::app

