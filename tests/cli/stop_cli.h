#pragma once
// Runs the real CLI and stops it with a signal at a chosen moment, for the
// interruption and reliability suites; finds the partial files a run left.
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "tests/cli/run_cli.h"
#include "tests/test_support.h"

extern char** environ;

namespace acpca::test {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

/// Every file under `dir` (any depth) whose name marks it unfinished.
inline std::vector<std::string> partialFiles(const fs::path& dir) {
  std::vector<std::string> found;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec);
       it != fs::recursive_directory_iterator(); it.increment(ec))
    if (it->path().filename().string().find(".partial-") != std::string::npos)
      found.push_back(it->path().string());
  return found;
}

inline bool hasPartial(const fs::path& dir, long long bytes) {
  std::error_code ec;
  for (const auto& p : partialFiles(dir))
    if (static_cast<long long>(fs::file_size(p, ec)) >= bytes) return true;
  return false;
}

struct Stopped {
  bool signalled = false;  ///< the signal was sent while it ran
  int exitCode = -1;       ///< -1: it did not exit normally
  double secondsToExit = 0;
  std::string output;
};

/// Whether process `pid` has installed a handler for `signal` (its SigCgt mask
/// in /proc): before that, the dynamic loader and the libraries' static
/// initializers still run, and the signal would kill it outright.
inline bool catchesSignal(pid_t pid, int signal) {
  const std::string status = test::readFile("/proc/" + std::to_string(pid) + "/status");
  const auto at = status.find("SigCgt:");
  if (at == std::string::npos) return false;
  const unsigned long long mask = std::stoull(status.substr(at + 7), nullptr, 16);
  return (mask >> (signal - 1)) & 1;
}

/// Runs the CLI with `args` (stderr to a file), sends `signal` once `ready()`
/// says so and the CLI catches it (or after 60 s), and waits for it. With `ignoredByParent` it
/// starts with SIGINT and SIGTERM ignored, as a script's background job does.
inline Stopped stopWhen(const std::vector<std::string>& args, const std::function<bool()>& ready,
                        int signal, const std::string& log, bool ignoredByParent = false) {
  std::vector<std::string> argv{ACPCA_CLI_PATH};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<char*> raw;
  for (auto& a : argv) raw.push_back(a.data());
  raw.push_back(nullptr);
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  struct sigaction ignore {
  }, oldInt{}, oldTerm{};
  ignore.sa_handler = SIG_IGN;
  if (ignoredByParent) sigaction(SIGINT, &ignore, &oldInt), sigaction(SIGTERM, &ignore, &oldTerm);
  pid_t pid;
  const int spawned = posix_spawn(&pid, raw[0], &files, nullptr, raw.data(), environ);
  if (ignoredByParent) sigaction(SIGINT, &oldInt, nullptr), sigaction(SIGTERM, &oldTerm, nullptr);
  posix_spawn_file_actions_destroy(&files);
  Stopped s;
  if (spawned != 0) return s;
  const auto start = Clock::now();
  int status = 0;
  for (;;) {
    if (waitpid(pid, &status, WNOHANG) == pid) break;  // finished first
    // SIGKILL has no handler to wait for.
    const bool armed = signal == SIGKILL || catchesSignal(pid, signal);
    if ((ready() && armed) || Clock::now() - start > std::chrono::seconds(60)) {
      kill(pid, signal);
      s.signalled = true;
      const auto sent = Clock::now();
      waitpid(pid, &status, 0);
      s.secondsToExit = std::chrono::duration<double>(Clock::now() - sent).count();
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  s.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  s.output = test::readFile(log);
  return s;
}

inline std::function<bool()> after(double seconds) {
  const auto start = Clock::now();
  return [=] { return Clock::now() - start > std::chrono::duration<double>(seconds); };
}

}  // namespace acpca::test
