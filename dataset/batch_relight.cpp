#include "dataset/batch_relight.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <mutex>
#include <optional>
#include <unordered_map>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/file_hash.h"
#include "core/input_guard.h"
#include "core/ordered_writer.h"
#include "core/rank_gather.h"
#include "core/ranks.h"
#include "core/resources.h"
#include "core/statistics.h"
#include "core/stopwatch.h"
#include "core/table.h"
#include "core/text.h"
#include "core/warning.h"
#include "dataset/batch_manifest.h"
#include "dataset/batch_run.h"
#include "dataset/batch_shards.h"
#include "dataset/camera_files.h"
#include "dataset/dataset_identity.h"
#include "dataset/frame_files.h"
#include "dataset/frame_labels.h"
#include "imageio/image_output.h"
#include "lighting/domain_lighting.h"
#include "lighting/envmap_export.h"
#include "lighting/lighting.h"
#include "lighting/map_source_listing.h"
#include "lighting/sh_lighting.h"
#include "lighting/spec_parsing.h"
#include "model/model.h"
#include "model/model_file.h"
#include "relight/dense_relight.h"
#include "relight/image_composer.h"
#include "relight/model_relighter.h"
#include "relight/relight_source.h"

namespace acpca {

namespace fs = std::filesystem;

namespace {

/// The batch's times and bytes per frame, in words and as JSON.
void summarize(BatchRelightResult& result, const BatchRelightOptions& a,
               const RelightSource& source, size_t frames, std::vector<double> msPerFrame) {
  const double med = median(msPerFrame);
  const auto [lowest, highest] = std::minmax_element(msPerFrame.begin(), msPerFrame.end());
  const double fastest = msPerFrame.empty() ? 0 : *lowest,
               slowest = msPerFrame.empty() ? 0 : *highest;
  // The frames of a group share one read of T (dense), or of V_g and the
  // bases (a model); groups hold frames / ceil(frames / 32) frames on average.
  const double groupFrames =
      frames == 0 ? 1 : double(frames) / double((frames + kFramesPerGroup - 1) / kFramesPerGroup);
  const double bytesPerFrame =
      frames == 0    ? 0
      : source.dense ? double(source.bytesPerPass) / groupFrames
                     : double(source.model->bytesPerFrame(static_cast<size_t>(groupFrames)));
  const double gbPerSecond = med > 0 ? bytesPerFrame / (med * 1e6) : 0;
  result.summary =
      concat("relit ", frames, " frame(s) from ", a.input, " (", source.method,
             "): ", msPerFrame.size(), " timed, median ", med, " ms/frame (min ", fastest, ", max ",
             slowest, "), ", formatBytes(bytesPerFrame), " read per frame, ", gbPerSecond, " GB/s");
  result.method = source.method;
  result.frames = static_cast<long long>(frames);
  result.bytesPerFrame = bytesPerFrame;
  result.json = {{"input", a.input},
                 {"method", source.method},
                 {"frames", frames},
                 {"timed_frames", msPerFrame.size()},
                 {"ms_per_frame_median", med},
                 {"ms_per_frame_min", fastest},
                 {"ms_per_frame_max", slowest},
                 {"bytes_per_frame", bytesPerFrame},
                 {"gb_per_s", gbPerSecond}};
  result.msPerFrame = std::move(msPerFrame);
}

/// How many frames went below zero and how far, in the summary and the JSON
/// report: a model's reconstruction undershoots where the transport is small.
void reportNegatives(BatchRelightResult& result, const BatchRun& run) {
  result.framesWithNegatives = run.framesWithNegatives;
  result.negatives = run.negatives;
  result.json["negative"] = {{"frames", run.framesWithNegatives},
                             {"values", run.negatives.values},
                             {"most_negative", run.negatives.mostNegative},
                             {"clamped", !run.a.keepNegative}};
  if (run.framesWithNegatives > 0)
    result.summary += concat("; ", run.framesWithNegatives, " frame(s) had ", run.negatives.values,
                             " value(s) below zero (down to ", run.negatives.mostNegative, "), ",
                             run.a.keepNegative ? "kept (--keep-negative)" : "clamped to 0");
}

}  // namespace

std::vector<std::pair<const char*, double>> BatchStages::named() const {
  return {{"open", open},
          {"lighting", lighting},
          {"projection", projection},
          {"shading", shading},
          {"local_lights", localLights},
          {"sources", sources},
          {"background", background},
          {"writing", writing},
          {"waiting_for_writing", waitingForWriting},
          {"wall", wall}};
}

nlohmann::json BatchStages::json(long long frames) const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [name, seconds] : named())
    j[name] = {{"seconds", seconds},
               {"share_of_wall", wall > 0 ? seconds / wall : 0.0},
               {"ms_per_frame", frames > 0 ? 1e3 * seconds / frames : 0.0}};
  return j;
}

BatchRelightResult relightBatch(const BatchRelightOptions& options) {
  return relightBatch(options, planBatchRelight(options));
}

BatchRelightResult relightBatch(const BatchRelightOptions& a, const BatchPlan& plan) {
  const bool batch = plan.batch;
  if (batch) refuseAnotherDataset(a.out, datasetIdentity(a));
  if (a.shardSize > 0) refuseUnclaimedShards(a.out);
  const Stopwatch wall;
  BatchRun run(a, plan);
  const std::vector<std::string> views = a.viewInputs();
  // The lightings load beside the model's opening; what either finds wrong
  // is reported in the order of old: the model first.
  std::vector<LoadedLighting> loaded;
  tbb::task_group loading;
  loading.run([&] { loaded = loadLightings(a.envs, a.sources); });
  std::optional<RelightSource> source;
  try {
    source.emplace(openRelightSource(views[0], a.maxRank));
    requireAovs(source->header, a.aovs, views[0], !source->dense);
    requireLightingDomain(source->header, run, views[0]);
  } catch (...) {
    loading.cancel();  // the model's error comes now, not after every map
    loading.wait();
    throw;
  }
  run.stages.open = wall.seconds();
  loading.wait();
  requireFrameSpace(a, source->header.camera.size, run.formats, batch,
                    run.sets.size() * views.size());
  // Sampled lighting draws from every map given: one that cannot be read
  // stops the batch, so that a seed always makes the same frames.
  run.inputs = takeInputs(a.envs, std::move(loaded), batch && a.sampling.count == 0, a.warn);
  // Local lights alone: one frame over a black environment.
  if (run.inputs.empty()) run.inputs.push_back({"", makeConstantEnvironment(Rgb::Zero()), "", {}});
  for (const auto& set : run.sets) run.setSpecs.push_back(canonicalSpecs(set));
  run.viewFrames = batchFrames(a, run.inputs, run.sets.size());
  const int indexDigits =
      frameIndexDigits(static_cast<long long>(run.viewFrames.size() * views.size()));
  if (batch) {
    requireDistinctFrameFiles(run, views.size(), indexDigits);
    createOutputDirectory(a.out);
    if (ranks::rank() == 0) writeDatasetIdentity(a.out, datasetIdentity(a));
  }
  if (batch && ranks::rank() == 0)
    run.manifests.emplace(a, run.inputs, views.size(),
                          static_cast<long long>(run.viewFrames.size() * views.size()),
                          indexDigits);
  for (size_t k = 0; k < views.size(); ++k) {
    if (k > 0) {  // one view's model in memory at a time
      source.reset();
      const Stopwatch open;
      source.emplace(openRelightSource(views[k], a.maxRank));
      requireAovs(source->header, a.aovs, views[k], !source->dense);
      requireLightingDomain(source->header, run, views[k]);
      run.stages.open += open.seconds();
    }
    if (!source->header.isLightSet()) run.cameras.push_back(source->header.camera);
    run.frames +=
        relightView(run, *source, BatchView{k, views.size(), views[k], run.frames, indexDigits});
  }
  // The camera files read the finished manifest.jsonl: one pass, flat memory.
  if (run.manifests) {
    if (run.manifests->shards) run.manifests->shards->writeIndex();
    run.manifests.reset();
    if (run.cameras.size() == views.size()) writeCameraFiles(a.out, run.cameras, a.colmap);
  }
  run.uncovered.report();
  BatchRelightResult result;
  if (ranks::rank() != 0) {  // rank 0 wrote the images and reports
    result.method = source->method;
    result.frames = static_cast<long long>(run.frames);
    return result;
  }
  for (const auto& in : run.inputs)
    if (!in.env) result.failed.push_back(in.error);
  BatchStages& stages = run.stages;
  stages.wall = wall.seconds();
  const size_t frames = run.frames;
  summarize(result, a, *source, frames, std::move(run.msPerFrame));
  if (a.envs.empty())  // local lights alone: no environment was relit
    result.summary =
        concat("relit ", frames, " frame(s) from ", a.input, " (", source->method,
               ") under local lights alone, ",
               1e3 * stages.localLights / static_cast<double>(run.sets.size() * views.size()),
               " ms per light set");
  result.stages = stages;
  result.json["stages"] = stages.json(static_cast<long long>(frames));
  result.json["frames_per_second"] = stages.wall > 0 ? frames / stages.wall : 0.0;
  if (run.lampShadowRays > 0) {
    const double perPixel = double(run.lampShadowRays) / double(std::max(1LL, run.lampPixels));
    result.json["lamp_shadow_rays"] = {{"total", run.lampShadowRays},
                                       {"per_covered_pixel", perPixel}};
    result.summary += concat("; lamps: ", perPixel, " shadow rays per covered pixel");
  }
  if (run.sourceShadowRays > 0) {
    const double perSource = double(run.sourceShadowRays) / double(std::max(1LL, run.sourcePixels));
    result.json["source_shadow_rays"] = {{"total", run.sourceShadowRays},
                                         {"per_source_per_covered_pixel", perSource}};
    result.summary += concat("; sources: ", perSource, " shadow rays per covered pixel each");
  }
  result.summary += concat("; ", frames, " frame(s) written in ", stages.wall, " s (",
                           stages.wall > 0 ? frames / stages.wall : 0.0, " frames/s)");
  nlohmann::json sources = nlohmann::json::array();
  for (const EnvInput& in : run.inputs)
    if (!in.split.sources.empty())
      sources.push_back({{"env", in.spec}, {"sources", sourcesJson(in.split.sources)}});
  result.json["sources"] = std::move(sources);
  result.json["outputs"] = std::move(run.outputs);
  if (!a.aovs.empty()) result.json["labels"] = run.labels;
  if (views.size() > 1) result.json["views"] = views;
  result.json["failed"] = result.failed;
  reportNegatives(result, run);
  return result;
}

void refuseFailedMaps(const BatchRelightResult& result, size_t maps) {
  if (result.failed.empty()) return;
  std::string list;
  for (const auto& f : result.failed) list += "\n  " + f;
  throw UserError(concat(result.failed.size(), " of ", maps,
                         " environment maps could not be used (the others were written):", list));
}

}  // namespace acpca
