#pragma once
// Helpers every subcommand shares: options common to all, JSON output, the
// flags errors name, fault injection for the tests.
#include <CLI/CLI.hpp>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/progress_line.h"
#include "core/resources.h"
#include "core/study_output.h"
#include "core/text.h"
#include "core/thread_limit.h"
#include "imageio/image_output.h"
#include "lighting/lighting.h"
#include "model/model.h"
#include "precompute/scene.h"
#include "relight/image_composer.h"

namespace acpca::cli {

/// --quiet, --json FILE|-, --threads N, as most subcommands take them.
struct CommonOptions {
  bool quiet = false;
  std::string jsonPath;
  int threads = 0;
  void add(CLI::App& app, bool withThreads = true);
};

/// Writes JSON to a file (atomically) or to stdout for "-"; nothing when empty.
void writeJson(const std::string& path, const nlohmann::json& value);

/// `first` followed by `more` (a command's lightings and the files it reads).
std::vector<std::string> joined(std::vector<std::string> first,
                                const std::vector<std::string>& more);

/// The --json report's opening of a command that renders `scene` into `out`:
/// out, scene, width, height, ranks and peak_memory_bytes.
nlohmann::json sceneReport(const std::string& out, const Scene& scene);

/// Refuses, before any work, an output that would replace one of `inputs`
/// (core/input_guard.h): the files `outFiles` (--json's "-" is none) and the
/// directories `outDirs`.
void refuseOutputsOverInputs(const std::vector<std::string>& inputs,
                             const std::vector<std::string>& outFiles,
                             const std::vector<std::string>& outDirs = {});

/// Says which library parameters flags of `command` set where a flag is not
/// named after its parameter (`--spp` sets "samples per pixel"; `--global-energy`
/// sets "global energy" and needs no entry), so that errors name the flag.
void nameParameters(CLI::App& command,
                    const std::map<std::string, std::vector<std::string>>& flagParameters);

/// --fast-rotation: sets `mode` to RotationMode::FastLattice.
void addFastRotationFlag(CLI::App& command, RotationMode& mode);

/// --background as given, or else its default for the input file: black for a
/// captured light set (no camera sees an environment behind it), else env.
Background backgroundFor(const std::string& given, const std::string& input);

/// ParameterError's message with the flag of the command that ran (`app`'s
/// parsed subcommand) that sets the parameter in place of the library's name
/// for it; the message as is for parameters without a flag.
std::string messageWithFlag(const ParameterError& error, const CLI::App& app);

/// For the tests: when the environment variable `variable` holds N, a hook that
/// says so and kills this process (SIGKILL) as it starts `item` N; else none.
std::function<void(long long)> faultInjection(const char* variable, const char* item);

/// A log callback printing "PREFIX: line" on stderr, one write a line; none
/// when quiet.
StudyLog stderrLog(const std::string& prefix, bool quiet);

/// Prints a study's summary on stdout (unless quiet) and writes its JSON.
void printStudy(const StudyOutput& output, const CommonOptions& common);
/// The same for a benchmark, whose table is its result: printed even when quiet.
void printBenchmark(const StudyOutput& output, const CommonOptions& common);

}  // namespace acpca::cli
