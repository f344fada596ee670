#include "dataset/dataset_identity.h"

#include <filesystem>
#include <fstream>

#include "core/atomic_file.h"
#include "core/error.h"

namespace acpca {

namespace {

constexpr const char* kFileName = "dataset.json";
/// The directory's layout: 2 names every frame's files by its index in the
/// batch and lists paths relative to the directory (docs/formats.md, "Batch
/// manifest"); 1 (no "layout" key) named them by lighting alone.
constexpr int kDatasetLayout = 2;

std::string identityPath(const std::string& directory) {
  return (std::filesystem::path(directory) / kFileName).string();
}

}  // namespace

nlohmann::json datasetIdentity(const BatchRelightOptions& a) {
  nlohmann::json rotations = nlohmann::json::array();
  for (const EnvRotation& r : a.rotations) rotations.push_back({r.yaw, r.pitch, r.roll});
  nlohmann::json aovs = nlohmann::json::array();
  for (Aov aov : a.aovs) aovs.push_back(kAovNames.name(aov));
  nlohmann::json identity = {{"format", "adaptive-cpca dataset"},
                             {"layout", kDatasetLayout},
                             {"input", a.viewInputs()},
                             {"envs", a.envs},
                             {"rotations", rotations},
                             {"lights", a.lights},
                             {"light_path", a.lightPath},
                             {"exposure", a.exposure},
                             {"background", kBackgroundNames.name(a.background)},
                             {"image_format", a.format.empty() ? "exr" : a.format},
                             {"exr_float", a.exrFloat},
                             {"tone", kToneCurveNames.name(a.tone)},
                             {"max_rank", a.maxRank.text()},
                             {"aovs", aovs},
                             {"label_format", kLabelFormatNames.name(a.labelFormat)},
                             {"lighting_exr", a.lightingImages},
                             {"keep_negative", a.keepNegative}};
  // The sources lit exactly change every sunlit pixel: "off", or at most K.
  identity["sun"] = a.sources ? std::to_string(a.sources->maxSources) : "off";
  if (a.shardSize > 0) identity["shard_size"] = a.shardSize;
  if (a.sampling.count > 0)
    identity["sampling"] = {{"count", a.sampling.count},
                            {"seed", a.sampling.seed},
                            {"rotation", kSampledRotationNames.name(a.sampling.rotation)},
                            {"exposure_jitter", a.sampling.exposureJitter}};
  return identity;
}

void refuseAnotherDataset(const std::string& directory, const nlohmann::json& identity) {
  const std::string path = identityPath(directory);
  std::ifstream in(path);
  if (!in) return;  // a new directory, or one no dataset claimed
  const nlohmann::json held = nlohmann::json::parse(in, nullptr, false);
  if (held.is_discarded() || !held.is_object())
    throw UserError(concat(path, ": not a dataset description; give another --out or remove it"));
  if (!held.contains("layout") || held.at("layout") != kDatasetLayout)
    throw UserError(concat(directory, " holds a dataset of an earlier layout (frames named by ",
                           "lighting alone): give another --out, or remove it and run again"));
  for (const auto& [key, value] : identity.items())
    if (!held.contains(key) || held.at(key) != value)
      throw UserError(concat(directory, " holds another dataset (", key, ": ",
                             held.contains(key) ? held.at(key).dump() : "unset", " there, ",
                             value.dump(), " here): give another --out, or remove it first"));
  for (const auto& [key, value] : held.items())
    if (!identity.contains(key))
      throw UserError(concat(directory, " holds another dataset (with ", key,
                             "): give another --out, or remove it first"));
}

void writeDatasetIdentity(const std::string& directory, const nlohmann::json& identity) {
  writeTextFile(identityPath(directory), identity.dump(2) + "\n");
}

}  // namespace acpca
