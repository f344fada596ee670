// `mpirun -np K adaptive-cpca precompute`: the same file, byte for byte, for
// any rank count and without MPI; a rank that dies is named and leaves nothing
// that reads as valid; commands that do not deal their work refuse to run K
// times. Needs Open MPI (scripts/setup.sh installs it); skipped in a build
// without it.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "model/model_file.h"
#include "tests/cli/run_cli.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

using test::TempDir;
namespace fs = std::filesystem;

#ifdef ACPCA_MPIEXEC
/// mpirun with what a container's root needs: permission to run as root and
/// no cross-memory-attach (often not permitted there); more ranks than cores;
/// no binding, so each rank's threads may use every core.
std::string mpirun(int ranks, const std::string& environment = "") {
  return (environment.empty() ? std::string() : environment + " ") +
         "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 "
         "OMPI_MCA_btl_vader_single_copy_mechanism=none " ACPCA_MPIEXEC
         " --oversubscribe --bind-to none -np " +
         std::to_string(ranks);
}

/// The core gather primitive (core/rank_gather.h) through gather_probe: every
/// item arrives once and whole at rank 0, in item order where asked, for 1..4
/// ranks, floats and bytes, more items than ranks and fewer.
TEST(Mpi, GatherDeliversEveryItemOnceAtOneToFourRanks) {
  TempDir dir;
  for (int ranks : {1, 2, 3, 4})
    for (const std::string order : {"item", "arrival"})
      for (const std::string type : {"float", "char"})
        for (int count : {0, 3, 29}) {
          SCOPED_TRACE(std::to_string(ranks) + " ranks, " + order + ", " + type + ", " +
                       std::to_string(count) + " items");
          const std::string out = dir.file("out.txt");
          fs::remove(out);
          const RunResult r =
              runShell(mpirun(ranks) + " " + ACPCA_GATHER_PROBE + " " + std::to_string(count) +
                       " " + order + " " + type + " -1 " + out);
          ASSERT_EQ(r.status, 0) << r.output;
          EXPECT_EQ(test::readFile(out), "gathered " + std::to_string(count) + "\n");
        }
}

/// A rank killed mid-gather ends the whole job, promptly, with nothing written.
TEST(Mpi, GatherWithAKilledRankEndsTheJob) {
  TempDir dir;
  for (int ranks : {2, 3, 4})
    for (const std::string order : {"item", "arrival"}) {
      SCOPED_TRACE(std::to_string(ranks) + " ranks, " + order);
      const std::string out = dir.file("out.txt");
      // Item 5 belongs to rank 5 mod K (never rank 0 here).
      const RunResult r = runShell("timeout 120 env " + mpirun(ranks) + " " + ACPCA_GATHER_PROBE +
                                   " 12 " + order + " float 5 " + out);
      EXPECT_NE(r.status, 0) << r.output;
      EXPECT_NE(r.status, 124) << "the job hung after a rank died";
      EXPECT_NE(r.status, 127) << r.output;  // the command itself ran
      EXPECT_FALSE(fs::exists(out));
    }
}

TEST(Mpi, PrecomputeWritesTheSameBytesForAnyRankCount) {
  TempDir dir;
  // Direct light, and bounced light (R, G and B rows; each rank builds the
  // indirect cache itself). 50 image rows: four tiles of 16 and a short one.
  for (const std::string scene :
       {"--scene plant --size 56x50 --cubemap 8",
        "--scene plant --size 40x34 --cubemap 8 --bounces 1 --indirect-samples 4"}) {
    const std::string alone = dir.file("alone.h5");
    const RunResult r = runCli("precompute " + scene + " --quiet --out " + alone);
    ASSERT_EQ(r.status, 0) << r.output;
    const std::string expected = test::readFile(alone);
    ASSERT_GT(expected.size(), 1000u);
    for (int ranks : {1, 2, 3}) {
      const std::string out = dir.file("ranks" + std::to_string(ranks) + ".h5");
      const RunResult m =
          runCli("precompute " + scene + " --quiet --json - --out " + out, mpirun(ranks));
      ASSERT_EQ(m.status, 0) << m.output;
      EXPECT_TRUE(test::readFile(out) == expected) << scene << ": " << ranks << " ranks";
      EXPECT_NE(m.output.find("\"ranks\": " + std::to_string(ranks)), std::string::npos)
          << m.output;
    }
  }
}

TEST(Mpi, ARankThatDiesIsNamedAndLeavesNoFile) {
  TempDir dir;
  // Image row 21 goes to rank 1 (rows are dealt round robin), which logs rows 16-31.
  const RunResult r =
      runCli("precompute --scene plant --size 48x48 --cubemap 8 --out " + dir.file("t.h5"),
             mpirun(2, "ACPCA_FAULT_ROW=21"));
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("rank 1 of 2: starts image rows 16-31"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("rank 1 of 2: fault injected at image row 21"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir.file("t.h5")));
  // What a killed rank 0 cannot remove is its partial file, under a name no
  // reader takes for the output.
  for (const auto& entry : fs::directory_iterator(dir.path()))
    EXPECT_EQ(entry.path().filename().string().rfind(".t.partial-", 0), 0u)
        << "left behind: " << entry.path();
}

/// Every value a relight or a reader uses (the file's timing and memory
/// attributes are the run's own).
void expectSameModel(const Model& a, const Model& b, const std::string& what) {
  EXPECT_EQ(a.geometry.pixels, b.geometry.pixels) << what;
  EXPECT_EQ(a.geometry.albedo, b.geometry.albedo) << what;
  EXPECT_EQ(a.geometry.coverage, b.geometry.coverage) << what;
  EXPECT_TRUE(a.globalBasis == b.globalBasis) << what;
  EXPECT_EQ(a.settings, b.settings) << what;
  EXPECT_EQ(a.clusterRows, b.clusterRows) << what;
  EXPECT_EQ(a.rowOffsets, b.rowOffsets) << what;
  EXPECT_EQ(a.ranks, b.ranks) << what;
  EXPECT_EQ(a.bases, b.bases) << what;
  EXPECT_EQ(a.means, b.means) << what;
  EXPECT_EQ(a.coeffI8, b.coeffI8) << what;
  EXPECT_EQ(a.coeffScale, b.coeffScale) << what;
  EXPECT_EQ(a.transportError, b.transportError) << what;
}

TEST(Mpi, BuildMakesTheSameModelForAnyRankCount) {
  TempDir dir;
  const std::string build =
      "build --scene plant --size 80x72 --spp 1 --cubemap 8 --block 16 --sample-rows 1500 "
      "--coeffs i8 --quiet ";
  const RunResult r = runCli(build + "--out " + dir.file("alone.h5"));
  ASSERT_EQ(r.status, 0) << r.output;
  const Model alone = readModel(dir.file("alone.h5"));
  ASSERT_GT(alone.clusters(), 20);
  for (int ranks : {1, 2, 3}) {
    const std::string out = dir.file("ranks" + std::to_string(ranks) + ".h5");
    const RunResult m = runCli(build + "--json - --out " + out, mpirun(ranks));
    ASSERT_EQ(m.status, 0) << m.output;
    expectSameModel(readModel(out), alone, std::to_string(ranks) + " ranks");
    // No clock readings or memory figures in the file: the very same bytes.
    EXPECT_TRUE(test::readFile(out) == test::readFile(dir.file("alone.h5")))
        << ranks << " ranks: the model's bytes differ from one process's";
    EXPECT_NE(m.output.find("\"ranks\": " + std::to_string(ranks)), std::string::npos) << m.output;
  }

  // A rank that dies is named, no model appears, and the tiles finished
  // before it resume in one process to the same model.
  const std::string out = dir.file("killed.h5");
  const RunResult killed = runCli(
      "build --scene plant --size 80x72 --spp 1 --cubemap 8 --block 16 "
      "--sample-rows 1500 --coeffs i8 --tiles-in-flight 1 --out " +
          out,
      mpirun(2, "ACPCA_FAULT_TILE=13"));
  EXPECT_NE(killed.status, 0) << killed.output;
  EXPECT_NE(killed.output.find("rank 1 of 2: starts tile 13"), std::string::npos) << killed.output;
  EXPECT_FALSE(fs::exists(out));
  const RunResult resumed = runCli(build + "--resume --json - --out " + out);
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  EXPECT_EQ(resumed.output.find("\"tiles_resumed\": 0,"), std::string::npos) << resumed.output;
  expectSameModel(readModel(out), alone, "resumed after a killed rank");
}

/// Every pixel value of an image file.
std::vector<float> exrPixels(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<float> pixels(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())) return {};
  return pixels;
}

TEST(Mpi, BatchRelightWritesTheSameImagesForAnyRankCount) {
  TempDir dir;
  ASSERT_EQ(runCli("precompute --scene plant --size 40x32 --cubemap 8 --spp 1 --quiet --out " +
                   dir.file("t.h5"))
                .status,
            0);
  ASSERT_EQ(runCli("compress " + dir.file("t.h5") + " --method adaptive-quad --block 16 --quiet " +
                   "--out " + dir.file("m.h5"))
                .status,
            0);
  // 3 maps x 2 rotations (a sweep leaves out its end): 6 frames, dealt unevenly over 4 ranks.
  const std::string batch = " --env sky --env sun:50,30,4,1000 --env constant:1 --rotate 0:90:45 ";
  for (const std::string input : {"m.h5", "t.h5"}) {  // a model, and the dense transport
    SCOPED_TRACE(input);
    const std::string alone = dir.file("alone-" + input);
    ASSERT_EQ(runCli("relight " + dir.file(input) + batch + "--quiet --out " + alone).status, 0);
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(alone))
      if (entry.path().extension() == ".exr") names.push_back(entry.path().filename().string());
    ASSERT_EQ(names.size(), 6u);
    for (int ranks : {1, 2, 3, 4}) {
      const std::string out = dir.file("ranks" + std::to_string(ranks) + "-" + input);
      const RunResult r =
          runCli("relight " + dir.file(input) + batch + "--quiet --out " + out, mpirun(ranks));
      ASSERT_EQ(r.status, 0) << r.output;
      for (const auto& name : names)  // pixels: an EXR's bytes carry the time it was written
        ASSERT_FALSE(exrPixels(alone + "/" + name).empty()) << name;
      for (const auto& name : names)
        EXPECT_EQ(exrPixels(out + "/" + name), exrPixels(alone + "/" + name))
            << name << ", " << ranks << " ranks";
      // The manifests list the same frames in the same order, byte for byte
      // (no times; paths relative to the dataset's directory).
      EXPECT_EQ(test::readFile(out + "/manifest.csv"), test::readFile(alone + "/manifest.csv"));
      EXPECT_EQ(test::readFile(out + "/manifest.jsonl"), test::readFile(alone + "/manifest.jsonl"));
    }
  }
}

/// Every file of a batch's directory, by name: its bytes, with the directory's
/// own path (which the manifests name) written as "OUT".
std::map<std::string, std::string> datasetFiles(const std::string& directory) {
  std::map<std::string, std::string> files;
  for (const auto& entry : fs::directory_iterator(directory)) {
    std::string bytes = test::readFile(entry.path().string());
    for (size_t at; (at = bytes.find(directory)) != std::string::npos;)
      bytes.replace(at, directory.size(), "OUT");
    files[entry.path().filename().string()] = bytes;
  }
  return files;
}

TEST(Mpi, ASampledDatasetIsTheSameBytesForAnyRankCountAndItsSeedAlone) {
  TempDir dir;
  ASSERT_EQ(runCli("precompute --scene plant --size 24x20 --cubemap 4 --spp 2 --quiet --out " +
                   dir.file("t.h5"))
                .status,
            0);
  ASSERT_EQ(runCli("compress " + dir.file("t.h5") + " --method adaptive-binary --quiet --out " +
                   dir.file("m.h5"))
                .status,
            0);
  const auto dataset = [&](const std::string& name, const std::string& seed, int ranks) {
    const std::string out = dir.file(name);
    const RunResult r = runCli("relight " + dir.file("m.h5") +
                                   " --env sky --env sun:50,30,4,1000 --env constant:1 "
                                   "--env-sample 7 --sample-rotation sphere --exposure-jitter 1 "
                                   "--aov all --label-format both --quiet --seed " +
                                   seed + " --out " + out,
                               ranks > 1 ? mpirun(ranks) : "");
    EXPECT_EQ(r.status, 0) << r.output;
    return datasetFiles(out);
  };
  const auto alone = dataset("alone", "11", 1);
  // Frames, shading .exr/.npy; labels (and the mask PNG); manifests, dataset, transforms.json.
  EXPECT_EQ(alone.size(), 7 * 3 + 9 + 4u);
  EXPECT_EQ(alone.count("transforms.json"), 1u);
  EXPECT_EQ(dataset("again", "11", 1), alone);
  for (int ranks : {2, 3}) EXPECT_EQ(dataset("ranks" + std::to_string(ranks), "11", ranks), alone);
  // Another seed: other draws, so other manifests.
  const auto other = dataset("other", "12", 1);
  EXPECT_NE(other.at("manifest.csv"), alone.at("manifest.csv"));
  EXPECT_EQ(other.at("labels.exr"), alone.at("labels.exr"));  // the view is the same
}

TEST(Mpi, CommandsThatDoNotDealTheirWorkRefuseToRunOnSeveralRanks) {
  TempDir dir;
  ASSERT_EQ(
      runCli("precompute --scene plant --size 16x16 --cubemap 4 --quiet --out " + dir.file("t.h5"))
          .status,
      0);
  const RunResult r = runCli(
      "compress " + dir.file("t.h5") + " --method global --out " + dir.file("m.h5"), mpirun(2));
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("'compress' does not run over MPI ranks"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir.file("m.h5")));
  // One rank is an ordinary run.
  EXPECT_EQ(runCli("info " + dir.file("t.h5"), mpirun(1)).status, 0);
  // build deals its tiles, but --keep-transport needs every row in one process.
  const RunResult kept = runCli("build --scene plant --size 16x16 --cubemap 4 --keep-transport " +
                                    dir.file("kept.h5") + " --out " + dir.file("b.h5"),
                                mpirun(2));
  EXPECT_NE(kept.status, 0) << kept.output;
  EXPECT_NE(kept.output.find("--keep-transport '"), std::string::npos) << kept.output;
  EXPECT_FALSE(fs::exists(dir.file("kept.h5")));
  EXPECT_FALSE(fs::exists(dir.file("b.h5")));
}
#else
TEST(Mpi, NeedsAnMpiBuild) {
  GTEST_SKIP() << "built without MPI (scripts/setup.sh installs Open MPI)";
}
#endif

}  // namespace
}  // namespace acpca
