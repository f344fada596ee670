// `mpirun -np K adaptive-cpca precompute`: the same file, byte for byte, for
// any rank count and without MPI; a rank that dies is named and leaves nothing
// that reads as valid; commands that do not deal their work refuse to run K
// times. Needs Open MPI (scripts/setup.sh installs it); skipped in a build
// without it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

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

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
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
    const std::string expected = bytesOf(alone);
    ASSERT_GT(expected.size(), 1000u);
    for (int ranks : {1, 2, 3}) {
      const std::string out = dir.file("ranks" + std::to_string(ranks) + ".h5");
      const RunResult m =
          runCli("precompute " + scene + " --quiet --json - --out " + out, mpirun(ranks));
      ASSERT_EQ(m.status, 0) << m.output;
      EXPECT_TRUE(bytesOf(out) == expected) << scene << ": " << ranks << " ranks";
      EXPECT_NE(m.output.find("\"ranks\": " + std::to_string(ranks)), std::string::npos)
          << m.output;
    }
  }
}

TEST(Mpi, ARankThatDiesIsNamedAndLeavesNoFile) {
  TempDir dir;
  // Band 21 (image row 21) lies in tile 1 (rows 16-31) and goes to rank 1.
  const RunResult r =
      runCli("precompute --scene plant --size 48x48 --cubemap 8 --out " + dir.file("t.h5"),
             mpirun(2, "ACPCA_FAULT_BAND=21"));
  EXPECT_NE(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("rank 1 of 2: starts tile 1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("rank 1 of 2: fault injected at band 21"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir.file("t.h5")));
  // What a killed rank 0 cannot remove is its partial file, under a name no
  // reader takes for the output.
  for (const auto& entry : fs::directory_iterator(dir.path()))
    EXPECT_EQ(entry.path().filename().string().rfind(".t.partial-", 0), 0u)
        << "left behind: " << entry.path();
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
}
#else
TEST(Mpi, NeedsAnMpiBuild) {
  GTEST_SKIP() << "built without MPI (scripts/setup.sh installs Open MPI)";
}
#endif

}  // namespace
}  // namespace acpca
