// lgi/apps/plugin.cpp — loading plugins (plugin_loader.hpp).
#include "plugin_loader.hpp"

#include <dlfcn.h>
#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <set>
#include <string>

namespace lgi::app {

void load_plugin(const std::string& path, const std::string& where) {
  static std::mutex mutex;
  static std::set<std::string> loaded;  // canonical paths
  const std::lock_guard lock(mutex);
  const std::string prefix = (where.empty() ? std::string() : where + ": ") + path + ": ";
  struct stat st {};
  if (stat(path.c_str(), &st) != 0) throw InputError(prefix + "cannot load the plugin: " + std::strerror(errno));
  std::error_code ec;
  const std::string key = std::filesystem::canonical(path, ec).string();
  if (!ec && loaded.count(key)) return;
  // dlopen searches the library path for a name without a '/': a plugin is always a file.
  const std::string file = path.find('/') == std::string::npos ? "./" + path : path;
  void* handle = dlopen(file.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = dlerror();
    throw InputError(prefix + "cannot load the plugin: " + (why ? why : "unknown error"));
  }
  using Entry = const PluginInfo* (*)();
  const auto entry = reinterpret_cast<Entry>(dlsym(handle, "lgi_plugin_v1"));
  if (!entry) {
    dlclose(handle);
    throw InputError(prefix + "not an lgi plugin (it does not export lgi_plugin_v1; build it with lgi_add_plugin)");
  }
  const PluginInfo* info = entry();
  if (!info || info->magic != plugin_magic) {
    dlclose(handle);
    throw InputError(prefix + "not an lgi plugin (its lgi_plugin_v1 does not describe one)");
  }
  if (!info->build_id || std::strcmp(info->build_id, plugin_build_id()) != 0) {
    const std::string theirs = info->build_id ? info->build_id : "?";
    dlclose(handle);
    throw InputError(prefix + "built for another lgi (" + theirs + "; this is " + plugin_build_id() +
                     "): rebuild it against this lgi");
  }
  for (std::size_t i = 0; i < info->count; ++i)
    if (find_problem(info->problems[i]->name)) {
      const std::string name(info->problems[i]->name);
      dlclose(handle);
      throw InputError(prefix + "its problem type \"" + name +
                       "\" is defined already (built in, or by another plugin)");
    }
  for (std::size_t i = 0; i < info->count; ++i) add_problem(*info->problems[i]);
  loaded.insert(ec ? path : key);  // the library stays loaded for the life of the process
}

}  // namespace lgi::app
