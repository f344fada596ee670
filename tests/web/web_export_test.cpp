// `adaptive-cpca web`'s export: the packed model relights as the model does,
// at its stored precision and rank limit, over the directions some pixel
// sees; the maps go as the CLI reads them; the directory guard.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "core/half.h"
#include "imageio/image_output.h"
#include "lighting/environment.h"
#include "lighting/envmap_export.h"
#include "lighting/lighting.h"
#include "model/model_file.h"
#include "relight/model_relighter.h"
#include "tests/cli/run_cli.h"
#include "tests/temp_dir.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

namespace fs = std::filesystem;
using test::fixture;
using test::readFile;
using test::TempDir;
using test::writeFile;

struct Site {
  nlohmann::json manifest;
  std::vector<unsigned char> bin;
  template <typename T>
  std::vector<T> array(const std::string& name) const {
    const auto& entry = manifest["arrays"][name];
    const size_t offset = entry["offset"], count = entry["count"];
    EXPECT_EQ(offset % 8, 0u) << name;
    EXPECT_LE(offset + count * sizeof(T), bin.size()) << name;
    std::vector<T> values(count);
    std::memcpy(values.data(), bin.data() + offset, count * sizeof(T));
    return values;
  }
};

Site readSite(const std::string& dir) {
  Site site;
  std::ifstream json(dir + "/model.json");
  site.manifest = nlohmann::json::parse(json);
  std::ifstream bin(dir + "/model.bin", std::ios::binary);
  site.bin.assign(std::istreambuf_iterator<char>(bin), {});
  return site;
}

std::vector<float> widened(const Site& site, const std::string& name) {
  const std::string type = site.manifest["arrays"][name]["type"];
  if (type == "f32") return site.array<float>(name);
  std::vector<float> out;
  if (type == "f16") {
    const auto h = site.array<std::uint16_t>(name);
    out.resize(h.size());
    halfToFloat(h.data(), out.data(), h.size());
  } else {
    for (std::int8_t q : site.array<std::int8_t>(name)) out.push_back(q);
  }
  return out;
}

/// Each row's relit RGB (cluster order) from the site's arrays, in doubles:
/// albedo (u . scale W^T V^T L + mean . V^T L), as the page's passes compute it.
std::vector<double> relitFromSite(const Site& site, const LatticeLighting& lighting) {
  const auto& m = site.manifest;
  const int n = m["global_bases"], channels = m["channels"];
  const auto seen = site.array<std::int32_t>("seen_texels");
  const auto basis = site.array<float>("global_basis");
  const size_t width = channels * seen.size();
  std::vector<double> g(3 * n, 0.0);
  for (int k = 0; k < n; ++k)
    for (size_t i = 0; i < width; ++i) {
      const size_t s = i % seen.size(), c = i / seen.size();
      for (int ch = 0; ch < 3; ++ch)
        if (channels == 1 || static_cast<int>(c) == ch) {
          g[3 * k + ch] += basis[k * width + i] * lighting[3 * seen[s] + ch];
        }
    }
  const auto ranks = site.array<std::int32_t>("cluster_rank");
  const auto rows = site.array<std::int32_t>("cluster_rows");
  const auto bases = widened(site, "bases"), coefficients = widened(site, "coefficients");
  const auto scale = site.array<float>("coefficient_scale");
  const auto albedo = site.array<float>("albedo");
  const std::vector<float> means = m["has_mean"] ? widened(site, "means") : std::vector<float>();
  std::vector<double> out;
  size_t basisAt = 0, coefficientAt = 0, row = 0;
  for (size_t c = 0; c < ranks.size(); ++c) {
    std::vector<double> towards(3 * ranks[c] + 3, 0.0);
    for (int b = 0; b <= ranks[c]; ++b)
      for (int k = 0; k < n; ++k) {
        const bool mean = b == ranks[c];
        if (mean && means.empty()) break;
        const double w =
            mean ? means[c * n + k] : bases[(basisAt + b) * n + k] * scale[basisAt + b];
        for (int ch = 0; ch < 3; ++ch) towards[3 * b + ch] += w * g[3 * k + ch];
      }
    for (int r = 0; r < rows[c]; ++r, ++row) {
      double v[3] = {towards[3 * ranks[c]], towards[3 * ranks[c] + 1], towards[3 * ranks[c] + 2]};
      for (int b = 0; b < ranks[c]; ++b)
        for (int ch = 0; ch < 3; ++ch)
          v[ch] += coefficients[coefficientAt + b] * towards[3 * b + ch];
      coefficientAt += ranks[c];
      for (int ch = 0; ch < 3; ++ch) out.push_back(albedo[3 * row + ch] * v[ch]);
    }
    basisAt += ranks[c];
  }
  return out;
}

/// The model's own relight of `lighting`, rows put in cluster order.
std::vector<double> relitByModel(const Model& model, const LatticeLighting& lighting, int maxRank) {
  ModelRelighter relighter(model);
  relighter.setMaxRank(maxRank);
  const std::vector<float> rgb = relighter.relight(lighting);
  std::vector<double> out;
  for (std::int32_t row : model.clusterRows)
    for (int ch = 0; ch < 3; ++ch) out.push_back(rgb[3 * row + ch]);
  return out;
}

double relativeError(const std::vector<double>& a, const std::vector<double>& b) {
  double diff = 0, norm = 0;
  for (size_t i = 0; i < a.size(); ++i) diff += (a[i] - b[i]) * (a[i] - b[i]), norm += b[i] * b[i];
  return std::sqrt(diff / norm);
}

class WebExport : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const RunResult r = runCli(concat("compress ", fixture("small-plant"),
                                      " --method adaptive-binary --coeffs i8 --bases f16 --out ",
                                      dir_->file("model.h5"), " --quiet"));
    ASSERT_EQ(r.status, 0) << r.output;
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string model() { return dir_->file("model.h5"); }
  static TempDir* dir_;
};
TempDir* WebExport::dir_ = nullptr;

TEST_F(WebExport, PacksTheModelAtItsStoredPrecisionOverTheDirectionsPixelsSee) {
  const std::string out = dir_->file("site");
  const RunResult r = runCli(concat("web ", model(), " --out ", out, " --quiet"));
  ASSERT_EQ(r.status, 0) << r.output;
  const Site site = readSite(out);
  EXPECT_EQ(site.manifest["arrays"]["coefficients"]["type"], "i8");
  EXPECT_EQ(site.manifest["arrays"]["bases"]["type"], "f16");
  const Model m = readModel(model());
  // Left out: exactly the texels where V_g is zero in every channel.
  const auto seen = site.array<std::int32_t>("seen_texels");
  const int l = m.geometry.latticeSize();
  EXPECT_LT(seen.size(), static_cast<size_t>(l)) << "the plant's floor hides the lower directions";
  std::vector<bool> isSeen(l, false);
  for (std::int32_t j : seen) isSeen[j] = true;
  for (int j = 0; j < l; ++j) {
    if (!isSeen[j]) {
      EXPECT_FALSE(m.globalBasis.row(j).any()) << "texel " << j;
    }
  }
  // Under random lightings the packed arrays relight as the model does.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(0, 1);
  for (int trial = 0; trial < 3; ++trial) {
    LatticeLighting lighting(3 * l);
    for (double& v : lighting) v = uniform(random);
    const double error =
        relativeError(relitFromSite(site, lighting), relitByModel(m, lighting, -1));
    EXPECT_LT(error, 1e-5);
  }
  for (const char* file : {"index.html", "main.js", "gpu_relighter.js", "site.json"})
    EXPECT_TRUE(fs::exists(out + "/" + file)) << file;
}

TEST_F(WebExport, KeepsEachClustersFirstBasesUnderMaxRank) {
  const std::string out = dir_->file("site-rank");
  ASSERT_EQ(runCli(concat("web ", model(), " --max-rank 2 --out ", out, " --quiet")).status, 0);
  const Site site = readSite(out);
  const Model m = readModel(model());
  const auto ranks = site.array<std::int32_t>("cluster_rank");
  for (size_t c = 0; c < ranks.size(); ++c) EXPECT_EQ(ranks[c], std::min(2, m.ranks[c]));
  LatticeLighting lighting(3 * m.geometry.latticeSize(), 0.5);
  EXPECT_LT(relativeError(relitFromSite(site, lighting), relitByModel(m, lighting, 2)), 1e-5);
}

TEST_F(WebExport, WritesALatLongMapsPixelsAsTheCliReadsThem) {
  const std::string map = "/usr/share/blender/datafiles/studiolights/world/courtyard.exr";
  const std::string out = dir_->file("site-map");
  ASSERT_EQ(
      runCli(concat("web ", model(), " --env sky --env ", map, " --out ", out, " --quiet")).status,
      0);
  const Site site = readSite(out);
  ASSERT_EQ(site.manifest["maps"].size(), 2u);
  EXPECT_EQ(site.manifest["maps"][0]["spec"], "sky");
  const auto& entry = site.manifest["maps"][1];
  const auto env = loadEnvironment(map);
  const LatLongPixels* pixels = env->latLong();
  ASSERT_NE(pixels, nullptr);
  EXPECT_EQ(entry["width"], pixels->width);
  EXPECT_EQ(entry["height"], pixels->height);
  const std::string bytes = readFile(out + "/" + entry["file"].get<std::string>());
  ASSERT_EQ(bytes.size(), 12u * pixels->width * pixels->height);
  EXPECT_EQ(std::memcmp(bytes.data(), pixels->rgb, bytes.size()), 0);
}

TEST_F(WebExport, RewritesItsOwnDirectoryAndNoOther) {
  const std::string out = dir_->file("site-guard");
  const std::string map = "/usr/share/blender/datafiles/studiolights/world/forest.exr";
  ASSERT_EQ(
      runCli(concat("web ", model(), " --env sky --env ", map, " --out ", out, " --quiet")).status,
      0);
  EXPECT_TRUE(fs::exists(out + "/maps/map-1.bin"));
  // Again with one map: its own files are rewritten, the one it no longer writes removed.
  ASSERT_EQ(runCli(concat("web ", model(), " --out ", out, " --quiet")).status, 0);
  EXPECT_FALSE(fs::exists(out + "/maps/map-1.bin"));
  writeFile(out + "/notes.txt", "mine");
  expectFailure(concat("web ", model(), " --out ", out), "notes.txt, which no web export wrote");
  EXPECT_EQ(readFile(out + "/notes.txt"), "mine");
}

TEST_F(WebExport, RefusesWhatThePageCannotRelight) {
  TempDir dir;
  expectFailure(concat("web ", fixture("small-plant"), " --out ", dir.file("a")),
                "not a model file");
  expectFailure(concat("web ", model(), " --max-rank x --out ", dir.file("b")), "--max-rank 'x'");
  expectFailure(concat("web ", model(), " --env missing.hdr --out ", dir.file("c")), "missing.hdr");
  // A cube cross: the page integrates lat-long maps only.
  const CubeLattice lattice(8);
  LatticeLighting lighting(3 * lattice.size(), 1.0);
  writeImage(latticeToCross(lighting, lattice, 16), dir.file("cross.exr"), ImageFormat::Exr, 0,
             true);
  expectFailure(concat("web ", model(), " --env ", dir.file("cross.exr"), " --out ", dir.file("d")),
                "lat-long maps (2:1) only");
  EXPECT_FALSE(fs::exists(dir.file("d") + "/model.json"));
}

}  // namespace
}  // namespace acpca
