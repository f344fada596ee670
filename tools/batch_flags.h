#pragma once
// The flags `relight` and `bench batch` share: which frames (--env, --rotate),
// how a map's sources are lit (--sun, --lamp-rays), where and how they are
// written (--out, --format, the codecs, the labels), bound to
// BatchRelightOptions.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "dataset/batch_relight.h"

namespace acpca::cli {

struct BatchFlags {
  std::vector<std::string> envs, rotations;
  std::string exrCompression, aovs, labelFormat, sampleRotation, tone;
  std::string lampRays;  ///< empty: the default
  std::string sun = "auto";
  CLI::Option* envSample = nullptr;  ///< given at all: 0 is refused, not taken as none
  CLI::Option* shardSize = nullptr;  ///< given at all: 0 is refused, not taken as none

  /// Declares the flags on `command`, bound to `options` (and this).
  void add(CLI::App& command, BatchRelightOptions& options, const std::string& outHelp);
  /// Puts the parsed maps, rotations and codec into `options`, checks them
  /// (and that no output replaces an input, the JSON report included) and
  /// returns the batch's plan, its specs parsed once.
  BatchPlan apply(BatchRelightOptions& options, const std::string& jsonPath) const;
};

}  // namespace acpca::cli
