#pragma once
// A batch's manifest.csv (docs/formats.md, "Batch manifest"), written as the
// frames land: the header at once, then one row per frame in frame order, each
// appended with one write after the frame's files are in place, so a batch
// killed midway leaves a manifest that lists the frames on disk: all of them
// but, at most, the one whose files were being renamed into place.
// manifest.jsonl beside it holds the same frames as JSON objects, a line each.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/table.h"

namespace acpca {

/// A file created empty (or emptied) and appended to, each piece of text in
/// one write: a kill lands between pieces, never inside one.
class AppendOnlyFile {
 public:
  /// WriteError naming the path when it cannot be created.
  explicit AppendOnlyFile(std::string path);
  ~AppendOnlyFile();
  AppendOnlyFile(const AppendOnlyFile&) = delete;
  AppendOnlyFile& operator=(const AppendOnlyFile&) = delete;
  /// WriteError naming the path when the disk refuses it.
  void write(const std::string& text);

 private:
  std::string path_;
  int fd_ = -1;
};

class BatchManifest {
 public:
  /// Creates (or empties) the file and writes the header.
  BatchManifest(std::string path, std::vector<std::string> columns);
  /// Appends one row (a cell per column).
  void append(std::vector<Table::Cell> row);

 private:
  AppendOnlyFile file_;
  std::vector<std::string> columns_;
};

/// manifest.jsonl: one JSON object per line.
class JsonLinesManifest {
 public:
  explicit JsonLinesManifest(std::string path) : file_(std::move(path)) {}
  void append(const nlohmann::json& object) { file_.write(object.dump() + "\n"); }

 private:
  AppendOnlyFile file_;
};

}  // namespace acpca
