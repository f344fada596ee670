#include "core/atomic_file.h"

#include <signal.h>
#include <unistd.h>

#include <cerrno>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>

#include "core/error.h"
#include "core/interrupt_cleanup.h"
#include "core/warning.h"

namespace acpca {

namespace fs = std::filesystem;

namespace {

/// Removes what killed runs left of earlier writes to the same target: files
/// named as tempPath names them whose process no longer exists.
/// Removes the partial files (".NAME.partial-PID-N.EXT") in `dir` whose
/// process is gone, once per directory and process: a batch writes thousands
/// of files into one directory, and scanning it for each would cost the square.
void removeStalePartials(const fs::path& dir) {
  static std::mutex mutex;
  static std::set<std::string> scanned;
  {
    std::lock_guard lock(mutex);
    if (!scanned.insert(fs::absolute(dir).lexically_normal().string()).second) return;
  }
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    const auto marker = name.find(".partial-");
    if (name.empty() || name[0] != '.' || marker == std::string::npos || marker < 2) continue;
    const std::string rest = name.substr(marker + 9);  // PID-N.EXT
    const auto dash = rest.find('-');
    if (dash == std::string::npos || dash == 0 || rest.find_first_not_of("0123456789") != dash)
      continue;
    const auto dot = rest.find('.', dash);
    const std::string counter =
        rest.substr(dash + 1, dot == std::string::npos ? dot : dot - dash - 1);
    if (counter.empty() || counter.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string target =
        name.substr(1, marker - 1) + (dot == std::string::npos ? std::string() : rest.substr(dot));
    const long pid = std::stol(rest.substr(0, dash));
    if (pid > 0 && ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH &&
        fs::remove(entry.path(), ec))
      warn(concat("removed ", entry.path().string(), ", an unfinished ", target,
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
  removeStalePartials(dir);
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
