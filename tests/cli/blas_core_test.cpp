// The CLI and the kernels OpenBLAS runs (cluster/blas_core.h): a generic
// fallback on a CPU that has more is replaced before any work, a core the
// user forces is kept and its answers checked, and every method makes a
// model as good as the one the CPU's own kernels make.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cluster/blas_core.h"
#include "model/model_file.h"
#include "tests/cli/run_cli.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

using test::TempDir;

const std::string kPlant = std::string(ACPCA_FIXTURE_DIR) + "/small-plant.h5";

nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

/// `env -u` both OpenBLAS variables, then `extra` (more variables, a preload).
std::string environment(const std::string& extra) {
  return "env -u OPENBLAS_CORETYPE -u OPENBLAS_L2_SIZE -u ACPCA_CHOSE_OPENBLAS_CORETYPE " + extra;
}

TEST(BlasCoreCli, AGenericFallbackIsReplacedByTheCpusCoreBeforeAnyWork) {
  // The shim answers "Prescott" while OPENBLAS_CORETYPE is unset, as Debian
  // 12's OpenBLAS does on an Emerald Rapids or Zen 5 CPU.
  TempDir dir;
  const RunResult r =
      runCli("compress " + kPlant + " --method adaptive-binary --clusters 4 --quiet --out " +
                 dir.file("m.h5") + " --json " + dir.file("r.json"),
             environment(std::string("LD_PRELOAD=") + ACPCA_PRESCOTT_SHIM));
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json report = readJson(dir.file("r.json"));
  const std::string cpu = cpuBlasCore();
  if (cpu == "Prescott") GTEST_SKIP() << "a CPU without AVX: its generic kernels are its own";
  EXPECT_EQ(report["blas_core_chosen_by"], "adaptive-cpca") << report.dump();
  EXPECT_EQ(report["eigensolver"], "LAPACK");
  // OPENBLAS_CORETYPE names cores in any case; OpenBLAS reports its own spelling.
  EXPECT_EQ(report["blas_core"], cpu) << report.dump();
  const auto settings = nlohmann::json::parse(readModel(dir.file("m.h5")).settings);
  EXPECT_EQ(settings["blas_core"], cpu);
}

TEST(BlasCoreCli, EveryMethodUnderForcedGenericKernelsMatchesTheCpusOwn) {
  // OPENBLAS_CORETYPE=PRESCOTT set by the user is kept; on a CPU with AVX2
  // Eigen's solver answers in place of those kernels, checked. The model
  // agrees with the one the CPU's kernels make to the compressor's own
  // tolerance: ranks chosen near a threshold may differ by one.
  TempDir dir;
  for (const std::string method : {"global", "block", "cpca", "adaptive-quad", "adaptive-binary"}) {
    SCOPED_TRACE(method);
    const std::string args = "compress " + kPlant + " --method " + method +
                             " --clusters 4 --quiet --json " + dir.file("r.json") + " --out ";
    const RunResult own = runCli(args + dir.file("own.h5"), environment(""));
    ASSERT_EQ(own.status, 0) << own.output;
    const RunResult forced =
        runCli(args + dir.file("forced.h5"), environment("OPENBLAS_CORETYPE=PRESCOTT"));
    ASSERT_EQ(forced.status, 0) << forced.output;
    const nlohmann::json report = readJson(dir.file("r.json"));
    EXPECT_EQ(report["blas_core"], "Prescott");
    EXPECT_EQ(report["blas_core_chosen_by"], "OPENBLAS_CORETYPE");
    EXPECT_EQ(report["eigensolver"], cpuBlasCore() == "Prescott" ? "LAPACK" : "Eigen");
    const Model a = readModel(dir.file("own.h5")), b = readModel(dir.file("forced.h5"));
    ASSERT_EQ(a.globalBases(), b.globalBases());
    EXPECT_NEAR(b.transportError, a.transportError, 0.02 * a.transportError + 1e-6);
    EXPECT_NEAR(b.totalCost(), a.totalCost(), 0.05 * a.totalCost());
  }
}

}  // namespace
}  // namespace acpca
