#include "core/plugin_library.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>

#include "core/error.h"

namespace acpca {

namespace {

/// The folder of the executable or shared object this code was linked into.
std::filesystem::path holderFolder() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&pluginCandidates), &info) == 0 || !info.dli_fname) return {};
  std::error_code ec;
  const std::filesystem::path holder = std::filesystem::canonical(info.dli_fname, ec);
  return ec ? std::filesystem::path() : holder.parent_path();
}

}  // namespace

std::vector<std::string> pluginCandidates(const PluginSpec& plugin) {
  if (const char* named = std::getenv(plugin.variable); named && *named) return {named};
  std::vector<std::string> candidates;
  if (const std::filesystem::path folder = holderFolder(); !folder.empty())
    candidates.push_back((folder / plugin.file).string());
  if (plugin.built && *plugin.built && (candidates.empty() || candidates[0] != plugin.built))
    candidates.push_back(plugin.built);
  return candidates;
}

void* loadPluginEntry(const PluginSpec& plugin) {
  std::string reasons;
  for (const std::string& path : pluginCandidates(plugin)) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
      reasons += concat("\n  ", path, ": not there");
      continue;
    }
    void* library = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!library) {
      reasons += concat("\n  ", path, ": ", dlerror());
      continue;
    }
    if (void* entry = dlsym(library, plugin.entry)) return entry;
    reasons += concat("\n  ", path, ": exports no ", plugin.entry, " (another file of that name?)");
  }
  throw UserError(concat("cannot load ", plugin.what, ":", reasons));
}

}  // namespace acpca
