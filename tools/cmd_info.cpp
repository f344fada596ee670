// `adaptive-cpca info`: what a transport (or model) file holds.
#include <iostream>

#include "dataset/file_info.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct InfoArgs {
  std::string file, jsonPath;
};

void run(const InfoArgs& a) {
  refuseOutputsOverInputs({a.file}, {a.jsonPath});
  // The JSON where --json says; the words on stdout unless the JSON went there.
  const FileDescription description = describeFile(a.file);
  writeJson(a.jsonPath, description.json);
  if (a.jsonPath != "-") std::cout << description.words;
}

}  // namespace

void registerInfo(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  auto* sub = app.add_subcommand(
      "info",
      "Describe a transport or model file, or a frame (its lighting, camera, colour space)");
  sub->add_option("file", args->file, "Transport or model file, or a frame (.exr, .png)")
      ->required();
  sub->add_option("--json", args->jsonPath, "Write the description as JSON to FILE (- for stdout)");
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
