#include "dataset/batch_frames.h"

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

const Environment& latticeMap(const EnvInput& in, bool exactSources) {
  return exactSources && in.split.rest ? *in.split.rest : *in.env;
}

std::vector<BatchFrame> batchFrames(const BatchRelightOptions& a,
                                    const std::vector<EnvInput>& inputs, size_t lightSets) {
  std::vector<BatchFrame> frames;
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

std::vector<std::string> canonicalSpecs(const std::vector<LocalLight>& lights) {
  std::vector<std::string> specs;
  for (const LocalLight& light : lights) specs.push_back(light.canonicalSpec());
  return specs;
}

std::string joinedBySemicolons(const std::vector<std::string>& texts) {
  std::string joined;
  for (const std::string& t : texts) joined += (joined.empty() ? "" : ";") + t;
  return joined;
}

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

}  // namespace acpca
