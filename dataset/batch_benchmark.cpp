#include "dataset/batch_benchmark.h"

#include <algorithm>
#include <memory>
#include <optional>
#include <string>

#include "core/error.h"
#include "core/statistics.h"
#include "core/stopwatch.h"
#include "core/text.h"
#include "lighting/domain_lighting.h"
#include "lighting/environment.h"
#include "relight/image_composer.h"
#include "relight/memory_bandwidth.h"
#include "relight/relight_source.h"

namespace acpca {

namespace {

/// The lighting and background stages of a batch's frames, ms a frame, on
/// all cores with nothing beside them.
struct StagesAlone {
  double lightingMs = 0, backgroundMs = 0;
  int frames = 0;
};

/// The batch's first map under each of its rotations, timed stage by stage
/// after the batch: in the batch the writing threads share the cores, so its
/// stages read longer than their own work. None without a map.
std::optional<StagesAlone> stagesAlone(const BatchRelightOptions& a) {
  if (a.envs.empty()) return std::nullopt;
  const TransportHeader header = openRelightSource(a.input, a.maxRank).header;
  const DomainLighting domain(header);
  const std::unique_ptr<Environment> env = loadEnvironment(a.envs[0]);
  const ImageComposer composer(header);
  const int channels = ImageComposer::channels(a.background);
  std::vector<float> pixels(static_cast<size_t>(header.camera.size.pixels()) * channels);
  // The lightings as the batch makes a map's frames, together (after one
  // untimed pass that makes the map's row sums): the median of 3 passes.
  const auto frames = static_cast<double>(a.rotations.size());
  std::vector<double> lighting;
  for (int pass = 0; pass < 4; ++pass) {
    const Stopwatch lit;
    const std::vector<LatticeLighting> l = domain.lightings(*env, a.rotations, a.rotationMode);
    if (pass > 0) lighting.push_back(1e3 * lit.seconds() / frames);
  }
  std::vector<double> background;
  for (const EnvRotation& rotation : a.rotations) {
    const Stopwatch drawn;
    composer.background(a.background, *env, rotationMatrix(rotation), pixels.data());
    background.push_back(1e3 * drawn.seconds());
  }
  return StagesAlone{median(lighting), median(background), static_cast<int>(a.rotations.size())};
}

}  // namespace

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
  const std::optional<StagesAlone> alone = stagesAlone(o.batch);
  if (alone)
    text += formatted(
        "alone, nothing beside them (the first map under %d rotation(s), medians): lighting %.3f "
        "ms, background %.3f ms a frame\n",
        alone->frames, alone->lightingMs, alone->backgroundMs);
  StudyOutput out;
  out.summary = text;
  out.json = {{"frames", result.frames},
              {"frames_per_second", endToEnd},
              {"relight_alone_frames_per_second", relightAlone},
              {"streaming_read_gb_per_s", stream.gbPerSecondMedian},
              {"stages", s.json(result.frames)},
              {"batch", result.json}};
  if (alone)
    out.json["alone_ms_per_frame"] = {{"lighting", alone->lightingMs},
                                      {"background", alone->backgroundMs},
                                      {"frames", alone->frames}};
  return out;
}

}  // namespace acpca
