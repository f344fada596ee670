#pragma once
// `bench relight`: the model relighter's ms per frame and bandwidth against the
// machine's streaming-read bandwidth, a dense relight of the same image from
// memory and other models (e.g. global PCA at equal error), all in one run.
#include <string>
#include <vector>

#include "core/study_output.h"

namespace acpca {

struct RelightBenchmarkOptions {
  std::string model;      ///< the model timed first; the others are set against it
  std::string transport;  ///< optional: the dense reference (and the errors)
  std::vector<std::string> envs, baselines;
  int frames = 50, denseFrames = 5;
  double streamGiB = 1.0;
  int threads = 1;  ///< as the caller limited them (reported only)
};

void validateRelightBenchmarkOptions(const RelightBenchmarkOptions& options);

/// The table as text and the figures as JSON.
StudyOutput runRelightBenchmark(const RelightBenchmarkOptions& options);

}  // namespace acpca
