#include "eval/batch_benchmark.h"

#include <algorithm>
#include <string>

#include "core/error.h"
#include "core/statistics.h"
#include "core/text.h"
#include "relight/memory_bandwidth.h"

namespace acpca {

StudyOutput runBatchBenchmark(const BatchBenchmarkOptions& o) {
  if (!(o.streamGiB > 0 && o.streamGiB <= 64))
    throw ParameterError("stream size (GiB)", o.streamGiB, "is out of range (0, 64]");
  const BandwidthMeasurement stream = measureStreamingRead(o.streamGiB * (1 << 30), 5);
  const BatchRelightResult result =
      relightBatch(o.batch, o.plan ? *o.plan : planBatchRelight(o.batch));
  const BatchStages& s = result.stages;
  const double frames = static_cast<double>(result.frames);
  const double endToEnd = s.wall > 0 ? frames / s.wall : 0;
  const double relightAlone =
      s.projection + s.shading > 0 ? frames / (s.projection + s.shading) : 0;

  std::string text = formatted("%-22s %10s %9s %11s\n", "stage", "seconds", "of wall", "ms/frame");
  for (const auto& [name, seconds] : s.named()) {
    std::string label = std::string(name) == "writing" ? "writing (own threads)" : name;
    std::replace(label.begin(), label.end(), '_', ' ');  // the JSON key, in words
    text += formatted("%-22s %10.3f %8.1f%% %11.3f\n", label.c_str(), seconds,
                      s.wall > 0 ? 100 * seconds / s.wall : 0.0,
                      frames > 0 ? 1e3 * seconds / frames : 0.0);
  }
  text += formatted(
      "%lld frame(s) of %s (%s): %.1f frames/s end to end, %.1f frames/s relight alone "
      "(end to end / relight alone: %.3f)\n",
      result.frames, o.batch.input.c_str(), result.method.c_str(), endToEnd, relightAlone,
      relightAlone > 0 ? endToEnd / relightAlone : 0.0);
  text += formatted(
      "streaming read, %.2f GiB array: %.1f GB/s (median of 5); the relighter read "
      "%s a frame, %.1f GB/s while it ran\n",
      o.streamGiB, stream.gbPerSecondMedian, formatBytes(result.bytesPerFrame).c_str(),
      s.projection + s.shading > 0
          ? result.bytesPerFrame * frames / (s.projection + s.shading) / 1e9
          : 0.0);
  StudyOutput out;
  out.summary = text;
  out.json = {{"frames", result.frames},
              {"frames_per_second", endToEnd},
              {"relight_alone_frames_per_second", relightAlone},
              {"streaming_read_gb_per_s", stream.gbPerSecondMedian},
              {"stages", s.json(result.frames)},
              {"batch", result.json}};
  return out;
}

}  // namespace acpca
