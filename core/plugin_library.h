#pragma once
// Plugins: shared objects of ours that link a heavy library (OpenImageIO,
// OpenCV's windows) and are loaded with dlopen on first use, so a command
// that needs none of it starts without loading it (docs/architecture.md,
// "Plugins"). Each exports one C function returning its interface.
#include <string>
#include <vector>

namespace acpca {

/// Where a plugin is found and what it exports.
struct PluginSpec {
  const char* file;      ///< its file name: "libacpca_image_codecs.so"
  const char* variable;  ///< the environment variable that names its file instead
  const char* built;     ///< where the build put it; null for nowhere
  const char* entry;     ///< the C function it exports
  const char* what;      ///< in words, for errors: "the image codecs (OpenImageIO)"
};

/// Where the plugin is looked for, in order: the file its variable names
/// (alone, when set); beside the executable or Python module holding this
/// code (an installed copy); where the build put it.
std::vector<std::string> pluginCandidates(const PluginSpec& plugin);

/// Loads the plugin and returns its entry function. Throws UserError naming
/// each place tried and why it failed (not there, the loader's message, no
/// entry). Never unloaded: its objects live as long as the process.
void* loadPluginEntry(const PluginSpec& plugin);

}  // namespace acpca
