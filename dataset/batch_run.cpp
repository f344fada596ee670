#include "dataset/batch_run.h"

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
#include "relight/rank_limit.h"
#include "relight/relight_source.h"

namespace acpca {

namespace fs = std::filesystem;

void requireLightingDomain(const TransportHeader& h, const BatchRun& run, const std::string& path) {
  const BatchRelightOptions& a = run.a;
  if (!h.isLightSet()) return;
  if (a.colmap)
    throw ParameterError("COLMAP", path,
                         "is a captured light set: it has no camera for a COLMAP model");
  requireBackgroundShown(h, a.background, path);
  for (const auto& lights : run.sets) requireLocalLightsApply(h, path, false, lights);
  DomainLighting::requireRotationMode(true, a.rotationMode);
}

void requireDistinctFrameFiles(const BatchRun& run, size_t views, int indexDigits) {
  const BatchRelightOptions& a = run.a;
  std::vector<std::string> suffixes;
  for (ImageFormat format : run.formats) suffixes.push_back(imageExtension(format));
  if (a.lightingImages) suffixes.push_back("_lighting.exr");
  if (std::find(a.aovs.begin(), a.aovs.end(), Aov::Shading) != a.aovs.end()) {
    if (a.labelFormat != LabelFormat::Npy) suffixes.push_back("_shading.exr");
    if (a.labelFormat != LabelFormat::Exr) suffixes.push_back("_shading.npy");
  }
  const std::vector<BatchFrame>& frames = run.viewFrames;
  const auto viewOf = [&](size_t k) {
    const size_t v = k / frames.size();
    return BatchView{v, views, "", v * frames.size(), indexDigits};
  };
  requireDistinctFiles(
      frames.size() * views,
      [&](size_t k) {
        const std::string stem = (fs::path(a.out) / frameStem(a, frames[k % frames.size()],
                                                              viewOf(k), k % frames.size()))
                                     .string();
        std::vector<std::string> files;
        for (const std::string& suffix : suffixes) files.push_back(stem + suffix);
        return files;
      },
      [&](size_t k) {
        const BatchFrame& f = frames[k % frames.size()];
        return lightingInWords(f, run.setSpecs[f.lights]) +
               (views > 1 ? concat(" in view ", k / frames.size()) : std::string());
      });
}

bool sourcesLitExactly(const BatchRun& run, const RelightSource& source, const std::string& path) {
  const BatchRelightOptions& a = run.a;
  if (!a.sources || a.lamps.mode != LampMode::Exact) return false;
  if (source.sourcesUnavailable.empty()) return true;
  const bool any = std::any_of(run.inputs.begin(), run.inputs.end(),
                               [](const EnvInput& in) { return !in.split.sources.empty(); });
  if (any && !source.header.isLightSet())
    warn(concat(path, ": the maps' suns and bright lamps go through the lattice (their shadows ",
                "come out soft and shifted by up to a texel): ", source.sourcesUnavailable,
                "; --sun off asks for it without this warning"));
  return false;
}

size_t relightView(BatchRun& run, const RelightSource& source, BatchView view) {
  const BatchRelightOptions& a = run.a;
  BatchStages& stages = run.stages;
  std::vector<double>& msPerFrame = run.msPerFrame;
  const DomainLighting domain(source.header);
  LocalLightRows localRows(source, run.sets, a.anchorSpread, a.lamps, stages.localLights);
  const bool exactSources = view.exactSources = sourcesLitExactly(run, source, view.input);
  view.method = source.method;
  if (source.model) view.costPerPixel = costMetricPerPixel(*source.model);
  const long long raysBefore = source.lampShadowRays();
  // Frames in groups: each group streams T once; memory stays flat for any count.
  const std::vector<BatchFrame>& frames = run.viewFrames;
  const int rank = ranks::rank();
  FrameBuffers buffers;  // before the writing threads that hand buffers back
  std::optional<FrameWriting> writing;
  if (rank == 0)
    writing.emplace(a, frames, run.formats, run.batch, run.setSpecs, domain, source.header,
                    std::move(view), run.manifests ? &*run.manifests : nullptr, buffers);
  // Under mpirun -np K frame i goes to rank i mod K; rank 0 takes each
  // composed image (and its time) in frame order (a sender waits its turn, so
  // memory stays bounded): the same files for any K.
  const int channels = ImageComposer::channels(a.background);
  const ImageSize size = source.header.camera.size;
  // Another rank's frame arrives with its time as one more value; rank 0's
  // own frames come as they are (no copy of the image to append it), their
  // time in ownMs.
  double ownMs = 0;
  const auto deliver = [&](long long i, std::vector<float>& pixels) {
    const bool own = ranks::ownerOf(i) == 0;
    ACPCA_CHECK(own || !pixels.empty(), "frame ", i, " arrived empty");
    const double ms = own ? ownMs : pixels.back();
    if (!own) pixels.pop_back(), msPerFrame.push_back(ms);  // rank 0's own are counted below
    writing->submit(static_cast<size_t>(i),
                    Image{size.width, size.height, channels, std::move(pixels)}, ms);
  };
  ranks::Gather<float> gather(static_cast<long long>(frames.size()), ranks::GatherOrder::ItemOrder,
                              deliver);
  std::vector<size_t> mine;
  for (long long i : ranks::itemsOfThisRank(static_cast<long long>(frames.size())))
    mine.push_back(static_cast<size_t>(i));
  // A group's frames of one map after another (a batch runs map by map)
  // are made together (DomainLighting's many rotations), the runs of
  // different maps at once.
  const auto lightingsOf = [&](size_t first, size_t n) {
    std::vector<size_t> runStarts;
    for (size_t k = 0; k < n; ++k)
      if (k == 0 || frames[mine[first + k]].input != frames[mine[first + k - 1]].input)
        runStarts.push_back(k);
    runStarts.push_back(n);
    std::vector<LatticeLighting> lightings(n);
    std::vector<double> uncovered(n, 0.0);
    tbb::parallel_for(size_t(0), runStarts.size() - 1, [&](size_t run) {
      const size_t k0 = runStarts[run], k1 = runStarts[run + 1];
      std::vector<EnvRotation> rotations;
      for (size_t k = k0; k < k1; ++k) rotations.push_back(frames[mine[first + k]].rotation);
      std::vector<double> shares;
      std::vector<LatticeLighting> made =
          domain.lightings(latticeMap(*frames[mine[first + k0]].input, exactSources), rotations,
                           a.rotationMode, &shares);
      for (size_t k = k0; k < k1; ++k)
        lightings[k] = std::move(made[k - k0]), uncovered[k] = shares[k - k0];
    });
    for (size_t k = 0; k < n; ++k) {
      run.uncovered.note(uncovered[k]);
      if (writing) writing->noteLighting(mine[first + k], lightings[k]);
    }
    return lightings;
  };
  const ImageComposer composer(source.header);
  // A frame's sources, turned with it, lit exactly onto its pixels.
  const auto addSources = [&](const BatchFrame& f, float* pixels) {
    if (!exactSources || f.input->split.sources.empty()) return;
    const Stopwatch watch;
    const long long raysBefore = source.lampShadowRays();  // frames light one at a time
    const std::vector<float> rows = source.relightSources(
        turnedSources(f.input->split.sources, f.rotation), a.lamps.sphereRays);
    composer.addRows(rows.data(), pixels, channels);
    stages.sources += watch.seconds();
    run.lampPixels += source.header.rows();
    run.sourceShadowRays += source.lampShadowRays() - raysBefore;
    run.sourcePixels +=
        source.header.rows() * static_cast<long long>(f.input->split.sources.size());
  };
  relightInGroups(
      mine.size(), lightingsOf,
      [&](size_t g, const std::vector<LatticeLighting>& lightings) {
        const auto backgroundOf = [&](size_t k, float* pixels) {
          const BatchFrame& f = frames[mine[g + k]];
          composer.background(a.background, *f.input->env, rotationMatrix(f.rotation), pixels);
        };
        relightGroupImages(
            source, composer, buffers, lightings, channels, backgroundOf, a.timingRepeats,
            msPerFrame, stages, [&](size_t k, std::vector<float>& pixels, double ms) {
              const std::vector<float>& local = localRows.of(frames[mine[g + k]].lights);
              if (!local.empty()) composer.addRows(local.data(), pixels.data(), channels);
              addSources(frames[mine[g + k]], pixels.data());
              if (rank == 0)
                ownMs = ms;
              else
                pixels.push_back(static_cast<float>(ms));
              gather.put(static_cast<long long>(mine[g + k]), pixels);
            });
      },
      &stages.lighting);
  gather.finish();
  run.lampShadowRays += source.lampShadowRays() - raysBefore;
  run.lampPixels += localRows.relit() * source.header.rows();
  if (!writing) return frames.size();
  writing->finish();
  stages.writing += writing->writingSeconds();
  stages.waitingForWriting += writing->waitingSeconds();
  run.framesWithNegatives += writing->framesWithNegatives();
  run.negatives.add(writing->negatives());
  for (auto& output : writing->takeOutputs()) run.outputs.push_back(std::move(output));
  for (const auto& path : writing->labelPaths()) run.labels.push_back(path);
  return frames.size();
}

}  // namespace acpca
