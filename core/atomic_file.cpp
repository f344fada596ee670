#include "core/atomic_file.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>

#include <atomic>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "core/interrupt_cleanup.h"
#include "core/warning.h"

namespace acpca {

namespace fs = std::filesystem;

namespace {

/// Removes what killed runs left of earlier writes to the same target: files
/// named as tempPath names them whose process no longer exists.
void removeStalePartials(const fs::path& dir, const fs::path& target) {
  const std::string prefix = concat(".", target.stem().string(), ".partial-");
  const std::string extension = target.extension().string();
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0 || name.size() < prefix.size() + extension.size() ||
        name.compare(name.size() - extension.size(), extension.size(), extension) != 0)
      continue;
    const std::string rest = name.substr(prefix.size());
    const auto dash = rest.find('-');
    if (dash == std::string::npos || dash == 0 || rest.find_first_not_of("0123456789") != dash)
      continue;
    const long pid = std::stol(rest.substr(0, dash));
    if (pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH &&
        fs::remove(entry.path(), ec))
      warn(concat("removed ", entry.path().string(), ", an unfinished ", target.filename().string(),
                  " left by process ", pid, " (killed or powered off)"));
  }
}

}  // namespace

AtomicOutput::AtomicOutput(std::string finalPath) : finalPath_(std::move(finalPath)) {
  if (finalPath_.empty()) throw UserError("output path is empty");
  const fs::path target(finalPath_);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw UserError(concat(finalPath_, ": output directory '", dir.string(), "' does not exist"));
  if (fs::is_directory(target, ec))
    throw UserError(concat(finalPath_, ": is a directory, expected a file path"));
  removeStalePartials(dir, target);
  static std::atomic<int> counter{0};
  // Keep the extension last: image writers pick the format from it.
  tempPath_ = (dir / concat(".", target.stem().string(), ".partial-", ::getpid(), "-", counter++,
                            target.extension().string()))
                  .string();
  interruptSlot_ = interrupt::registerTemporary(tempPath_);
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::error_code ec;
    fs::remove(tempPath_, ec);
  }
  interrupt::releaseTemporary(interruptSlot_);
}

void AtomicOutput::commit() {
  std::error_code ec;
  fs::rename(tempPath_, finalPath_, ec);
  if (ec)
    throw UserError(
        concat(finalPath_, ": cannot move the finished file into place: ", ec.message()));
  committed_ = true;
  interrupt::releaseTemporary(interruptSlot_);
  interruptSlot_ = -1;
}

void createOutputDirectory(const std::string& path) {
  std::error_code ec;
  fs::create_directories(path, ec);
  if (!fs::is_directory(path, ec))
    throw WriteError(concat(path, ": cannot create the output directory"));
}

void writeTextFile(const std::string& path, const std::string& text) {
  AtomicOutput file(path);
  {
    std::ofstream out(file.tempPath());
    out << text;
    out.close();  // a full disk often shows only when the buffer is flushed
    if (!out) throw WriteError(concat(path, ": cannot write (disk full or directory removed?)"));
  }
  file.commit();
}

}  // namespace acpca
