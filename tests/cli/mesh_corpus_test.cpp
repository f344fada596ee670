// Real model files, many malformed on purpose: every file of Debian's
// assimp-testmodels that assimp claims to read either renders or is refused
// with a message naming it; none crashes the renderer, ends in an internal
// error or hangs. Crashes inside assimp are contained (mesh_import.h).
// Each file costs a process start (about half a second, most of it loading
// OpenImageIO's dependencies), so the corpus runs as shards that ctest can
// run side by side and that each stay far inside the per-test timeout.
#include <gtest/gtest.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "tests/cli/run_cli.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

namespace fs = std::filesystem;
const fs::path kModels = "/usr/share/assimp/models";

std::string shellQuoted(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

constexpr int kShards = 6;

// The files of shard `shard`: every kShards-th of the sorted corpus, so that
// the shards mix the formats (and their costs) evenly.
std::vector<fs::path> corpusShard(int shard) {
  Assimp::Importer importer;
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(kModels))
    if (e.is_regular_file() && importer.IsExtensionSupported(e.path().extension().string()))
      files.push_back(e.path());
  std::sort(files.begin(), files.end());
  EXPECT_GT(files.size(), 300u) << "the corpus should hold hundreds of model files";
  std::vector<fs::path> mine;
  for (size_t i = shard; i < files.size(); i += kShards) mine.push_back(files[i]);
  return mine;
}

class MeshCorpus : public ::testing::TestWithParam<int> {};

TEST_P(MeshCorpus, EveryAssimpTestModelRendersOrIsRefusedWithAMessage) {
  if (!fs::is_directory(kModels)) GTEST_SKIP() << "assimp-testmodels is not installed";
  const std::vector<fs::path> files = corpusShard(GetParam());

  test::TempDir dir;
  const std::string scene = dir.file("scene.json"), out = dir.file("t.h5");
  int rendered = 0, refused = 0;
  for (const fs::path& file : files) {
    const nlohmann::json doc = {{"camera",
                                 {{"eye", {0, 0, 5}},
                                  {"target", {0, 0, 0}},
                                  {"up", {0, 1, 0}},
                                  {"fov", 40},
                                  {"width", 12},
                                  {"height", 12}}},
                                {"objects", {{{"mesh", file.string()}}}}};
    test::writeFile(scene, doc.dump());
    // timeout: a hang shows as status 124, not as a stuck suite.
    const RunResult r =
        runShell("timeout 120 " + std::string(ACPCA_CLI_PATH) + " precompute --scene " +
                 shellQuoted(scene) + " --camera auto --cubemap 4 --spp 1 --quiet --out " + out);
    if (r.status == 0) {
      ++rendered;
      continue;
    }
    ++refused;
    EXPECT_EQ(r.status, 1) << file
                           << ": a user error is status 1 (3: internal error, 124: hang, "
                              "-1: crash)\n"
                           << r.output;
    EXPECT_NE(r.output.find(file.string()), std::string::npos)
        << file << ": the message names the file\n"
        << r.output;
    EXPECT_EQ(r.output.find("internal"), std::string::npos) << file << "\n" << r.output;
  }
  std::cout << files.size() << " model files: " << rendered << " rendered, " << refused
            << " refused with a message\n";
  EXPECT_GT(rendered, 0.6 * files.size()) << "most of the corpus is readable";
}

INSTANTIATE_TEST_SUITE_P(Shards, MeshCorpus, ::testing::Range(0, kShards));

}  // namespace
}  // namespace acpca
