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
#include "dataset/batch_frames.h"
#include "dataset/batch_manifest.h"
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

void requireFrameSpace(const BatchRelightOptions& a, ImageSize size,
                       const std::vector<ImageFormat>& formats, bool batch, size_t lightSets) {
  const fs::path out(a.out);
  const long long pixels = static_cast<long long>(size.width) * size.height;
  const int channels = a.background == Background::Alpha ? 4 : 3;
  long long frameBytes = 0;
  ImageEncoding encoding;
  encoding.exrFloat = a.exrFloat;
  for (ImageFormat f : formats) frameBytes += pixels * channels * storedBytesPerValue(f, encoding);
  ResourceNeed need;
  const size_t frames =
      (a.sampling.count > 0 ? static_cast<size_t>(a.sampling.count)
                            : std::max<size_t>(1, a.envs.size()) * a.rotations.size()) *
      lightSets;
  need.what = concat(frames, " frame(s) of ", size.width, "x", size.height);
  need.diskBytes = frameBytes * static_cast<long long>(frames);
  need.largestFile = frameBytes;
  need.diskDirectory = batch ? a.out : (out.has_parent_path() ? out.parent_path().string() : ".");
  if (batch && !fs::exists(a.out)) need.diskDirectory = fs::path(a.out).parent_path().string();
  need.diskAdvice = "write fewer frames at once, or to another disk";
  requireResources(need, a.force);
}

std::vector<ImageFormat> imageFormatsFor(const std::string& format, const std::string& out,
                                         bool batch) {
  ++specParseCounts().formats;
  if (!format.empty()) return parseImageFormatList(format == "both" ? "exr,png" : format);
  if (batch) return {ImageFormat::Exr};
  const ImageFormatRow* row = imageFormatOfExtension(fs::path(out).extension().string());
  if (!row) {
    std::string extensions;
    for (const ImageFormatRow& r : kImageFormats)
      if (extensions.find(r.extension) == std::string::npos) {
        if (!extensions.empty()) extensions += '/';
        extensions += r.extension;
      }
    throw ParameterError(
        "output path", out,
        concat("cannot tell the format from the extension; use ", extensions, " or a format"));
  }
  return {row->format};
}

BatchPlan planBatchRelight(const BatchRelightOptions& a) {
  if (a.timingRepeats < 0) throw ParameterError("timing frames", a.timingRepeats, "must be >= 0");
  if (a.envs.empty() && a.lights.empty() && a.lightPath.empty())
    throw ParameterError("environment", "", "give at least one lighting (or a local light)");
  if (a.rotations.empty()) throw ParameterError("rotation", "", "give at least one rotation");
  if (a.envs.empty() && a.rotations.size() > 1)
    throw ParameterError("rotation", "", "rotates environments: give one with it");
  BatchPlan plan;
  plan.batch = a.batch();
  plan.lightSets = lightSets(a);
  if (!(a.anchorSpread >= 0 && a.anchorSpread <= 64))
    throw ParameterError("anchor spread", a.anchorSpread, "is not in 0..64 texels");
  requireFinite(a.exposure, "exposure");
  if (a.sampling.count == 0 && a.sampling.exposureJitter != 0)
    throw ParameterError("exposure jitter", a.sampling.exposureJitter,
                         "jitters drawn lightings: give a number of environment samples");
  if (a.sampling.count != 0) {
    validateLightingSampling(a.sampling);
    if (a.envs.empty())
      throw ParameterError("environment samples", a.sampling.count, "needs maps to draw from");
    if (a.rotations.size() != 1 || !a.rotations[0].isIdentity())
      throw ParameterError("rotation", "",
                           "cannot be given with environment samples: each draw has its own");
  }
  if (a.pngLevel < 0 || a.pngLevel > 9)
    throw ParameterError("PNG level", a.pngLevel, "is not 0..9");
  if (a.colmap && !plan.batch)
    throw ParameterError("COLMAP", "", "is written beside a batch's frames: give a batch");
  if (a.shardSize < 0) throw ParameterError("shard size", a.shardSize, "must be at least 1");
  if (a.shardSize > 0 && !plan.batch)
    throw ParameterError("shard size", a.shardSize, "shards a batch's frames: give a batch");
  plan.formats = imageFormatsFor(a.format, a.out, plan.batch);
  const std::vector<ImageFormat>& formats = plan.formats;
  // No frame may replace the model, the transport or a lighting it reads.
  std::vector<std::string> inputs = a.envs;
  for (const std::string& view : a.viewInputs()) inputs.push_back(view);
  if (!a.lightPath.empty()) inputs.push_back(a.lightPath);
  if (plan.batch) {
    refuseDirectoryOverInputs(a.out, inputs);
    return plan;
  }
  const fs::path out(a.out);
  for (ImageFormat format : formats)
    refuseOutputOverInputs(
        formats.size() > 1
            ? (out.parent_path() / (out.stem().string() + imageExtension(format))).string()
            : a.out,
        inputs);
  return plan;
}

}  // namespace acpca
