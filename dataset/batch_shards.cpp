#include "dataset/batch_shards.h"

#include <filesystem>
#include <iomanip>

#include "core/atomic_file.h"
#include "core/error.h"

namespace acpca {

namespace {

namespace fs = std::filesystem;

constexpr const char* kStagingPrefix = ".shard-";
constexpr const char* kStagingSuffix = ".partial";

std::string zeroPadded(long long value, int digits) {
  return concat(std::setw(digits), std::setfill('0'), value);
}

/// The directory's name: what its shards are called after.
std::string directoryName(const std::string& directory) {
  return fs::weakly_canonical(directory).filename().string();
}

}  // namespace

void refuseUnclaimedShards(const std::string& directory) {
  std::error_code ec;
  if (!fs::is_directory(directory, ec) || fs::exists(fs::path(directory) / "dataset.json")) return;
  const std::string prefix = directoryName(directory) + "-";
  for (const auto& entry : fs::directory_iterator(directory)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with(prefix) && name.ends_with(".tar") && name.size() == prefix.size() + 6 + 4)
      throw UserError(concat(entry.path().string(),
                             ": a shard no dataset.json in its directory claims; give another "
                             "--out, or remove the shards first"));
  }
}

BatchShards::BatchShards(const std::string& directory, long long shardSize, long long frames,
                         int keyDigits)
    : directory_(directory),
      name_(directoryName(directory)),
      size_(shardSize),
      frames_(frames),
      keyDigits_(keyDigits) {
  ACPCA_CHECK(size_ > 0, "shard size ", size_);
  for (long long s = 0; s * size_ < frames_; ++s)
    if (fs::exists(fs::path(directory_) / shardName(s))) packed_.insert(s);
  for (const auto& entry : fs::directory_iterator(directory_)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with(kStagingPrefix) && name.ends_with(kStagingSuffix))
      fs::remove_all(entry.path());
  }
}

std::string BatchShards::shardName(long long shard) const {
  return concat(name_, "-", zeroPadded(shard, 6), ".tar");
}

std::string BatchShards::stagingDirectory(long long shard) const {
  return (fs::path(directory_) / concat(kStagingPrefix, zeroPadded(shard, 6), kStagingSuffix))
      .string();
}

std::string BatchShards::stagedPath(long long frame, const std::string& suffix) const {
  const std::string dir = stagingDirectory(frame / size_);
  if (!packed(frame) && !fs::exists(dir)) createOutputDirectory(dir);  // a packed one's is gone
  return (fs::path(dir) / (zeroPadded(frame, keyDigits_) + suffix)).string();
}

void BatchShards::committed(long long frame, const std::vector<std::string>& files,
                            const std::vector<std::string>& viewLabels,
                            const nlohmann::json& line) {
  if (packed(frame)) return;
  for (const std::string& label : viewLabels) {
    const std::string name = fs::path(label).filename().string();
    if (labelsIn_.insert(name).second) members_.push_back({name, label});
  }
  for (const std::string& file : files)
    members_.push_back({fs::path(file).filename().string(), file});
  const std::string json = stagedPath(frame, ".json");
  writeTextFile(json, line.dump() + "\n");
  members_.push_back({fs::path(json).filename().string(), json});
  const long long shard = frame / size_;
  if (frame + 1 != std::min(frames_, (shard + 1) * size_)) return;
  writeTar((fs::path(directory_) / shardName(shard)).string(), members_);
  fs::remove_all(stagingDirectory(shard));
  members_.clear();
  labelsIn_.clear();
}

void BatchShards::writeIndex() const {
  nlohmann::ordered_json shards = nlohmann::ordered_json::array();
  for (long long s = 0; s * size_ < frames_; ++s)
    shards.push_back({{"name", shardName(s)},
                      {"first_frame", s * size_},
                      {"samples", std::min(size_, frames_ - s * size_)}});
  const nlohmann::ordered_json index = {{"format", "adaptive-cpca shards"},
                                        {"name", name_},
                                        {"shard_size", size_},
                                        {"samples", frames_},
                                        {"key_digits", keyDigits_},
                                        {"shards", shards}};
  writeTextFile((fs::path(directory_) / (name_ + "-shards.json")).string(), index.dump(2) + "\n");
}

}  // namespace acpca
