#include "tools/cli_common.h"

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/input_guard.h"
#include "core/ranks.h"
#include "core/warning.h"
#include "transport/image_header.h"

namespace acpca::cli {

void CommonOptions::add(CLI::App& app, bool withThreads) {
  // Quiet: errors alone on stderr, so warnings go too.
  app.add_flag("-q,--quiet", quiet, "Nothing on stderr but errors")->each([](const std::string&) {
    setWarningHandler({});
  });
  app.add_option("--json", jsonPath, "Write machine-readable results to FILE (- for stdout)");
  if (withThreads)
    app.add_option("--threads", threads, "Worker threads (0: all cores)")
        ->check(CLI::NonNegativeNumber);
}

void writeJson(const std::string& path, const nlohmann::json& value) {
  if (path.empty()) return;
  if (path == "-") {
    std::cout << value.dump(2) << std::endl;
    return;
  }
  writeTextFile(path, value.dump(2) + "\n");
}

std::vector<std::string> joined(std::vector<std::string> first,
                                const std::vector<std::string>& more) {
  first.insert(first.end(), more.begin(), more.end());
  return first;
}

nlohmann::json sceneReport(const std::string& out, const Scene& scene) {
  return {{"out", out},
          {"scene", scene.name},
          {"width", scene.camera.size.width},
          {"height", scene.camera.size.height},
          {"ranks", ranks::count()},
          {"peak_memory_bytes", peakMemoryBytes()}};
}

void refuseOutputsOverInputs(const std::vector<std::string>& inputs,
                             const std::vector<std::string>& outFiles,
                             const std::vector<std::string>& outDirs) {
  for (const auto& file : outFiles)
    if (file != "-") refuseOutputOverInputs(file, inputs);
  for (const auto& dir : outDirs) refuseDirectoryOverInputs(dir, inputs);
}

Background backgroundFor(const std::string& given, const std::string& input) {
  return parseBackground(!given.empty() ? given : fileHoldsLightSet(input) ? "black" : "env");
}

void addFastRotationFlag(CLI::App& command, RotationMode& mode) {
  command.add_flag_callback(
      "--fast-rotation", [&mode] { mode = RotationMode::FastLattice; },
      "Rotate by bilinear lookup on the lattice (fast, not energy-preserving)");
}

namespace {
/// The parameters of options whose flag is not named after them.
std::map<const CLI::Option*, std::vector<std::string>>& taggedParameters() {
  static std::map<const CLI::Option*, std::vector<std::string>> tags;
  return tags;
}

bool sameWords(std::string flag, const std::string& parameter) {
  std::replace(flag.begin(), flag.end(), '-', ' ');
  return flag.size() == parameter.size() &&
         std::equal(flag.begin(), flag.end(), parameter.begin(),
                    [](char a, char b) { return ::tolower(a) == ::tolower(b); });
}
}  // namespace

void nameParameters(CLI::App& command,
                    const std::map<std::string, std::vector<std::string>>& flagParameters) {
  for (const auto& [flag, parameters] : flagParameters)
    taggedParameters()[command.get_option(flag)] = parameters;
}

std::string messageWithFlag(const ParameterError& error, const CLI::App& app) {
  const CLI::App* command = &app;
  while (!command->get_subcommands().empty()) command = command->get_subcommands().front();
  for (const CLI::Option* option : command->get_options()) {
    const auto tag = taggedParameters().find(option);
    const bool sets = tag != taggedParameters().end()
                          ? std::count(tag->second.begin(), tag->second.end(), error.parameter())
                          : !option->get_lnames().empty() &&
                                sameWords(option->get_lnames().front(), error.parameter());
    if (sets) return error.messageFor("--" + option->get_lnames().front());
  }
  return error.what();
}

std::function<void(long long)> faultInjection(const char* variable, const char* item) {
  const char* value = std::getenv(variable);
  if (!value) return {};
  return [item, fault = std::atoll(value)](long long i) {
    if (i != fault) return;
    std::cerr << (ranks::prefix() + concat("fault injected at ", item, " ", i, "\n"));
    std::raise(SIGKILL);
  };
}

StudyLog stderrLog(const std::string& prefix, bool quiet) {
  if (quiet) return {};
  // One write per line: under mpirun the ranks share stderr.
  return [prefix](const std::string& line) { std::cerr << (prefix + ": " + line + "\n"); };
}

void printStudy(const StudyOutput& output, const CommonOptions& common) {
  if (!common.quiet) std::cout << output.summary << std::flush;
  writeJson(common.jsonPath, output.json);
}

void printBenchmark(const StudyOutput& output, const CommonOptions& common) {
  CommonOptions loud = common;
  loud.quiet = false;
  printStudy(output, loud);
}

}  // namespace acpca::cli
