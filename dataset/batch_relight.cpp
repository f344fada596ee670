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
#include "dataset/file_hash.h"
#include "dataset/frame_files.h"
#include "dataset/frame_labels.h"
#include "dataset/map_source_listing.h"
#include "imageio/image_output.h"
#include "lighting/domain_lighting.h"
#include "lighting/envmap_export.h"
#include "lighting/lighting.h"
#include "lighting/sh_lighting.h"
#include "lighting/spec_parsing.h"
#include "model/model.h"
#include "model/model_file.h"
#include "relight/dense_relight.h"
#include "relight/image_composer.h"
#include "relight/model_relighter.h"
#include "relight/relight_source.h"

namespace acpca {

namespace {

namespace fs = std::filesystem;

/// One environment argument after expanding directories.
struct EnvInput {
  std::string spec;
  std::unique_ptr<Environment> env;
  std::string error;       // non-empty: could not be loaded
  SplitEnvironment split;  ///< its sources split off (--sun); none when off or none found
};

/// What a frame's lattice lighting integrates: the map less its sources
/// where they are lit exactly, else the whole map.
const Environment& latticeMap(const EnvInput& in, bool exactSources) {
  return exactSources && in.split.rest ? *in.split.rest : *in.env;
}

/// One frame of the batch: a lighting under a rotation, and its local lights.
struct Frame {
  const EnvInput* input;
  EnvRotation rotation;
  size_t lights;          ///< which of the batch's light sets (the line of its light path)
  double exposure;        ///< stops: the batch's, plus a sampled draw's offset
  long long sample = -1;  ///< the draw it relights (sampled lighting), or -1
};

/// The batch's frames, light set by light set (so each set's lights are
/// relit once per rank): every map x rotation, or the sampled draws.
std::vector<Frame> batchFrames(const BatchRelightOptions& a, const std::vector<EnvInput>& inputs,
                               size_t lightSets) {
  std::vector<Frame> frames;
  std::vector<LightingDraw> draws;
  if (a.sampling.count > 0) draws = drawLightings(a.sampling, inputs.size());
  for (size_t set = 0; set < lightSets; ++set) {
    for (size_t k = 0; k < draws.size(); ++k)
      frames.push_back({&inputs[draws[k].map], draws[k].rotation, set,
                        a.exposure + draws[k].exposureOffset, static_cast<long long>(k)});
    if (!draws.empty()) continue;
    for (const auto& in : inputs)
      if (in.env)
        for (const auto& r : a.rotations) frames.push_back({&in, r, set, a.exposure});
  }
  return frames;
}

/// The batch's sets of local lights: every combination of the --light
/// lights' sweeps (one set when none sweeps, which may hold no light), each
/// added to every line of the light path if there is one (path line major).
std::vector<std::vector<LocalLight>> lightSets(const BatchRelightOptions& a) {
  std::vector<std::vector<LocalLight>> swept{{}};
  for (const std::string& flag : a.lights) {
    std::vector<LocalLight> choices;
    for (const std::string& spec : expandLightSweep(flag)) choices.push_back(parseLocalLight(spec));
    std::vector<std::vector<LocalLight>> longer;
    for (const auto& set : swept)
      for (const LocalLight& light : choices) {
        longer.push_back(set);
        longer.back().push_back(light);
      }
    if (longer.size() > static_cast<size_t>(kMaxLightSweepSpecs))
      throw ParameterError("light", flag,
                           concat("makes the sweeps more than ", kMaxLightSweepSpecs, " frames"));
    swept = std::move(longer);
  }
  if (a.lightPath.empty()) return swept;
  std::vector<std::vector<LocalLight>> sets;
  for (const auto& line : readLightPath(a.lightPath))
    for (const auto& sweep : swept) {
      sets.push_back(line);
      sets.back().insert(sets.back().end(), sweep.begin(), sweep.end());
    }
  return sets;
}

/// The lights of a set as canonical specs.
std::vector<std::string> canonicalSpecs(const std::vector<LocalLight>& lights) {
  std::vector<std::string> specs;
  for (const LocalLight& light : lights) specs.push_back(light.canonicalSpec());
  return specs;
}

/// Texts joined by ';', as manifest.csv lists a frame's lights and files.
std::string joinedBySemicolons(const std::vector<std::string>& texts) {
  std::string joined;
  for (const std::string& t : texts) joined += (joined.empty() ? "" : ";") + t;
  return joined;
}

/// The rows of a frame's local lights, relit when first asked for; frames
/// come set by set, so earlier sets are dropped.
class LocalLightRows {
 public:
  LocalLightRows(const RelightSource& source, const std::vector<std::vector<LocalLight>>& sets,
                 double anchorSpread, const LampSettings& lamps, double& seconds)
      : source_(source),
        sets_(sets),
        anchorSpread_(anchorSpread),
        lamps_(lamps),
        seconds_(seconds) {}
  /// Empty when the set has no lights.
  const std::vector<float>& of(size_t set) {
    if (set != current_) {
      const Stopwatch watch;
      rows_ = sets_[set].empty() ? std::vector<float>()
                                 : source_.relightLocal(sets_[set], anchorSpread_, lamps_);
      relit_ += !sets_[set].empty();
      current_ = set;
      seconds_ += watch.seconds();
    }
    return rows_;
  }
  /// How many light sets this relit (this rank's).
  long long relit() const { return relit_; }

 private:
  const RelightSource& source_;
  const std::vector<std::vector<LocalLight>>& sets_;
  double anchorSpread_;
  LampSettings lamps_;
  double& seconds_;
  size_t current_ = static_cast<size_t>(-1);
  std::vector<float> rows_;
  long long relit_ = 0;
};

/// Refuses a batch whose frames, uncompressed in every format (an upper
/// bound), would not fit the disk.
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

/// A lighting as loaded on some thread: the map, or what stopped it, and
/// the warnings it raised, held for their turn.
struct LoadedLighting {
  std::unique_ptr<Environment> env;
  SplitEnvironment split;
  std::exception_ptr error;
  bool userError = false;  ///< the input's fault (a batch skips it)
  std::vector<std::string> warnings;
};

/// Every lighting of the batch read at once, each on its own task (decoding
/// and checking a 2048x1024 map takes tens of milliseconds of one core).
/// Each task is isolated, so its held warnings are its own.
std::vector<LoadedLighting> loadLightings(const std::vector<std::string>& specs,
                                          const std::optional<SourceFinding>& sources) {
  std::vector<LoadedLighting> loaded(specs.size());
  tbb::parallel_for(size_t(0), specs.size(), [&](size_t k) {
    tbb::this_task_arena::isolate([&] {
      LoadedLighting& l = loaded[k];
      HeldWarnings held;
      try {
        l.env = loadEnvironment(specs[k]);
        if (sources) l.split = l.env->splitSources(*sources);
      } catch (const UserError&) {
        l.error = std::current_exception(), l.userError = true;
      } catch (...) {
        l.error = std::current_exception();
      }
      l.warnings = held.take();
    });
  });
  return loaded;
}

/// The lightings loaded, their warnings and errors in the order given, as
/// if read one after another: in a batch, one that cannot be read is skipped
/// with a warning (and reported), otherwise its error stops the run.
std::vector<EnvInput> takeInputs(const std::vector<std::string>& specs,
                                 std::vector<LoadedLighting> loaded, bool batch,
                                 const std::function<void(const std::string&)>& warnOf) {
  std::vector<EnvInput> inputs;
  for (size_t k = 0; k < specs.size(); ++k) {
    LoadedLighting& l = loaded[k];
    for (const std::string& w : l.warnings) warn(w);
    EnvInput in{specs[k], std::move(l.env), "", std::move(l.split)};
    if (l.error) {
      if (!batch || !l.userError) std::rethrow_exception(l.error);
      try {
        std::rethrow_exception(l.error);
      } catch (const UserError& e) {
        in.error = e.what();
      }
      if (warnOf) warnOf(concat("skipping: ", in.error));
    }
    inputs.push_back(std::move(in));
  }
  return inputs;
}

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

/// Frames encoded, written or waiting for their turn to commit at once: the
/// memory a batch holds beyond the group it relights.
constexpr size_t kFramesInFlight = 8;

/// Frames' pixel buffers, handed back by the writing threads once a frame is
/// encoded and taken again for the next: a fresh 1024x1024 frame is 12 MB of
/// pages the kernel zeroes and the vector zeroes again (a third of the
/// background stage). Nothing is read before the background writes it.
class FrameBuffers {
 public:
  std::vector<float> take(size_t values) {
    std::vector<float> buffer;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (!free_.empty()) buffer = std::move(free_.back()), free_.pop_back();
    }
    buffer.resize(values);  // the same size as before: nothing to fill
    return buffer;
  }
  void giveBack(std::vector<float>&& buffer) {
    const std::lock_guard<std::mutex> lock(mutex_);
    // As many as can be in flight at once, and the group relighting.
    if (free_.size() < 2 * kFramesInFlight) free_.push_back(std::move(buffer));
  }

 private:
  std::mutex mutex_;
  std::vector<std::vector<float>> free_;
};

/// Writing threads beside the relighter's, as many as it may use: the system shares the
/// cores, and writing fills what the relighter leaves (138-141 frames/s at
/// 256x256 on 2 cores, against 124 with one writing thread).
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

/// One group relit into composed images (`backgroundOf(k, pixels)` puts frame
/// k's background there first), each handed to `done` with its relight time
/// (which may move the pixels away). A model shades its frames straight into
/// their images after one projection of the group; a transport's rows (and
/// timing mode's) are added onto the background.
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
    csv.emplace((fs::path(a.out) / "manifest.csv").string(), columns);
    jsonLines.emplace((fs::path(a.out) / "manifest.jsonl").string());
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
  /// "vNN_" before frame names, "_vNN" after label names (several views only).
  std::string label() const { return concat("v", std::setw(2), std::setfill('0'), index); }
};

/// A batch frame's file name without its extension (docs/datasets.md, "Frame
/// names"): its index in the batch, then its map and rotation (or its draw),
/// along a light path or sweep its light set, and its view.
std::string frameStem(const BatchRelightOptions& a, const Frame& f, const BatchView& view,
                      size_t i) {
  std::string name = f.input->spec.empty() ? "lights" : f.input->env->name();
  name += "_" + f.rotation.label();
  if (f.sample >= 0) name = concat("sample_", std::setw(5), std::setfill('0'), f.sample);
  if (a.movesLights()) name += concat("_l", std::setw(4), std::setfill('0'), f.lights);
  if (view.count > 1) name = view.label() + "_" + name;
  return indexedFrameStem(static_cast<long long>(view.firstFrame + i), view.indexDigits, name);
}

/// A frame's lighting in words, for errors: its spec, rotation and lights.
std::string lightingInWords(const Frame& f, const std::vector<std::string>& lights) {
  std::string words =
      concat(f.input->spec.empty() ? "no environment" : f.input->spec, " at yaw ", f.rotation.yaw,
             ", pitch ", f.rotation.pitch, ", roll ", f.rotation.roll);
  for (const std::string& light : lights) words += " with " + light;
  return words;
}

/// The paths of a batch's files, as the manifests list them: relative to the
/// dataset's directory (docs/formats.md, "Batch manifest").
std::vector<std::string> inDataset(const std::vector<std::string>& paths) {
  std::vector<std::string> names;
  for (const std::string& path : paths) names.push_back(fs::path(path).filename().string());
  return names;
}

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
  FrameWriting(const BatchRelightOptions& a, const std::vector<Frame>& frames,
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
    if (manifests_) sh_.emplace(domain);
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
  void submit(size_t i, Image&& image, double ms) {
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
                               const NegativeClamp& negatives) {
    const Frame& f = frames_[i];
    const fs::path out(a_.out);
    const bool write = !(shards_ && shards_->packed(static_cast<long long>(view_.firstFrame + i)));
    auto files = std::make_shared<std::vector<std::unique_ptr<AtomicOutput>>>();
    FrameFiles written;
    if (sh_ || a_.lightingImages) {
      const LatticeLighting lighting = lightingOf(i);
      if (sh_) written.sh9 = sh9Json(sh_->project(lighting), sourcesOf(f));
      if (a_.lightingImages) {
        const std::string path = fileStem(i, "lighting") + ".exr";
        // The radiance the lattice (or a light set's cells) holds, before
        // exposure; 8R x 4R sees every texel.
        const int r = domain_.mapLattice().resolution();
        if (write) {
          files->push_back(std::make_unique<AtomicOutput>(path));
          encodeImage(latticeRadianceToLatLong(domain_.mapLighting(lighting), domain_.mapLattice(),
                                               8 * r, 4 * r),
                      files->back()->tempPath(), path, ImageFormat::Exr, 0, encoding_);
        }
        written.lighting.push_back(path);
      }
    }
    for (ImageFormat format : formats_) {
      std::string path = a_.out;
      if (batch_)
        path = fileStem(i, "") + imageExtension(format);
      else if (formats_.size() > 1)
        path = (out.parent_path() / (out.stem().string() + imageExtension(format))).string();
      if (write) {
        files->push_back(std::make_unique<AtomicOutput>(path));
        encodeImage(image, files->back()->tempPath(), path, format, f.exposure, encoding_);
      }
      written.frames.push_back(path);
    }
    if (labels_.shading()) {
      const std::string stem = fileStem(i, "shading");
      written.shading =
          write ? labels_.encodeShading(image, *f.input->env, rotationMatrix(f.rotation),
                                        f.exposure, stem, *files)
                : labels_.shadingPaths(stem);
    }
    return [this, i, ms, negatives, files, written = std::move(written)] {
      const Stopwatch busy;
      for (auto& file : *files) file->commit();
      const Frame& f = frames_[i];
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

  /// Frame i's row of manifest.csv and line of manifest.jsonl, appended once
  /// its files are in place; in a sharded batch its files and line go to
  /// its shard.
  void addToManifests(size_t i, const FrameFiles& written, const std::string& lights) {
    const Frame& f = frames_[i];
    const long long frame = static_cast<long long>(view_.firstFrame + i);
    std::vector<Table::Cell> row{view_.input,     f.input->spec,
                                 f.rotation.yaw,  f.rotation.pitch,
                                 f.rotation.roll, f.exposure,
                                 lights,          joinedBySemicolons(inDataset(written.frames))};
    if (view_.count > 1) row.insert(row.begin(), static_cast<long long>(view_.index));
    manifests_->csv->append(std::move(row));
    nlohmann::json line = {{"frame", frame},
                           {"input", view_.input},
                           {"env", f.input->spec},
                           {"env_sha256", hashOf(f.input)},
                           {"yaw", f.rotation.yaw},
                           {"pitch", f.rotation.pitch},
                           {"roll", f.rotation.roll},
                           {"exposure", f.exposure},
                           {"lights", lightSpecs_[f.lights]},
                           {"sh9", written.sh9},
                           {"sources", sourcesJson(sourcesOf(f))},
                           {"outputs", inDataset(written.frames)}};
    if (view_.count > 1) line["view"] = view_.index;
    if (f.sample >= 0) line["sample"] = f.sample;
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

  /// Where frame i's file of `part` ("", "shading", "lighting") goes, less
  /// its extension: in a batch's directory under its stem (STEM_shading), in
  /// a sharded batch staged under its key (KEY.shading), else beside the
  /// one image (OUT_shading).
  std::string fileStem(size_t i, const std::string& part) const {
    if (shards_)
      return shards_->stagedPath(static_cast<long long>(view_.firstFrame + i),
                                 part.empty() ? "" : "." + part);
    if (!batch_) return stemBeside(part);
    return (fs::path(a_.out) / frameStem(a_, frames_[i], view_, i)).string() +
           (part.empty() ? "" : "_" + part);
  }

  void addWriting(double seconds) {
    for (double seen = writing_; !writing_.compare_exchange_weak(seen, seen + seconds);)
      ;
  }

  const BatchRelightOptions& a_;
  const std::vector<Frame>& frames_;
  const std::vector<ImageFormat>& formats_;
  const bool batch_;
  const ImageEncoding encoding_;
  /// A lighting file's SHA-256; null for a built-in lighting.
  nlohmann::json hashOf(const EnvInput* input) const {
    const auto at = manifests_->hashes.find(input);
    return at == manifests_->hashes.end() ? nlohmann::json(nullptr) : nlohmann::json(at->second);
  }

  /// Frame i's lattice lighting: as noted, or (a frame another rank relit)
  /// made again here, on a writing thread; the same numbers either way.
  LatticeLighting lightingOf(size_t i) {
    {
      const std::lock_guard<std::mutex> lock(knownMutex_);
      if (const auto at = known_.find(i); at != known_.end()) {
        LatticeLighting lighting = std::move(at->second);
        known_.erase(at);
        return lighting;
      }
    }
    const Frame& f = frames_[i];
    return domain_(latticeMap(*f.input, view_.exactSources), f.rotation, a_.rotationMode);
  }

  /// Frame f's sources lit exactly, turned with it (none where the lattice
  /// holds them).
  std::vector<MapSource> sourcesOf(const Frame& f) const {
    if (!view_.exactSources) return {};
    return turnedSources(f.input->split.sources, f.rotation);
  }

  /// Where a label file of the view goes: the batch's directory, or beside
  /// the one image (OUT_name).
  std::string stemBeside(const std::string& name) const {
    const fs::path out(a_.out);
    return batch_ ? (out / name).string()
                  : (out.parent_path() / (out.stem().string() + "_" + name)).string();
  }

  const std::vector<std::vector<std::string>>& lightSpecs_;  ///< per light set: its lights
  const DomainLighting& domain_;
  const BatchView view_;
  BatchManifests* const manifests_;
  BatchShards* const shards_;      ///< a sharded batch's (null otherwise)
  std::optional<ShProjector> sh_;  ///< the lighting labels (sh9), batches only
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

std::vector<ImageFormat> imageFormatsFor(const std::string& format, const std::string& out,
                                         bool batch) {
  ++specParseCounts().formats;
  if (!format.empty()) return parseImageFormatList(format == "both" ? "exr,png" : format);
  if (batch) return {ImageFormat::Exr};
  const ImageFormatRow* row = imageFormatOfExtension(fs::path(out).extension().string());
  if (!row) {
    std::string extensions;
    for (const ImageFormatRow& r : kImageFormats)
      if (extensions.find(r.extension) == std::string::npos)
        extensions += (extensions.empty() ? "" : "/") + std::string(r.extension);
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

namespace {

/// What the views of a batch share while they relight one after another.
/// How much of the frames' lighting fell on directions a captured light
/// set has no cell for (the image cannot show it).
struct UncoveredLighting {
  /// Shares of a frame's energy below this are not worth a word.
  static constexpr double kNegligible = 1e-3;
  long long frames = 0;
  double largest = 0;
  void note(double share) {
    if (share <= kNegligible) return;
    ++frames;
    largest = std::max(largest, share);
  }
  void report() const {
    if (frames > 0)
      warn(concat(frames,
                  " frame(s) are lit partly from directions no captured light stands for "
                  "(up to ",
                  100 * largest, "% of a frame's lighting): their images leave that light out"));
  }
};

struct BatchRun {
  BatchRun(const BatchRelightOptions& options, const BatchPlan& plan)
      : a(options), batch(plan.batch), formats(plan.formats), sets(plan.lightSets) {}
  const BatchRelightOptions& a;
  const bool batch;
  const std::vector<ImageFormat> formats;
  const std::vector<std::vector<LocalLight>> sets;
  std::vector<std::vector<std::string>> setSpecs;
  std::vector<EnvInput> inputs;
  std::vector<Frame> viewFrames;            ///< each view's frames (the same for every view)
  std::optional<BatchManifests> manifests;  ///< rank 0 of a batch
  BatchStages stages;
  std::vector<double> msPerFrame;
  nlohmann::json outputs = nlohmann::json::array();
  nlohmann::json labels = nlohmann::json::array();
  size_t frames = 0;            ///< frames of the views done
  std::vector<Camera> cameras;  ///< each view's (none for captured light sets)
  UncoveredLighting uncovered;
  long long framesWithNegatives = 0;  ///< rank 0: frames written with values below zero
  NegativeClamp negatives;
  /// This rank's lamps: shadow rays traced, and covered pixels relit (rows x light sets).
  long long lampShadowRays = 0, lampPixels = 0;
};

/// Refuses, before any frame, what a captured light set cannot do: show the
/// environment behind it (it has no camera) or take local lights (no
/// positions); the fast rotation resamples a cube lattice.
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

/// Refuses, before any work, a batch that would write one file twice. Frame
/// names start with their index, so only a broken naming rule gets here.
void requireDistinctFrameFiles(const BatchRun& run, size_t views, int indexDigits) {
  const BatchRelightOptions& a = run.a;
  std::vector<std::string> suffixes;
  for (ImageFormat format : run.formats) suffixes.push_back(imageExtension(format));
  if (a.lightingImages) suffixes.push_back("_lighting.exr");
  if (std::find(a.aovs.begin(), a.aovs.end(), Aov::Shading) != a.aovs.end()) {
    if (a.labelFormat != LabelFormat::Npy) suffixes.push_back("_shading.exr");
    if (a.labelFormat != LabelFormat::Exr) suffixes.push_back("_shading.npy");
  }
  const std::vector<Frame>& frames = run.viewFrames;
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
        const Frame& f = frames[k % frames.size()];
        return lightingInWords(f, run.setSpecs[f.lights]) +
               (views > 1 ? concat(" in view ", k / frames.size()) : std::string());
      });
}

/// Whether the view's file lights the maps' sources exactly: --sun on, exact
/// lamps asked for, and a file that holds its surfaces and direct light
/// apart. Where it cannot, one warning names the file and why, and the
/// sources stay in the maps, on the lattice.
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

/// One view's frames relit and (rank 0) written; returns its frame count.
size_t relightView(BatchRun& run, const RelightSource& source, BatchView view) {
  const BatchRelightOptions& a = run.a;
  BatchStages& stages = run.stages;
  std::vector<double>& msPerFrame = run.msPerFrame;
  const DomainLighting domain(source.header);
  LocalLightRows localRows(source, run.sets, a.anchorSpread, a.lamps, stages.localLights);
  const bool exactSources = view.exactSources = sourcesLitExactly(run, source, view.input);
  const long long raysBefore = source.lampShadowRays();
  // Frames in groups: each group streams T once; memory stays flat for any count.
  const std::vector<Frame>& frames = run.viewFrames;
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
  const auto addSources = [&](const Frame& f, float* pixels) {
    if (!exactSources || f.input->split.sources.empty()) return;
    const Stopwatch watch;
    const std::vector<float> rows = source.relightSources(
        turnedSources(f.input->split.sources, f.rotation), a.lamps.sphereRays);
    composer.addRows(rows.data(), pixels, channels);
    stages.sources += watch.seconds();
    run.lampPixels += source.header.rows();
  };
  relightInGroups(
      mine.size(), lightingsOf,
      [&](size_t g, const std::vector<LatticeLighting>& lightings) {
        const auto backgroundOf = [&](size_t k, float* pixels) {
          const Frame& f = frames[mine[g + k]];
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
