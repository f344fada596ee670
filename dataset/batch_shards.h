#pragma once
// A sharded batch's tar files (docs/datasets.md, "Shards"): frames in
// groups of N by their index in the batch, WebDataset style. A frame's files
// are staged under its key (00123.exr, 00123.shading.exr, 00123.json holding
// its manifest line) in a hidden directory as it commits; after a group's
// last frame they are packed into NAME-000000.tar, renamed into place whole,
// with each view's labels once before that view's first frame in the shard.
// A kill leaves whole tars and staged files the next run removes; a rerun
// packs only the shards that are missing.
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "dataset/tar_archive.h"

namespace acpca {

/// Throws UserError naming the first tar of the directory's name pattern
/// (NAME-NNNNNN.tar) in a directory no dataset.json claims: a sharded batch
/// would take it for one of its own.
void refuseUnclaimedShards(const std::string& directory);

class BatchShards {
 public:
  /// `directory` exists; `frames` in the batch, `keyDigits` of a key
  /// (frameIndexDigits). Notes which shards are in place already and
  /// removes what a killed run left staged.
  BatchShards(const std::string& directory, long long shardSize, long long frames, int keyDigits);

  /// NAME-000000.tar, NAME the directory's name.
  std::string shardName(long long shard) const;
  /// Whether the frame's shard was in place when the batch began (its
  /// files are not written again).
  bool packed(long long frame) const { return packed_.count(frame / size_) > 0; }
  /// Where the frame's file with `suffix` (".exr", ".shading") is staged:
  /// its key, then the suffix (the staging directory made when it is not
  /// packed).
  std::string stagedPath(long long frame, const std::string& suffix) const;
  /// The frame's committed files (staged paths, in order), its view's label
  /// files and its manifest line, in frame order; after a shard's last
  /// frame the shard is packed. Nothing for a frame whose shard is packed.
  void committed(long long frame, const std::vector<std::string>& files,
                 const std::vector<std::string>& viewLabels, const nlohmann::json& line);
  /// NAME-shards.json: every shard's name, first frame and sample count.
  void writeIndex() const;

 private:
  std::string stagingDirectory(long long shard) const;
  std::string directory_, name_;
  long long size_, frames_;
  int keyDigits_;
  std::set<long long> packed_;      ///< shards in place when the batch began
  std::vector<TarMember> members_;  ///< the shard being staged
  std::set<std::string> labelsIn_;  ///< label files it holds already
};

}  // namespace acpca
