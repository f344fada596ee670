#pragma once
// Outputs are written under a temporary name beside the target and renamed into
// place only when complete, so an error or a kill never leaves a file that reads
// as valid.
#include <string>

namespace acpca {

class AtomicOutput {
 public:
  /// Checks that the target's directory exists; throws UserError naming it if not.
  explicit AtomicOutput(std::string finalPath);
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;
  /// Removes the temporary file unless commit() succeeded.
  ~AtomicOutput();

  const std::string& tempPath() const { return tempPath_; }
  const std::string& finalPath() const { return finalPath_; }
  /// Renames the temporary file onto the final path.
  void commit();

 private:
  std::string finalPath_;
  std::string tempPath_;
  int interruptSlot_ = -1;  // where SIGINT/SIGTERM find the temporary
  bool committed_ = false;
};

/// Creates a directory (and its parents) for outputs; throws WriteError naming
/// it when that fails.
void createOutputDirectory(const std::string& path);

/// Writes a whole text file atomically; throws WriteError naming the path when
/// the disk is full or the directory is gone.
void writeTextFile(const std::string& path, const std::string& text);

}  // namespace acpca
