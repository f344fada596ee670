#include "dataset/group_relight.h"

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

/// One group relit; in timing mode an untimed warm-up, then the timed
/// repeats (frameMs: each frame's median). Times that count go to msPerFrame
/// (rank 0's own here; the others' as they arrive).
std::vector<std::vector<float>> relightTimed(const RelightSource& source,
                                             const std::vector<LatticeLighting>& lightings,
                                             int timingRepeats, std::vector<double>& frameMs,
                                             std::vector<double>& msPerFrame) {
  const int rank = ranks::rank(), rankCount = ranks::count();
  const size_t count = lightings.size();
  std::vector<double> ms;
  std::vector<std::vector<float>> results = source.relight(lightings, ms);
  frameMs = ms;
  if (timingRepeats > 0) {
    frameMs.assign(count, 0.0);
    std::vector<std::vector<double>> repeats(count);
    for (int rep = 0; rep < timingRepeats; ++rep) {
      results = source.relight(lightings, ms);
      for (size_t k = 0; k < count; ++k) repeats[k].push_back(ms[k]);
      if (rankCount == 1) msPerFrame.insert(msPerFrame.end(), ms.begin(), ms.end());
    }
    for (size_t k = 0; k < count; ++k) frameMs[k] = median(repeats[k]);
    if (rankCount > 1 && rank == 0)
      msPerFrame.insert(msPerFrame.end(), frameMs.begin(), frameMs.end());
  } else if (rank == 0) {
    msPerFrame.insert(msPerFrame.end(), ms.begin(), ms.end());
  }
  return results;
}

}  // namespace

void relightGroupImages(const RelightSource& source, const ImageComposer& composer,
                        FrameBuffers& buffers, const std::vector<LatticeLighting>& lightings,
                        int channels, const std::function<void(size_t, float*)>& backgroundOf,
                        int timingRepeats, std::vector<double>& msPerFrame, BatchStages& stages,
                        const std::function<void(size_t, std::vector<float>&, double)>& done) {
  const size_t values = static_cast<size_t>(source.header.camera.size.pixels()) * channels;
  // Lightings that give no light (local lights alone): rows of zeros, which
  // add nothing to the background, so nothing is relit (at 1024x1024 a
  // model's pass over its coefficients, as long as a sky relight).
  const auto dark = [](const LatticeLighting& l) {
    return std::all_of(l.begin(), l.end(), [](double v) { return v == 0; });
  };
  if (timingRepeats == 0 && std::all_of(lightings.begin(), lightings.end(), dark)) {
    for (size_t k = 0; k < lightings.size(); ++k) {
      const Stopwatch background;
      std::vector<float> pixels = buffers.take(values);
      backgroundOf(k, pixels.data());
      stages.background += background.seconds();
      if (ranks::rank() == 0) msPerFrame.push_back(0);
      done(k, pixels, 0);
    }
    return;
  }
  if (source.model && timingRepeats == 0) {
    const Stopwatch group;
    source.model->lightGroup(lightings);
    stages.projection += group.seconds();
    const double shared = group.milliseconds() / static_cast<double>(lightings.size());
    for (size_t k = 0; k < lightings.size(); ++k) {
      const Stopwatch background;
      std::vector<float> pixels = buffers.take(values);
      backgroundOf(k, pixels.data());
      stages.background += background.seconds();
      const Stopwatch watch;
      source.model->shadeFrameInto(k, pixels.data(), channels);
      stages.shading += watch.seconds();
      const double ms = shared + watch.milliseconds();
      if (ranks::rank() == 0) msPerFrame.push_back(ms);
      done(k, pixels, ms);
    }
    return;
  }
  std::vector<double> frameMs;
  const Stopwatch relit;
  std::vector<std::vector<float>> rows =
      relightTimed(source, lightings, timingRepeats, frameMs, msPerFrame);
  stages.shading += relit.seconds();
  for (size_t k = 0; k < lightings.size(); ++k) {
    const Stopwatch background;
    std::vector<float> pixels = buffers.take(values);
    backgroundOf(k, pixels.data());
    composer.addRows(rows[k].data(), pixels.data(), channels);
    stages.background += background.seconds();
    std::vector<float>().swap(rows[k]);
    done(k, pixels, frameMs[k]);
  }
}

}  // namespace acpca
