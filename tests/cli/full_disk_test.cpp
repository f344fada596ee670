// Writers on a full disk: a clear message naming the file, exit 1, no crash
// and no partial file. The disk is filled without mount privileges by a file
// size limit (ulimit -f, with SIGXFSZ ignored), which makes a write fail the
// way a full tmpfs does, part-way through.
#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include <filesystem>

#include "tests/cli/run_cli.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

namespace fs = std::filesystem;

/// Runs the CLI with files limited to `kib` KiB.
RunResult runCliOnFullDisk(const std::string& args, int kib) {
  return runShell("trap '' XFSZ; ulimit -f " + std::to_string(kib) + "; exec " +
                  std::string(ACPCA_CLI_PATH) + " " + args);
}

/// Only the files a test put there itself: nothing partial, no target.
std::vector<std::string> filesIn(const test::TempDir& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir.path()))
    names.push_back(e.path().filename().string());
  return names;
}

TEST(FullDisk, EveryWriterFailsCleanlyAndLeavesNothing) {
  test::TempDir in, out;
  const std::string transport = in.file("t.h5");
  ASSERT_EQ(
      runCli("precompute --scene plant --size 48x48 --cubemap 8 --quiet --out " + transport).status,
      0);
  ASSERT_EQ(
      runCli("compress " + transport + " --method adaptive-quad --quiet --out " + in.file("m.h5"))
          .status,
      0);
  // --force: past the estimate that refuses before any work (reliability_test),
  // so that the writes themselves meet the full disk.
  const std::vector<std::string> commands{
      "precompute --scene plant --size 48x48 --cubemap 8 --quiet --force --out " + out.file("t.h5"),
      "compress " + transport + " --method global --quiet --out " + out.file("m.h5"),
      "relight " + in.file("m.h5") +
          " --env sky --env constant:1 --rotate 0:360:30 --quiet --force --out " +
          out.file("frames"),
  };
  for (const auto& command : commands) {
    const RunResult r = runCliOnFullDisk(command, 4);
    EXPECT_EQ(r.status, 1) << command << "\n" << r.output;
    EXPECT_NE(r.output.find("adaptive-cpca: error:"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("internal error"), std::string::npos) << r.output;
    std::set<std::string> frames;
    for (const auto& name : filesIn(out)) {
      EXPECT_EQ(name.find(".partial-"), std::string::npos) << command << ": left " << name;
      EXPECT_TRUE(name != "t.h5" && name != "m.h5") << command << ": wrote " << name;
      if (name.size() > 4 && name.substr(name.size() - 4) == ".exr") frames.insert(name);
    }
    // The frames that fitted are complete, and the manifest lists them: all
    // but, at most, the one whose row the full disk refused.
    const fs::path manifest = fs::path(out.file("frames")) / "manifest.csv";
    if (fs::exists(manifest)) {
      std::ifstream in(manifest);
      std::string line;
      std::getline(in, line);  // the header
      std::set<std::string> listed;
      while (std::getline(in, line))
        listed.insert(fs::path(line.substr(line.rfind(',') + 1)).filename().string());
      for (const auto& name : listed) EXPECT_TRUE(frames.count(name)) << name << " listed";
      EXPECT_LE(frames.size(), listed.size() + 1) << command;
    } else {
      EXPECT_LE(frames.size(), 1u) << command;
    }
  }
}

TEST(FullDisk, AnOutputDirectoryRemovedMidwayIsAClearError) {
  test::TempDir dir;
  const std::string out = (dir.path() / "out").string();
  fs::create_directories(out);
  // Remove the directory once the precompute has started writing into it.
  const RunResult r = runShell(
      std::string(ACPCA_CLI_PATH) + " precompute --scene plant --size 256x256 --cubemap 16 " +
      "--quiet --out " + out + "/t.h5 & pid=$!; " + "for i in $(seq 600); do ls " + out +
      "/.t.partial-* >/dev/null 2>&1 && break; sleep 0.01; " + "done; rm -rf " + out +
      "; wait $pid");
  EXPECT_EQ(r.status, 1) << r.output;
  EXPECT_NE(r.output.find("t.h5: cannot"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace acpca
