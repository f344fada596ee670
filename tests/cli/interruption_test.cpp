// Work killed half-way (SIGKILL: no handler runs) leaves no file that reads as
// valid, and running the same command again gives the result of a clean run.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <nlohmann/json.hpp>

#include "tests/cli/image_pixels.h"
#include "tests/cli/stop_cli.h"

namespace acpca {
namespace {

using test::TempDir;
namespace fs = std::filesystem;
using test::Clock;

/// Runs the CLI with `args` and SIGKILLs it (no handler runs) once `ready()`
/// says so; whether it was killed before finishing.
bool killWhen(const std::vector<std::string>& args, const std::function<bool()>& ready,
              const TempDir& dir) {
  const test::Stopped s = test::stopWhen(args, ready, SIGKILL, dir.file("kill.log"));
  return s.signalled && s.exitCode == -1;
}

size_t partialFiles(const fs::path& dir) {
  return test::partialFiles(dir).size();
}

nlohmann::json info(const std::string& path) {
  const RunResult r = runCli("info " + path + " --json -");
  EXPECT_EQ(r.status, 0) << r.output;
  return r.status == 0 ? nlohmann::json::parse(r.output) : nlohmann::json{};
}

TEST(Interruption, AKilledPrecomputeLeavesNothingValidAndARerunIsExact) {
  TempDir dir;
  const std::string out = dir.file("t.h5");
  // Killed while rows are streaming into the partial file.
  ASSERT_TRUE(killWhen(
      {"precompute", "--scene", "plant", "--size", "160x160", "--quiet", "--out", out},
      [&] { return test::hasPartial(dir.path(), 1 << 20); }, dir))
      << "the precompute should still have been running";
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(partialFiles(dir.path()), 1u) << "the killed run's partial file is left";
  expectFailure("info " + out, "t.h5");

  // The rerun writes the file and clears the dead run's partial.
  ASSERT_EQ(runCli("precompute --scene plant --size 160x160 --quiet --out " + out).status, 0);
  EXPECT_EQ(partialFiles(dir.path()), 0u);
  const std::string clean = dir.file("clean.h5");
  ASSERT_EQ(runCli("precompute --scene plant --size 160x160 --quiet --out " + clean).status, 0);
  const auto a = info(out), b = info(clean);
  EXPECT_EQ(a["occupied_pixels"], b["occupied_pixels"]);
  // Same inputs, same rows: the dense relights agree exactly.
  ASSERT_EQ(runCli("relight " + out + " --env sky --quiet --out " + dir.file("a.exr")).status, 0);
  ASSERT_EQ(runCli("relight " + clean + " --env sky --quiet --out " + dir.file("b.exr")).status, 0);
  const auto pixelsA = test::readPixels(dir.file("a.exr")),
             pixelsB = test::readPixels(dir.file("b.exr"));
  ASSERT_FALSE(pixelsA.empty());
  EXPECT_EQ(pixelsA, pixelsB);
}

TEST(Interruption, AKilledCompressLeavesNothingValidAndARerunIsExact) {
  TempDir dir;
  const std::string transport = dir.file("t.h5");
  ASSERT_EQ(runCli("precompute --scene plant --size 96x96 --cubemap 16 --quiet --out " + transport)
                .status,
            0);
  const std::string out = dir.file("m.h5");
  const auto start = Clock::now();
  ASSERT_TRUE(killWhen(
      {"compress", transport, "--method", "adaptive-binary", "--quiet", "--out", out},
      [&] { return Clock::now() - start > std::chrono::milliseconds(300); }, dir))
      << "the compress should still have been running";
  EXPECT_FALSE(fs::exists(out));
  const std::string args = " --method block --block 8 --global-energy 0.99 --quiet --out ";
  ASSERT_EQ(runCli("compress " + transport + args + out).status, 0);
  ASSERT_EQ(runCli("compress " + transport + args + dir.file("clean.h5")).status, 0);
  EXPECT_EQ(partialFiles(dir.path()), 0u);
  const auto a = info(out), b = info(dir.file("clean.h5"));
  EXPECT_EQ(a["clusters"], b["clusters"]);
  EXPECT_EQ(a["cost_per_pixel"], b["cost_per_pixel"]);
  EXPECT_EQ(a["global_bases"], b["global_bases"]);
}

}  // namespace
}  // namespace acpca
