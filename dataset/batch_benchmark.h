#pragma once
// `bench batch`: a relight batch end to end (open, lightings, projection,
// shading, background, encoding and writing), each stage's share, against two
// references measured in the same run: the machine's streaming read and the
// relight alone (projection and shading), so the batch's cost beyond the
// relighter reads as a ratio on any machine; then the lighting and
// background of the first map's frames timed alone, with no writing
// threads sharing the cores.
#include <optional>

#include "core/study_output.h"
#include "dataset/batch_relight.h"

namespace acpca {

struct BatchBenchmarkOptions {
  BatchRelightOptions batch;      ///< its `out` is a directory the frames go to
  std::optional<BatchPlan> plan;  ///< the batch's plan when made already (else made here)
  double streamGiB = 0.5;         ///< array of the streaming-read loop
};

/// Table (stage, seconds, share of the wall, ms a frame) and the rates, as
/// text and JSON (the batch's own `relight --json` report under "batch").
StudyOutput runBatchBenchmark(const BatchBenchmarkOptions& options);

}  // namespace acpca
