#include "precompute/transport/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <filesystem>

#include "precompute/transport/error.h"

namespace acpca {

namespace fs = std::filesystem;

AtomicOutput::AtomicOutput(std::string finalPath) : finalPath_(std::move(finalPath)) {
  if (finalPath_.empty()) throw UserError("output path is empty");
  const fs::path target(finalPath_);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw UserError(concat(finalPath_, ": output directory '", dir.string(), "' does not exist"));
  if (fs::is_directory(target, ec))
    throw UserError(concat(finalPath_, ": is a directory, expected a file path"));
  static std::atomic<int> counter{0};
  // Keep the extension last: image writers pick the format from it.
  tempPath_ = (dir / concat(".", target.stem().string(), ".partial-", ::getpid(), "-", counter++,
                            target.extension().string()))
                  .string();
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(tempPath_, ec);
  }
}

void AtomicOutput::commit() {
  std::error_code ec;
  fs::rename(tempPath_, finalPath_, ec);
  if (ec)
    throw UserError(
        concat(finalPath_, ": cannot move the finished file into place: ", ec.message()));
  committed_ = true;
}

}  // namespace acpca
