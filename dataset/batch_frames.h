#pragma once
// A batch's lightings and frames: every map loaded at once (each on a task of
// its own), its sources split off; every map x rotation, or each sampled
// draw, as a frame; the sets of local lights and their rows, relit once a set.
#include <exception>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/stopwatch.h"
#include "dataset/batch_options.h"
#include "lighting/environment.h"
#include "lighting/map_sources.h"
#include "relight/relight_source.h"

namespace acpca {

/// One environment argument after expanding directories.
struct EnvInput {
  std::string spec;
  std::unique_ptr<Environment> env;
  std::string error;       // non-empty: could not be loaded
  SplitEnvironment split;  ///< its sources split off (--sun); none when off or none found
};

/// What a frame's lattice lighting integrates: the map less its sources
/// where they are lit exactly, else the whole map.
const Environment& latticeMap(const EnvInput& in, bool exactSources);

/// One frame of the batch: a lighting under a rotation, and its local lights.
struct BatchFrame {
  const EnvInput* input;
  EnvRotation rotation;
  size_t lights;          ///< which of the batch's light sets (the line of its light path)
  double exposure;        ///< stops: the batch's, plus a sampled draw's offset
  long long sample = -1;  ///< the draw it relights (sampled lighting), or -1
};

/// The batch's frames, light set by light set (so each set's lights are
/// relit once per rank): every map x rotation, or the sampled draws.
std::vector<BatchFrame> batchFrames(const BatchRelightOptions& a,
                                    const std::vector<EnvInput>& inputs, size_t lightSets);

/// The batch's sets of local lights: every combination of the --light
/// lights' sweeps (one set when none sweeps, which may hold no light), each
/// added to every line of the light path if there is one (path line major).
std::vector<std::vector<LocalLight>> lightSets(const BatchRelightOptions& a);

/// The lights of a set as canonical specs.
std::vector<std::string> canonicalSpecs(const std::vector<LocalLight>& lights);

/// Texts joined by ';', as manifest.csv lists a frame's lights and files.
std::string joinedBySemicolons(const std::vector<std::string>& texts);

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
                                          const std::optional<SourceFinding>& sources);

/// The lightings loaded, their warnings and errors in the order given, as
/// if read one after another: in a batch, one that cannot be read is skipped
/// with a warning (and reported), otherwise its error stops the run.
std::vector<EnvInput> takeInputs(const std::vector<std::string>& specs,
                                 std::vector<LoadedLighting> loaded, bool batch,
                                 const std::function<void(const std::string&)>& warnOf);

/// Refuses a batch whose frames, uncompressed in every format (an upper
/// bound), would not fit the disk.
void requireFrameSpace(const BatchRelightOptions& a, ImageSize size,
                       const std::vector<ImageFormat>& formats, bool batch, size_t lightSets);

}  // namespace acpca
