#pragma once
// A batch's manifest.csv (docs/formats.md, "Batch manifest"), written as the
// frames land: the header at once, then one row per frame in frame order, each
// appended with one write after the frame's files are in place, so a batch
// killed midway leaves a manifest that lists the frames on disk: all of them
// but, at most, the one whose files were being renamed into place.
#include <string>
#include <vector>

#include "core/table.h"

namespace acpca {

class BatchManifest {
 public:
  /// Creates (or empties) the file and writes the header; WriteError naming
  /// the path when it cannot.
  BatchManifest(std::string path, std::vector<std::string> columns);
  ~BatchManifest();
  BatchManifest(const BatchManifest&) = delete;
  BatchManifest& operator=(const BatchManifest&) = delete;

  /// Appends one row (a cell per column); WriteError when the disk refuses it.
  void append(std::vector<Table::Cell> row);

 private:
  void write(const std::string& text);

  std::string path_;
  std::vector<std::string> columns_;
  int fd_ = -1;
};

}  // namespace acpca
