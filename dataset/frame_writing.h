#pragma once
// Rank 0's writing of a batch's frames: each encoded and written on threads of
// its own while the next relight, committed in frame order with its manifest
// rows, labels, lighting images and shards; frames' names and the manifests
// the views share.
#include <atomic>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/atomic_file.h"
#include "core/file_hash.h"
#include "core/ordered_writer.h"
#include "core/stopwatch.h"
#include "dataset/batch_frames.h"
#include "dataset/batch_manifest.h"
#include "dataset/batch_shards.h"
#include "dataset/frame_labels.h"
#include "dataset/group_relight.h"
#include "lighting/domain_lighting.h"
#include "lighting/map_source_listing.h"
#include "lighting/sh_lighting.h"

namespace acpca {

/// Writing threads beside the relighter's, as many as it may use: the system shares the
/// cores, and writing fills what the relighter leaves (138-141 frames/s at
/// 256x256 on 2 cores, against 124 with one writing thread).
int writingThreads();

/// How a batch's frames are encoded: the options', and the codec a batch or
/// one image takes by default.
ImageEncoding encodingFor(const BatchRelightOptions& a, bool batch);

/// What a batch's views share on rank 0: the directory's manifests and each
/// lighting file's SHA-256 (built-in lightings are named by their spec).
struct BatchManifests {
  /// frames: in the whole batch; keyDigits: of a frame's index in names.
  BatchManifests(const BatchRelightOptions& a, const std::vector<EnvInput>& inputs, size_t views,
                 long long frames, int keyDigits) {
    if (a.shardSize > 0) shards.emplace(a.out, a.shardSize, frames, keyDigits);
    std::vector<std::string> columns{"input", "env",      "yaw",    "pitch",
                                     "roll",  "exposure", "lights", "output"};
    if (views > 1) columns.insert(columns.begin(), "view");
    csv.emplace((std::filesystem::path(a.out) / "manifest.csv").string(), columns);
    jsonLines.emplace((std::filesystem::path(a.out) / "manifest.jsonl").string());
    for (const EnvInput& in : inputs)
      if (in.env && !in.spec.empty() && !isAnalyticEnvironment(in.spec))
        hashes[&in] = sha256OfFile(in.spec);
  }
  std::optional<BatchManifest> csv;
  std::optional<JsonLinesManifest> jsonLines;
  std::unordered_map<const EnvInput*, std::string> hashes;
  std::optional<BatchShards> shards;  ///< --shard-size
};

/// One view of a batch: its input, its place among the views, and the
/// batch-wide number of its first frame.
struct BatchView {
  size_t index = 0, count = 1;
  std::string input;
  size_t firstFrame = 0;
  int indexDigits = 5;        ///< of a frame's index in its file name (frameIndexDigits)
  bool exactSources = false;  ///< the maps' sources lit exactly, not through the lattice
  std::string method{};       ///< the model's method, or "dense" (frames' headers)
  /// The model's cost metric per pixel at its rank limit; none for a transport.
  std::optional<double> costPerPixel{};
  /// "vNN_" before frame names, "_vNN" after label names (several views only).
  std::string label() const { return concat("v", std::setw(2), std::setfill('0'), index); }
};

/// A batch frame's file name without its extension (docs/datasets.md, "Frame
/// names"): its index in the batch, then its map and rotation (or its draw),
/// along a light path or sweep its light set, and its view.
std::string frameStem(const BatchRelightOptions& a, const BatchFrame& f, const BatchView& view,
                      size_t i);

/// A frame's lighting in words, for errors: its spec, rotation and lights.
std::string lightingInWords(const BatchFrame& f, const std::vector<std::string>& lights);

/// The paths of a batch's files, as the manifests list them: relative to the
/// dataset's directory (docs/formats.md, "Batch manifest").
std::vector<std::string> inDataset(const std::vector<std::string>& paths);

/// What a frame's commit puts in place and lists: its files by kind (final
/// paths) and its lighting's sh9.
struct FrameFiles {
  std::vector<std::string> frames, shading, lighting;
  nlohmann::json sh9 = nlohmann::json::array();
};

/// Rank 0's writing: every frame encoded and written on writing threads of
/// its own while the next frames relight, each committed in frame order (its
/// files renamed into place, then its manifest row, so a batch killed midway
/// leaves a manifest listing the frames in place, all but at most the one
/// whose commit it interrupted). No times in the
/// manifest: equal runs write equal files (frame times go to the JSON report).
class FrameWriting {
 public:
  /// lightSpecs: per light set, its lights as canonical specs.
  /// header: the view's (its labels are written now, before any frame).
  /// manifests: the batch's (null for one image).
  FrameWriting(const BatchRelightOptions& a, const std::vector<BatchFrame>& frames,
               const std::vector<ImageFormat>& formats, bool batch,
               const std::vector<std::vector<std::string>>& lightSpecs,
               const DomainLighting& domain, const TransportHeader& header, BatchView view,
               BatchManifests* manifests, FrameBuffers& buffers)
      : a_(a),
        frames_(frames),
        formats_(formats),
        batch_(batch),
        encoding_(encodingFor(a, batch)),
        lightSpecs_(lightSpecs),
        domain_(domain),
        view_(std::move(view)),
        manifests_(manifests),
        shards_(manifests && manifests->shards ? &*manifests->shards : nullptr),
        labels_(header, a.aovs, a.labelFormat, a.background, encoding_, a.keepNegative),
        buffers_(buffers),
        writer_(writingThreads(), kFramesInFlight) {
    labelPaths_ =
        labels_.writeView(stemBeside(view_.count > 1 ? "labels_" + view_.label() : "labels"));
    sh_.emplace(domain);
    hashInputs(header);
  }

  /// Frame i's lattice lighting, where this rank made it: kept for its
  /// labels, instead of made again on a writing thread.
  void noteLighting(size_t i, const LatticeLighting& lighting) {
    if (!sh_ && !a_.lightingImages) return;
    const std::lock_guard<std::mutex> lock(knownMutex_);
    known_[i] = lighting;
  }

  /// Queues frame i (in frame order); blocks while kFramesInFlight are in flight.
  /// The frame is clamped at zero first, unless the batch keeps negative values.
  void submit(size_t i, Image&& image, double ms);
  void finish() {
    const Stopwatch waiting;
    writer_.finish();
    waiting_ += waiting.seconds();
  }
  /// The frames' entries of the JSON report, moved out (a batch of 10,000
  /// frames holds megabytes of them: never copied).
  nlohmann::json takeOutputs() { return std::move(outputs_); }
  const std::vector<std::string>& labelPaths() const { return labelPaths_; }
  double writingSeconds() const { return writing_.load(); }
  /// The frames that held negative values, and those values together.
  long long framesWithNegatives() const { return framesWithNegatives_; }
  const NegativeClamp& negatives() const { return negatives_; }
  double waitingSeconds() const { return waiting_; }

 private:
  /// Frame i's files under temporary names; returns what puts them in place.
  /// A frame whose shard was packed before the batch began is written again
  /// only in the manifests.
  OrderedWriter::Commit encode(size_t i, const Image& image, double ms,
                               const NegativeClamp& negatives);

  /// What frame i's files and its manifest line both say of its lighting:
  /// env, env_sha256, yaw, pitch, roll, exposure, lights, sh9, sources, and
  /// where there are several, sample and view.
  nlohmann::json lightingFields(size_t i, const nlohmann::json& sh9) const;
  /// Frame i's header (imageio/frame_metadata.h): its lighting fields, what
  /// it was relit from, the tool, and the view's camera.
  std::shared_ptr<const FrameMetadata> frameMetadata(size_t i, const nlohmann::json& sh9) const;
  /// The SHA-256 of the view's model or transport and of each map file (a
  /// batch's manifests hold the maps' already), and the view's camera.
  void hashInputs(const TransportHeader& header);

  /// Frame i's row of manifest.csv and line of manifest.jsonl, appended once
  /// its files are in place; in a sharded batch its files and line go to
  /// its shard.
  void addToManifests(size_t i, const FrameFiles& written, const std::string& lights);

  /// Where frame i's file of `part` ("", "shading", "lighting") goes, less
  /// its extension: in a batch's directory under its stem (STEM_shading), in
  /// a sharded batch staged under its key (KEY.shading), else beside the
  /// one image (OUT_shading).
  std::string fileStem(size_t i, const std::string& part) const;

  void addWriting(double seconds) {
    for (double seen = writing_; !writing_.compare_exchange_weak(seen, seen + seconds);)
      ;
  }

  const BatchRelightOptions& a_;
  const std::vector<BatchFrame>& frames_;
  const std::vector<ImageFormat>& formats_;
  const bool batch_;
  const ImageEncoding encoding_;
  /// A lighting file's SHA-256; null for a built-in lighting.
  nlohmann::json hashOf(const EnvInput* input) const {
    const auto& hashes = manifests_ ? manifests_->hashes : ownHashes_;
    const auto at = hashes.find(input);
    return at == hashes.end() ? nlohmann::json(nullptr) : nlohmann::json(at->second);
  }
  std::unordered_map<const EnvInput*, std::string> ownHashes_;  ///< one image's map
  std::string sourceSha256_;                                    ///< the view's input file
  std::optional<Camera> camera_;                                ///< none for a light set

  /// Frame i's lattice lighting: as noted, or (a frame another rank relit)
  /// made again here, on a writing thread; the same numbers either way.
  LatticeLighting lightingOf(size_t i);

  /// Frame f's sources lit exactly, turned with it (none where the lattice
  /// holds them).
  std::vector<MapSource> sourcesOf(const BatchFrame& f) const {
    if (!view_.exactSources) return {};
    return turnedSources(f.input->split.sources, f.rotation);
  }

  /// Where a label file of the view goes: the batch's directory, or beside
  /// the one image (OUT_name).
  std::string stemBeside(const std::string& name) const {
    const std::filesystem::path out(a_.out);
    return batch_ ? (out / name).string()
                  : (out.parent_path() / (out.stem().string() + "_" + name)).string();
  }

  const std::vector<std::vector<std::string>>& lightSpecs_;  ///< per light set: its lights
  const DomainLighting& domain_;
  const BatchView view_;
  BatchManifests* const manifests_;
  BatchShards* const shards_;      ///< a sharded batch's (null otherwise)
  std::optional<ShProjector> sh_;  ///< the lighting's sh9, for headers and manifests
  const FrameLabels labels_;
  std::vector<std::string> labelPaths_;  ///< the view's labels
  std::mutex knownMutex_;
  std::unordered_map<size_t, LatticeLighting> known_;  ///< noted, not yet written
  nlohmann::json outputs_ = nlohmann::json::array();
  long long framesWithNegatives_ = 0;  ///< counted as frames commit, one at a time
  NegativeClamp negatives_;
  FrameBuffers& buffers_;
  std::atomic<double> writing_{0};
  double waiting_ = 0;
  OrderedWriter writer_;  ///< last: its threads stop before what they use goes
};

}  // namespace acpca
