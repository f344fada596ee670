#pragma once
// Runs the real `adaptive-cpca` binary for the end-to-end suites.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <string>

namespace acpca {

struct RunResult {
  int status = -1;
  std::string output;  // stdout and stderr together
};

/// Runs a shell command line (/bin/sh), stdout and stderr together; status -1
/// when it did not exit normally (a crash).
inline RunResult runShell(const std::string& commandLine) {
  const std::string command = "( " + commandLine + " ) 2>&1";
  RunResult r;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0) r.output.append(buffer.data(), n);
  const int raw = pclose(pipe);
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  return r;
}

/// Runs `prefix adaptive-cpca args`; the prefix may set the environment or
/// wrap the binary (e.g. "xvfb-run -a").
inline RunResult runCli(const std::string& args, const std::string& prefix = "") {
  return runShell((prefix.empty() ? "" : prefix + " ") + std::string(ACPCA_CLI_PATH) + " " + args);
}

inline void expectFailure(const std::string& args, const std::string& needle,
                          const std::string& prefix = "") {
  const RunResult r = runCli(args, prefix);
  EXPECT_NE(r.status, 0) << args << "\n" << r.output;
  EXPECT_NE(r.status, 3) << "an internal error, not a user error: " << r.output;
  EXPECT_NE(r.output.find(needle), std::string::npos)
      << "message should mention '" << needle << "':\n"
      << r.output;
}

}  // namespace acpca
