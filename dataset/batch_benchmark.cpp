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
#include "lighting/map_source_listing.h"
#include "lighting/map_sources.h"
#include "relight/image_composer.h"
#include "relight/lamp_light.h"
#include "relight/memory_bandwidth.h"
#include "relight/relight_source.h"

namespace acpca {

namespace {

/// The lighting and background stages of a batch's frames, ms a frame, on
/// all cores with nothing beside them; and, where the batch lights the map's
/// sources exactly, the frame through the lattice (the whole map's lighting,
/// the relight, the background) against the same frame with its sources
/// lit exactly (the lighting of the map less them, the relight, the
/// background, the sources).
struct StagesAlone {
  double lightingMs = 0, backgroundMs = 0;
  int frames = 0;
  double relightMs = 0;       ///< the relight of the frames' lattice lightings
  double sourcesMs = 0;       ///< the sources lit exactly (0: none)
  double restLightingMs = 0;  ///< the lighting of the map less its sources
  double sourceRays = 0;      ///< shadow rays a frame
  int sourceCount = 0;

  double latticeFrameMs() const { return lightingMs + relightMs + backgroundMs; }
  double exactFrameMs() const { return restLightingMs + relightMs + backgroundMs + sourcesMs; }
};

/// The median over passes 1..3 of ms a frame of `work` over `frames` frames
/// (pass 0 warms it: row sums, the occluder, caches).
template <typename Work>
double medianMsPerFrame(double frames, Work work) {
  std::vector<double> ms;
  for (int pass = 0; pass < 4; ++pass) {
    const Stopwatch watch;
    work();
    if (pass > 0) ms.push_back(1e3 * watch.seconds() / frames);
  }
  return median(ms);
}

/// The batch's first map under each of its rotations, timed stage by stage
/// after the batch: in the batch the writing threads share the cores, so its
/// stages read longer than their own work. None without a map.
std::optional<StagesAlone> stagesAlone(const BatchRelightOptions& a) {
  if (a.envs.empty()) return std::nullopt;
  RelightSource source = openRelightSource(a.input, a.maxRank);
  const TransportHeader& header = source.header;
  const DomainLighting domain(header);
  const std::unique_ptr<Environment> env = loadEnvironment(a.envs[0]);
  const ImageComposer composer(header);
  const int channels = ImageComposer::channels(a.background);
  std::vector<float> pixels(static_cast<size_t>(header.camera.size.pixels()) * channels);
  StagesAlone alone;
  alone.frames = static_cast<int>(a.rotations.size());
  const auto frames = static_cast<double>(a.rotations.size());
  // The lightings as the batch makes a map's frames, together.
  std::vector<LatticeLighting> lightings;
  alone.lightingMs = medianMsPerFrame(
      frames, [&] { lightings = domain.lightings(*env, a.rotations, a.rotationMode); });
  std::vector<double> background;
  for (const EnvRotation& rotation : a.rotations) {
    const Stopwatch drawn;
    composer.background(a.background, *env, rotationMatrix(rotation), pixels.data());
    background.push_back(1e3 * drawn.seconds());
  }
  alone.backgroundMs = median(background);
  std::vector<double> ms;
  alone.relightMs = medianMsPerFrame(frames, [&] { source.relight(lightings, ms); });
  if (!a.sources || a.lamps.mode != LampMode::Exact || !source.sourcesUnavailable.empty())
    return alone;
  const SplitEnvironment split = env->splitSources(*a.sources);
  if (split.sources.empty()) return alone;
  alone.sourceCount = static_cast<int>(split.sources.size());
  alone.restLightingMs =
      medianMsPerFrame(frames, [&] { domain.lightings(*split.rest, a.rotations, a.rotationMode); });
  const long long raysBefore = source.lampShadowRays();
  alone.sourcesMs = medianMsPerFrame(frames, [&] {
    for (const EnvRotation& rotation : a.rotations)
      source.relightSources(turnedSources(split.sources, rotation), a.lamps.sphereRays);
  });
  alone.sourceRays = static_cast<double>(source.lampShadowRays() - raysBefore) / (4 * frames);
  return alone;
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
  if (alone) {
    text += formatted(
        "alone, nothing beside them (the first map under %d rotation(s), medians): lighting %.3f "
        "ms, relight %.3f ms, background %.3f ms a frame\n",
        alone->frames, alone->lightingMs, alone->relightMs, alone->backgroundMs);
    if (alone->sourcesMs > 0)
      text += formatted(
          "its %d source(s) lit exactly (%d rays a sample in a penumbra): %.3f ms a frame, %.0f "
          "shadow rays; the frame with them %.3f ms against %.3f ms through the lattice "
          "(with / lattice: %.2fx)\n",
          alone->sourceCount, o.batch.lamps.sphereRays, alone->sourcesMs, alone->sourceRays,
          alone->exactFrameMs(), alone->latticeFrameMs(),
          alone->exactFrameMs() / alone->latticeFrameMs());
  }
  StudyOutput out;
  out.summary = text;
  out.json = {{"frames", result.frames},
              {"frames_per_second", endToEnd},
              {"relight_alone_frames_per_second", relightAlone},
              {"streaming_read_gb_per_s", stream.gbPerSecondMedian},
              {"stages", s.json(result.frames)},
              {"batch", result.json}};
  if (alone) {
    out.json["alone_ms_per_frame"] = {{"lighting", alone->lightingMs},
                                      {"relight", alone->relightMs},
                                      {"background", alone->backgroundMs},
                                      {"frames", alone->frames}};
    if (alone->sourcesMs > 0)
      out.json["sources_alone"] = {
          {"sources", alone->sourceCount},
          {"lamp_rays", o.batch.lamps.sphereRays},
          {"ms_per_frame", alone->sourcesMs},
          {"rest_lighting_ms_per_frame", alone->restLightingMs},
          {"shadow_rays_per_frame", alone->sourceRays},
          {"exact_frame_ms", alone->exactFrameMs()},
          {"lattice_frame_ms", alone->latticeFrameMs()},
          {"exact_over_lattice", alone->exactFrameMs() / alone->latticeFrameMs()}};
  }
  return out;
}

}  // namespace acpca
