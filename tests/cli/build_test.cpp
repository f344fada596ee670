// `adaptive-cpca build`: the streamed model equals the two-step precompute +
// compress model (same global basis, clusters and ranks; coefficients to the
// fits' rounding), an interrupted build resumes to the same model, and bad
// requests are refused before any work with nothing written.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <Eigen/Core>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "core/statistics.h"
#include "model/model_file.h"
#include "model/model_reference.h"
#include "relight/dense_relight.h"
#include "tests/cli/run_cli.h"
#include "tests/model_support.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

using test::TempDir;
namespace fs = std::filesystem;

/// A 96x96 plant: nine tiles of 32 (edge tiles cut), a basis sample smaller
/// than the image, so that both pipelines must draw the same rows.
const std::string kScene = "--scene plant --size 96x96 --spp 1 --cubemap 8";
const std::string kCompress = "--block 32 --sample-rows 2000 --global-energy 0.999";

/// sum over clusters of |U W^T - U' W'^T|^2 / |U W^T|^2: the reconstructed
/// global coefficients, whatever signs or rotations the eigensolvers chose.
double reconstructionDifference(const Model& a, const Model& b) {
  const int n = a.globalBases();
  double diff = 0, total = 0;
  for (int c = 0; c < a.clusters(); ++c) {
    const long long p = a.rowOffsets[c + 1] - a.rowOffsets[c];
    const auto reconstruct = [&](const Model& m) {
      const Eigen::Map<const Eigen::MatrixXf> w(m.bases.data() + m.basisOffsets[c], n, m.ranks[c]);
      Eigen::MatrixXd u(p, m.ranks[c]);
      for (long long r = 0; r < p; ++r)
        for (int k = 0; k < m.ranks[c]; ++k) u(r, k) = m.coefficient(c, r, k);
      return Eigen::MatrixXd(u * w.cast<double>().transpose());
    };
    const Eigen::MatrixXd x = reconstruct(a), y = reconstruct(b);
    diff += (x - y).squaredNorm(), total += x.squaredNorm();
  }
  return std::sqrt(diff / total);
}

void expectSameClusters(const Model& streamed, const Model& twoStep) {
  EXPECT_EQ(streamed.geometry.pixels, twoStep.geometry.pixels);
  EXPECT_EQ(streamed.geometry.albedo, twoStep.geometry.albedo);
  ASSERT_EQ(streamed.globalBases(), twoStep.globalBases());
  EXPECT_TRUE(streamed.globalBasis == twoStep.globalBasis) << "the same sampled rows, bit for bit";
  EXPECT_EQ(streamed.clusterRows, twoStep.clusterRows);
  EXPECT_EQ(streamed.rowOffsets, twoStep.rowOffsets);
  EXPECT_EQ(streamed.ranks, twoStep.ranks);
  EXPECT_DOUBLE_EQ(streamed.totalCost(), twoStep.totalCost());
  EXPECT_NEAR(streamed.transportError, twoStep.transportError, 1e-4 * twoStep.transportError);
  EXPECT_NEAR(streamed.globalEnergyKept, twoStep.globalEnergyKept, 1e-6);
}

/// A model from `build` records the compress settings a `compress` with the
/// same flags records, key for key and value for value (but for `source`),
/// and beside them how its rows were rendered (kScene's flags).
void expectSameCompressSettings(const Model& streamed, const Model& twoStep) {
  const auto built = nlohmann::json::parse(streamed.settings);
  const auto compressed = nlohmann::json::parse(twoStep.settings);
  for (const auto& [key, value] : compressed.items()) {
    if (key == "source") continue;
    ASSERT_TRUE(built.contains(key)) << "build's settings lack " << key;
    EXPECT_EQ(built[key], value) << key;
  }
  EXPECT_EQ(compressed.size(), 16u) << compressed.dump();
  EXPECT_EQ(built["cubemap"], 8);
  EXPECT_EQ(built["spp"], 1);
  EXPECT_EQ(built["antialiasing"], "adaptive");
  EXPECT_EQ(built["bounces"], 0);
  EXPECT_EQ(built["streamed"], true);
  EXPECT_EQ(built["source"], "build of plant");
}

TEST(Build, EqualsPrecomputeThenCompress) {
  TempDir dir;
  const RunResult pre = runCli("precompute " + kScene + " --quiet --out " + dir.file("t.h5"));
  ASSERT_EQ(pre.status, 0) << pre.output;
  // At the default tolerance the clusters are fitted in float, whose
  // eigensolver turns rounding-level differences of G into small rotations
  // near each cluster's cut; at 0.99995 the fits are in double.
  for (const auto& [tolerance, bound] : {std::pair{"0.999", 2e-3}, std::pair{"0.99995", 1e-5}}) {
    SCOPED_TRACE(tolerance);
    const std::string settings = kCompress + " --tolerance " + tolerance;
    const bool keep = std::string(tolerance) == "0.999";
    const RunResult built = runCli(
        "build " + kScene + " " + settings + " --quiet --json " + dir.file("b.json") +
        (keep ? " --keep-transport " + dir.file("kept.h5") : "") + " --out " + dir.file("b.h5"));
    ASSERT_EQ(built.status, 0) << built.output;
    if (keep) {  // three tile rows of three 32x32 tiles, written as precompute writes T
      const auto bytes = [](const std::string& path) {
        std::ifstream in(path, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
      };
      const std::string kept = bytes(dir.file("kept.h5"));
      EXPECT_FALSE(kept.empty());
      EXPECT_TRUE(kept == bytes(dir.file("t.h5"))) << "--keep-transport: precompute's file";
    }
    const RunResult compressed =
        runCli("compress " + dir.file("t.h5") + " --method adaptive-quad " + settings +
               " --quiet --out " + dir.file("c.h5"));
    ASSERT_EQ(compressed.status, 0) << compressed.output;
    const Model streamed = readModel(dir.file("b.h5")), twoStep = readModel(dir.file("c.h5"));
    expectSameClusters(streamed, twoStep);
    expectSameCompressSettings(streamed, twoStep);
    EXPECT_GT(streamed.clusters(), 9) << "the tiles split: the test exercises the quad tree";
    EXPECT_LT(reconstructionDifference(streamed, twoStep), bound);
    EXPECT_FALSE(fs::exists(dir.file("b.h5.tiles"))) << "the finished tiles are removed";
  }
}

TEST(Build, AnInterruptedBuildLeavesNoModelAndResumesToTheSameOne) {
  TempDir dir;
  const std::string build = "build " + kScene + " " + kCompress + " --coeffs i8 --quiet ";
  ASSERT_EQ(runCli(build + "--out " + dir.file("whole.h5")).status, 0);
  const RunResult killed =
      runCli(build + "--tiles-in-flight 1 --out " + dir.file("m.h5"), "ACPCA_FAULT_TILE=5");
  EXPECT_NE(killed.status, 0) << killed.output;
  EXPECT_FALSE(fs::exists(dir.file("m.h5")));
  ASSERT_TRUE(fs::exists(dir.file("m.h5.tiles/tile-0000004.h5"))) << "tiles before the kill kept";
  const RunResult resumed =
      runCli(build + "--resume --json " + dir.file("r.json") + " --out " + dir.file("m.h5"));
  ASSERT_EQ(resumed.status, 0) << resumed.output;
  EXPECT_NE(test::readFile(dir.file("r.json")).find("\"tiles_resumed\": 5"), std::string::npos)
      << test::readFile(dir.file("r.json"));
  const Model whole = readModel(dir.file("whole.h5")), resumedModel = readModel(dir.file("m.h5"));
  test::expectSameModelArrays(resumedModel, whole);

  // Tiles of other settings are not mixed in: --resume refuses them.
  ASSERT_NE(runCli(build + "--out " + dir.file("n.h5"), "ACPCA_FAULT_TILE=3").status, 0);
  expectFailure(build + "--tolerance 0.99 --resume --out " + dir.file("n.h5"), "other settings");
  EXPECT_FALSE(fs::exists(dir.file("n.h5")));
}

TEST(Build, CpcaAndAdaptiveBinaryClusterEachTileGroupOnItsOwn) {
  // Their clusters may gather rows from anywhere, so a streamed build clusters
  // each group of pixels alone: no cluster crosses a group, and the model is
  // close to (never much worse than) the whole-image one.
  TempDir dir;
  ASSERT_EQ(runCli("precompute " + kScene + " --quiet --out " + dir.file("t.h5")).status, 0);
  for (const std::string method : {"cpca", "adaptive-binary"}) {
    SCOPED_TRACE(method);
    const std::string settings = kCompress + " --method " + method + " --clusters 6";
    const RunResult built =
        runCli("build " + kScene + " " + settings + " --tile 48 --quiet --out " + dir.file("b.h5"));
    ASSERT_EQ(built.status, 0) << built.output;
    ASSERT_EQ(runCli("compress " + dir.file("t.h5") + " " + settings + " --quiet --out " +
                     dir.file("c.h5"))
                  .status,
              0);
    const Model streamed = readModel(dir.file("b.h5")), whole = readModel(dir.file("c.h5"));
    EXPECT_TRUE(streamed.hasMean);
    EXPECT_TRUE(streamed.globalBasis == whole.globalBasis);
    expectSameCompressSettings(streamed, whole);
    for (int c = 0; c < streamed.clusters(); ++c) {
      std::set<int> groups;
      for (long long r = streamed.rowOffsets[c]; r < streamed.rowOffsets[c + 1]; ++r) {
        const int pixel = streamed.geometry.pixels[streamed.clusterRows[r]];
        groups.insert((pixel / 96) / 48 * 2 + (pixel % 96) / 48);
      }
      EXPECT_EQ(groups.size(), 1u) << "cluster " << c << " crosses tile groups";
    }
    EXPECT_LT(streamed.transportError, 1.5 * whole.transportError);
    EXPECT_LT(streamed.totalCost(), 2.0 * whole.totalCost());
  }
}

std::vector<float> readExr(const std::string& path, int width, int height) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << path;
  std::vector<float> pixels(static_cast<size_t>(width) * height * 3);
  if (in) {
    EXPECT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, pixels.data()));
  }
  return pixels;
}

TEST(Build, ItsGroundTruthIsTheDenseRelightAndItsErrorsAreEvals) {
  // No transport file is kept, so the build computes the ground truth from
  // the rows it renders: the images must be relight's of the two-step
  // transport, and the errors those of the model against that dense relight.
  TempDir dir;
  ASSERT_EQ(runCli("precompute " + kScene + " --quiet --out " + dir.file("t.h5")).status, 0);
  const std::vector<std::string> envs{"sky", "sun:50,30,4,1000"};
  const RunResult built =
      runCli("build " + kScene + " " + kCompress + " --coeffs f16 --quiet --ground-truth " +
             dir.file("truth") + " --env sky --env sun:50,30,4,1000 --json " + dir.file("b.json") +
             " --out " + dir.file("b.h5"));
  ASSERT_EQ(built.status, 0) << built.output;
  const auto report = nlohmann::json::parse(std::ifstream(dir.file("b.json")));
  const TransportReader transport(dir.file("t.h5"));
  const Model model = readModel(dir.file("b.h5"));
  const CubeLattice lattice(transport.header().cubemapResolution);
  std::vector<LatticeLighting> lightings;
  for (const auto& spec : envs) {
    lightings.emplace_back(3 * lattice.size(), 0.0);
    loadEnvironment(spec)->integrate(lattice, Eigen::Matrix3d::Identity(), lightings.back());
  }
  const auto dense = denseRelight(transport, lightings);
  const auto relit = relightModelReference(model, lightings);
  for (size_t m = 0; m < envs.size(); ++m) {
    const std::string name = loadEnvironment(envs[m])->name();
    SCOPED_TRACE(name);
    const double error = relativeL2(relit[m], dense[m]);
    EXPECT_GT(error, 1e-4) << "a lossy model";
    EXPECT_NEAR(report["image_errors"][name].get<double>(), error, 1e-6 + 1e-4 * error);

    // The build's truth is what passes through T: the map's sources too.
    const RunResult r = runCli("relight --sun off " + dir.file("t.h5") + " --env " + envs[m] +
                               " --quiet --out " + dir.file(name + ".exr"));
    ASSERT_EQ(r.status, 0) << r.output;
    const auto expected = readExr(dir.file(name + ".exr"), 96, 96);
    const auto truth = readExr(dir.file("truth/" + name + ".exr"), 96, 96);
    double worst = 0, peak = 0;
    for (size_t i = 0; i < truth.size(); ++i)
      worst = std::max(worst, double(std::abs(truth[i] - expected[i]))),
      peak = std::max(peak, double(std::abs(expected[i])));
    EXPECT_LT(worst, 2e-3 * peak) << "half-float EXRs of the same relight";
  }
}

TEST(Build, RefusesWhatItCannotStreamBeforeAnyWork) {
  TempDir dir;
  const std::string out = " --out " + dir.file("m.h5");
  expectFailure("build " + kScene + " --method global" + out, "--method");
  expectFailure("build " + kScene + " --method global" + out, "precompute, then compress");
  expectFailure("build " + kScene + " --method cpca --tile -1" + out, "--tile");
  expectFailure("build " + kScene + " --tolerance 2" + out, "--tolerance");
  expectFailure("build " + kScene + " --sample-rows 0" + out, "--sample-rows");
  expectFailure("build " + kScene + " --env nosuchmap.exr" + out, "nosuchmap.exr");
  expectFailure("build " + kScene + " --out " + dir.file("missing/m.h5"), "does not exist");
  expectFailure("build " + kScene + " --keep-transport " + dir.file("missing/t.h5") + out,
                "does not exist");
  expectFailure("build " + kScene + " --resume --keep-transport " + dir.file("t.h5") + out,
                "cannot resume");
  EXPECT_TRUE(fs::is_empty(dir.path()));
}

}  // namespace
}  // namespace acpca
