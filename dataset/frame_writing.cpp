#include "dataset/frame_writing.h"

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
#include "imageio/frame_metadata.h"
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

int writingThreads() {
  return std::max(1, tbb::this_task_arena::max_concurrency());
}

ImageEncoding encodingFor(const BatchRelightOptions& a, bool batch) {
  ImageEncoding e;
  e.exrFloat = a.exrFloat;
  e.exrCompression = a.exrCompression.value_or(batch ? kBatchExrCompression : ExrCompression::Zips);
  e.pngLevel = a.pngLevel;
  e.tone = a.tone;
  return e;
}

std::string frameStem(const BatchRelightOptions& a, const BatchFrame& f, const BatchView& view,
                      size_t i) {
  std::string name = f.input->spec.empty() ? "lights" : f.input->env->name();
  // Appended piece by piece: GCC 12 warns of "_" + string (-Wrestrict, a false alarm).
  name += '_';
  name += f.rotation.label();
  if (f.sample >= 0) name = concat("sample_", std::setw(5), std::setfill('0'), f.sample);
  if (a.movesLights()) name += concat("_l", std::setw(4), std::setfill('0'), f.lights);
  if (view.count > 1) name = view.label() + "_" + name;
  return indexedFrameStem(static_cast<long long>(view.firstFrame + i), view.indexDigits, name);
}

std::string lightingInWords(const BatchFrame& f, const std::vector<std::string>& lights) {
  std::string words =
      concat(f.input->spec.empty() ? "no environment" : f.input->spec, " at yaw ", f.rotation.yaw,
             ", pitch ", f.rotation.pitch, ", roll ", f.rotation.roll);
  for (const std::string& light : lights) words += " with " + light;
  return words;
}

std::vector<std::string> inDataset(const std::vector<std::string>& paths) {
  std::vector<std::string> names;
  for (const std::string& path : paths) names.push_back(fs::path(path).filename().string());
  return names;
}

void FrameWriting::submit(size_t i, Image&& image, double ms) {
  const Stopwatch waiting;
  writer_.submit([this, i, ms, image = std::move(image)]() mutable {
    const Stopwatch busy;
    const NegativeClamp negatives =
        clampNegative(image.pixels.data(), image.pixels.size(), image.channels, a_.keepNegative);
    OrderedWriter::Commit commit = encode(i, image, ms, negatives);
    buffers_.giveBack(std::move(image.pixels));
    addWriting(busy.seconds());
    return commit;
  });
  waiting_ += waiting.seconds();
}

void FrameWriting::hashInputs(const TransportHeader& header) {
  if (!header.isLightSet()) camera_ = header.camera;
  if (!view_.input.empty()) sourceSha256_ = sha256OfFile(view_.input);
  if (manifests_) return;
  for (const BatchFrame& f : frames_)
    if (f.input->env && !f.input->spec.empty() && !isAnalyticEnvironment(f.input->spec) &&
        !ownHashes_.count(f.input))
      ownHashes_[f.input] = sha256OfFile(f.input->spec);
}

nlohmann::json FrameWriting::lightingFields(size_t i, const nlohmann::json& sh9) const {
  const BatchFrame& f = frames_[i];
  nlohmann::json fields = {{"env", f.input->spec},
                           {"env_sha256", hashOf(f.input)},
                           {"yaw", f.rotation.yaw},
                           {"pitch", f.rotation.pitch},
                           {"roll", f.rotation.roll},
                           {"exposure", f.exposure},
                           {"lights", lightSpecs_[f.lights]},
                           {"sh9", sh9},
                           {"sources", sourcesJson(sourcesOf(f))}};
  if (view_.count > 1) fields["view"] = view_.index;
  if (f.sample >= 0) fields["sample"] = f.sample;
  return fields;
}

std::shared_ptr<const FrameMetadata> FrameWriting::frameMetadata(size_t i,
                                                                 const nlohmann::json& sh9) const {
  auto m = std::make_shared<FrameMetadata>();
  m->fields = lightingFields(i, sh9);
  m->fields["frame"] = static_cast<long long>(view_.firstFrame + i);
  if (frames_[i].sample >= 0) m->fields["seed"] = a_.sampling.seed;
  m->fields["source"] = std::filesystem::path(view_.input).filename().string();
  m->fields["source_sha256"] = sourceSha256_;
  m->fields["method"] = view_.method;
  if (view_.costPerPixel) m->fields["cost_per_pixel"] = *view_.costPerPixel;
  m->fields["version"] = ACPCA_VERSION;
  if (camera_) m->setCamera(camera_->worldToCamera(), camera_->worldToNdc());
  return m;
}

OrderedWriter::Commit FrameWriting::encode(size_t i, const Image& image, double ms,
                                           const NegativeClamp& negatives) {
  const BatchFrame& f = frames_[i];
  const fs::path out(a_.out);
  const bool write = !(shards_ && shards_->packed(static_cast<long long>(view_.firstFrame + i)));
  auto files = std::make_shared<std::vector<std::unique_ptr<AtomicOutput>>>();
  FrameFiles written;
  const LatticeLighting lighting = lightingOf(i);
  written.sh9 = sh9Json(sh_->project(lighting), sourcesOf(f));
  const std::shared_ptr<const FrameMetadata> metadata = frameMetadata(i, written.sh9);
  ImageEncoding encoding = encoding_;
  encoding.metadata = metadata.get();
  if (a_.lightingImages) {
    const std::string path = fileStem(i, "lighting") + ".exr";
    // The radiance the lattice (or a light set's cells) holds, before
    // exposure; 8R x 4R sees every texel. Its header is the frame's, less
    // the camera, which does not see it.
    const int r = domain_.mapLattice().resolution();
    if (write) {
      files->push_back(std::make_unique<AtomicOutput>(path));
      FrameMetadata unseen = *metadata;
      unseen.worldToCamera.reset(), unseen.worldToNdc.reset();
      ImageEncoding lightingEncoding = encoding;
      lightingEncoding.metadata = &unseen;
      encodeImage(latticeRadianceToLatLong(domain_.mapLighting(lighting), domain_.mapLattice(),
                                           8 * r, 4 * r),
                  files->back()->tempPath(), path, ImageFormat::Exr, 0, lightingEncoding);
    }
    written.lighting.push_back(path);
  }
  for (ImageFormat format : formats_) {
    std::string path = a_.out;
    if (batch_)
      path = fileStem(i, "") + imageExtension(format);
    else if (formats_.size() > 1)
      path = (out.parent_path() / (out.stem().string() + imageExtension(format))).string();
    if (write) {
      files->push_back(std::make_unique<AtomicOutput>(path));
      encodeImage(image, files->back()->tempPath(), path, format, f.exposure, encoding);
    }
    written.frames.push_back(path);
  }
  if (labels_.shading()) {
    const std::string stem = fileStem(i, "shading");
    written.shading = write
                          ? labels_.encodeShading(image, *f.input->env, rotationMatrix(f.rotation),
                                                  f.exposure, stem, *files, metadata.get())
                          : labels_.shadingPaths(stem);
  }
  return [this, i, ms, negatives, files, written = std::move(written)] {
    const Stopwatch busy;
    for (auto& file : *files) file->commit();
    const BatchFrame& f = frames_[i];
    const std::string lights = joinedBySemicolons(lightSpecs_[f.lights]);
    if (manifests_) addToManifests(i, written, lights);
    nlohmann::json output = {{"env", f.input->spec},
                             {"lights", lights},
                             {"yaw", f.rotation.yaw},
                             {"pitch", f.rotation.pitch},
                             {"roll", f.rotation.roll},
                             {"paths", written.frames},
                             {"ms", ms},
                             {"negative_values", negatives.values},
                             {"most_negative", negatives.mostNegative}};
    if (negatives.values > 0) ++framesWithNegatives_, negatives_.add(negatives);
    if (view_.count > 1) output["view"] = view_.index;
    if (labels_.shading()) output["shading"] = written.shading;
    outputs_.push_back(std::move(output));
    if (a_.progress)
      a_.progress(static_cast<long long>(i + 1), static_cast<long long>(frames_.size()));
    addWriting(busy.seconds());
  };
}

void FrameWriting::addToManifests(size_t i, const FrameFiles& written, const std::string& lights) {
  const BatchFrame& f = frames_[i];
  const long long frame = static_cast<long long>(view_.firstFrame + i);
  std::vector<Table::Cell> row{view_.input,     f.input->spec,
                               f.rotation.yaw,  f.rotation.pitch,
                               f.rotation.roll, f.exposure,
                               lights,          joinedBySemicolons(inDataset(written.frames))};
  if (view_.count > 1) row.insert(row.begin(), static_cast<long long>(view_.index));
  manifests_->csv->append(std::move(row));
  nlohmann::json line = lightingFields(i, written.sh9);
  line["frame"] = frame;
  line["input"] = view_.input;
  line["outputs"] = inDataset(written.frames);
  if (labels_.any()) {
    line["labels"] = inDataset(labelPaths_);
    line["shading"] = inDataset(written.shading);
  }
  if (a_.lightingImages) line["lighting"] = inDataset(written.lighting);
  if (shards_) line["shard"] = shards_->shardName(frame / a_.shardSize);
  manifests_->jsonLines->append(line);
  if (!shards_) return;
  std::vector<std::string> members = written.frames;
  members.insert(members.end(), written.shading.begin(), written.shading.end());
  members.insert(members.end(), written.lighting.begin(), written.lighting.end());
  shards_->committed(frame, members, labelPaths_, line);
}

std::string FrameWriting::fileStem(size_t i, const std::string& part) const {
  if (shards_)
    return shards_->stagedPath(static_cast<long long>(view_.firstFrame + i),
                               part.empty() ? "" : "." + part);
  if (!batch_) return stemBeside(part);
  return (fs::path(a_.out) / frameStem(a_, frames_[i], view_, i)).string() +
         (part.empty() ? "" : "_" + part);
}

LatticeLighting FrameWriting::lightingOf(size_t i) {
  {
    const std::lock_guard<std::mutex> lock(knownMutex_);
    if (const auto at = known_.find(i); at != known_.end()) {
      LatticeLighting lighting = std::move(at->second);
      known_.erase(at);
      return lighting;
    }
  }
  const BatchFrame& f = frames_[i];
  return domain_(latticeMap(*f.input, view_.exactSources), f.rotation, a_.rotationMode);
}

}  // namespace acpca
