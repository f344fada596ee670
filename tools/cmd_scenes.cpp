#include <iomanip>
#include <iostream>

#include "precompute/scene.h"
#include "tools/commands.h"

namespace acpca::cli {

void registerScenes(CLI::App& app) {
  auto* sub = app.add_subcommand("scenes", "List the built-in scenes: name, then a description");
  sub->callback([] {
    for (const auto& s : builtinScenes())
      std::cout << std::left << std::setw(14) << s.name << s.description << "\n";
  });
}

}  // namespace acpca::cli
