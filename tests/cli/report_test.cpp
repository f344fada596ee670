// The report commands end to end on a tiny scene: every file they promise, one
// row per method and setting, numbers that hold together.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "relight/lamp_light.h"
#include "tests/cli/run_cli.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

using test::TempDir;
namespace fs = std::filesystem;

std::vector<std::vector<std::string>> readCsv(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> fields;
    std::string field;
    bool quoted = false;
    for (char c : line) {
      if (c == '"')
        quoted = !quoted;
      else if (c == ',' && !quoted)
        fields.push_back(field), field.clear();
      else
        field += c;
    }
    fields.push_back(field);
    rows.push_back(fields);
  }
  return rows;
}

class Reports : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    const RunResult p =
        runCli("precompute --scene plant --size 32x32 --cubemap 8 --quiet --out " + transport());
    ASSERT_EQ(p.status, 0) << p.output;
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string transport() { return dir_->file("t.h5"); }
  static TempDir* dir_;
};
TempDir* Reports::dir_ = nullptr;

TEST_F(Reports, EvalWritesEveryFileWithOneRowPerMethodSettingAndMap) {
  TempDir out;
  const std::string report = out.file("report");
  const RunResult r =
      runCli("eval " + transport() + " --env sky --env sun:50,30,4,1000 --out " + report +
             " --global-energies 0.999 --tolerances 0.99 --block-sizes 4,8 --cpca-clusters 5"
             " --haar-terms 10,40 --sh-orders 9,16 --sh-fits uls,cls --frames 2 --quiet --json " +
             out.file("eval.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* f : {"results.csv", "settings.csv", "results.json", "summary.md",
                        "error_vs_ms.png", "error_vs_cost.png", "images/truth.png"})
    EXPECT_TRUE(fs::exists(fs::path(report) / f)) << f;

  // One row per method and setting (global may add nested truncations of its
  // bases), and the CSVs agree with the JSON.
  const auto json = nlohmann::json::parse(std::ifstream(out.file("eval.json")));
  std::map<std::string, int> perMethod;
  for (const auto& row : json["results"]) {
    ++perMethod[row["method"]];
    EXPECT_EQ(row["maps"].size(), 2u);
    EXPECT_GT(row["cost_per_pixel"].get<double>(), 0) << row["method"];
    EXPECT_GT(row["ms_per_frame"].get<double>(), 0) << row["method"];
    EXPECT_GT(row["model_bytes"].get<double>(), 0) << row["method"];
  }
  EXPECT_EQ(perMethod["dense"], 1);
  EXPECT_EQ(perMethod["block"], 2);
  EXPECT_EQ(perMethod["cpca"], 1);
  EXPECT_EQ(perMethod["adaptive-quad"], 1);
  EXPECT_EQ(perMethod["adaptive-binary"], 1);
  EXPECT_EQ(perMethod["haar"], 2);
  EXPECT_EQ(perMethod["sh-uls"], 2);
  EXPECT_EQ(perMethod["sh-cls"], 2);
  EXPECT_EQ(perMethod.count("sh-ceb"), 0u);
  EXPECT_GE(perMethod["global"], 1);
  const auto settings = readCsv(report + "/settings.csv");
  const auto results = readCsv(report + "/results.csv");
  ASSERT_EQ(settings.size(), json["results"].size() + 1);
  ASSERT_EQ(results.size(), 2 * json["results"].size() + 1);
  // The columns users script against, as the first release wrote them.
  EXPECT_EQ(results[0],
            (std::vector<std::string>{"method", "setting", "env", "rel_l2", "psnr", "ms_per_frame",
                                      "cost_per_pixel", "model_bytes", "global_energy", "tolerance",
                                      "clusters", "compress_seconds"}));
  EXPECT_EQ(settings[0],
            (std::vector<std::string>{"method", "setting", "global_energy", "tolerance",
                                      "global_bases", "clusters", "image_error", "psnr_mean",
                                      "ms_per_frame", "cost_per_pixel", "model_bytes",
                                      "transport_error", "compress_seconds", "basis_seconds"}));
  for (const auto& row : results) EXPECT_EQ(row.size(), results[0].size());
  for (const auto& row : settings) EXPECT_EQ(row.size(), settings[0].size());

  // Each clustered method's best setting has a cluster map; every method has pictures.
  for (const auto& [method, count] : perMethod) {
    EXPECT_TRUE(fs::exists(report + "/images/" + method + "_relit.png")) << method;
    EXPECT_TRUE(fs::exists(report + "/images/" + method + "_error.png")) << method;
  }
  for (const char* m : {"block", "cpca", "adaptive-quad", "adaptive-binary"})
    EXPECT_TRUE(fs::exists(report + "/images/" + std::string(m) + "_clusters.png")) << m;

  // The dense relight is the ground truth; the aggregate is the RMS of the maps.
  for (const auto& row : json["results"]) {
    const double a = row["maps"][0]["rel_l2"], b = row["maps"][1]["rel_l2"];
    EXPECT_NEAR(row["image_error"].get<double>(), std::sqrt((a * a + b * b) / 2), 1e-9);
    if (row["method"] == "dense") {
      EXPECT_LT(row["image_error"].get<double>(), 1e-4);
    }
  }
  // Global PCA's lower ranks (its first k bases) have a transport error too:
  // larger for fewer bases, never below the whole model's.
  std::map<double, std::vector<std::pair<int, double>>> globalByEnergy;
  for (const auto& row : json["results"])
    if (row["method"] == "global") {
      ASSERT_TRUE(row["transport_error"].is_number()) << row["setting"];
      const std::string setting = row["setting"];
      const int k = setting.rfind("first ", 0) == 0 ? std::stoi(setting.substr(6)) : 1 << 30;
      globalByEnergy[row["global_energy"].get<double>()].push_back(
          {k, row["transport_error"].get<double>()});
    }
  for (auto& [energy, curve] : globalByEnergy) {
    std::sort(curve.begin(), curve.end());
    for (size_t i = 1; i < curve.size(); ++i) EXPECT_GE(curve[i - 1].second, curve[i].second);
  }
  std::stringstream summary;
  summary << std::ifstream(report + "/summary.md").rdbuf();
  EXPECT_NE(summary.str().find("## Who wins"), std::string::npos);
}

TEST_F(Reports, QuickEvalSweepsItsListsAndKeepsTheOnesGiven) {
  TempDir out;
  // --quick: one global energy (0.999) and tolerances 0.99, 0.999; a list on
  // the command line (here the block sides) wins over the quick one.
  const RunResult r = runCli("eval " + transport() + " --env sky --out " + out.file("r") +
                             " --quick --methods block,haar,adaptive-binary,cpca --block-sizes 4"
                             " --cpca-clusters 3 --frames 1 --quiet"
                             " --json " +
                             out.file("eval.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto json = nlohmann::json::parse(std::ifstream(out.file("eval.json")));
  std::set<std::pair<double, double>> blockSettings;
  std::set<std::string> haarSettings;
  for (const auto& row : json["results"]) {
    if (row["method"] == "block") {
      EXPECT_EQ(row["setting"], "B=4");
      blockSettings.insert({row["global_energy"].get<double>(), row["tolerance"].get<double>()});
    }
    if (row["method"] == "haar") haarSettings.insert(row["setting"].get<std::string>());
  }
  EXPECT_EQ(blockSettings, (std::set<std::pair<double, double>>{{0.999, 0.99}, {0.999, 0.999}}));
  EXPECT_EQ(haarSettings.size(), 2u);  // k = 50 and 200
  // CPCA with K = 3 and with as many clusters as adaptive binary found, at
  // both tolerances.
  int cpcaSettings = 0;
  for (const auto& row : json["results"]) cpcaSettings += row["method"] == "cpca";
  EXPECT_EQ(cpcaSettings, 4);
}

TEST_F(Reports, RelightBenchSetsEachFrameBesideItsOwnStreamingPass) {
  TempDir out;
  const std::string model = out.file("m.h5");
  ASSERT_EQ(runCli("compress " + transport() + " --method global --quiet --out " + model).status,
            0);
  const RunResult r = runCli("bench relight " + model + " --transport " + transport() +
                             " --env sky --frames 3 --dense-frames 1 --stream-gib 0.05 --quiet"
                             " --json " +
                             out.file("bench.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  const auto json = nlohmann::json::parse(std::ifstream(out.file("bench.json")));
  ASSERT_GE(json["relighters"].size(), 2u);  // the model at each kernel level, then dense
  for (const auto& row : json["relighters"]) {
    const std::string name = row["name"];
    EXPECT_GT(row["ms_per_frame_median"].get<double>(), 0) << name;
    EXPECT_GT(row["paired_stream_gb_per_s"].get<double>(), 0) << name;
    // bytes / ms over the paired pass's GB/s: finite, positive, and within a
    // factor of 2 of the frame's GB/s over the stream's (a median of ratios
    // against a ratio of medians over 3 frames: 1.52 apart on a loaded machine).
    const double paired = row["fraction_of_paired_stream"];
    EXPECT_TRUE(std::isfinite(paired) && paired > 0) << name;
    const double ratio =
        row["gb_per_s"].get<double>() / row["paired_stream_gb_per_s"].get<double>();
    EXPECT_LT(std::abs(std::log(paired / ratio)), std::log(2.0))
        << name << ": " << paired << " against " << ratio;
  }
  const auto& first = json["relighters"][0];
  EXPECT_LT(first["relative_l2_vs_dense"].get<double>(), 0.2);
}

TEST_F(Reports, BatchBenchSaysWhereABatchsTimeWent) {
  TempDir out;
  const std::string model = out.file("m.h5");
  ASSERT_EQ(
      runCli("compress " + transport() + " --method adaptive-quad --quiet --out " + model).status,
      0);
  const RunResult r =
      runCli("bench batch " + model + " --env sky --env constant:1 --rotate 0:360:30" +
             " --format png --stream-gib 0.05 --out " + out.file("frames") + " --json " +
             out.file("bench.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* line :
       {"projection", "writing (own threads)", "frames/s end to end", "streaming read"})
    EXPECT_NE(r.output.find(line), std::string::npos) << line << "\n" << r.output;
  const auto json = nlohmann::json::parse(std::ifstream(out.file("bench.json")));
  EXPECT_EQ(json["frames"].get<int>(), 24);
  const double endToEnd = json["frames_per_second"],
               alone = json["relight_alone_frames_per_second"];
  EXPECT_GT(endToEnd, 0);
  EXPECT_GE(alone, endToEnd) << "the relight alone is part of the batch";
  EXPECT_GT(json["streaming_read_gb_per_s"].get<double>(), 0);
  EXPECT_EQ(json["batch"]["outputs"].size(), 24u);
  EXPECT_TRUE(fs::exists(out.file("frames") + "/manifest.csv"));
  // The first map's stages alone, one frame per rotation.
  EXPECT_NE(r.output.find("alone, nothing beside them (the first map under 12 rotation(s)"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(json["alone_ms_per_frame"]["frames"].get<int>(), 12);
  EXPECT_GT(json["alone_ms_per_frame"]["lighting"].get<double>(), 0);
  EXPECT_GT(json["alone_ms_per_frame"]["background"].get<double>(), 0);
  // The sky's sun lit exactly, against the same frame through the lattice.
  ASSERT_TRUE(json.contains("sources_alone")) << r.output;
  const auto& sun = json["sources_alone"];
  EXPECT_EQ(sun["sources"].get<int>(), 1);
  EXPECT_EQ(sun["lamp_rays"].get<int>(), kDefaultSphereLampRays);
  EXPECT_GT(sun["shadow_rays_per_frame"].get<double>(), 0);
  const double relight = json["alone_ms_per_frame"]["relight"],
               background = json["alone_ms_per_frame"]["background"];
  EXPECT_NEAR(sun["exact_frame_ms"].get<double>(),
              sun["rest_lighting_ms_per_frame"].get<double>() + relight + background +
                  sun["ms_per_frame"].get<double>(),
              1e-9);
  EXPECT_NEAR(sun["lattice_frame_ms"].get<double>(),
              json["alone_ms_per_frame"]["lighting"].get<double>() + relight + background, 1e-9);
  EXPECT_NE(r.output.find("with / lattice"), std::string::npos) << r.output;
}

TEST_F(Reports, CodecBenchTimesEveryBatchFormatAgainstOpenImageIO) {
  TempDir out;
  const std::string frame = out.file("frame.exr");
  ASSERT_EQ(runCli("relight " + transport() + " --env sky --quiet --out " + frame).status, 0);
  const RunResult r = runCli("bench codecs " + frame + " --repeats 2 --stream-gib 0.05 --dir " +
                             out.path().string() + " --json " + out.file("codecs.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("streaming read"), std::string::npos) << r.output;
  const auto json = nlohmann::json::parse(std::ifstream(out.file("codecs.json")));
  ASSERT_EQ(json["codecs"].size(), 8u);
  for (const auto& row : json["codecs"]) {
    EXPECT_GT(row["imageio_ms"].get<double>(), 0) << row;
    EXPECT_GT(row["openimageio_ms"].get<double>(), 0) << row;
    // Lossless both: within a tenth of each other's size.
    EXPECT_NEAR(row["bytes"].get<double>(), row["openimageio_bytes"].get<double>(),
                0.1 * row["openimageio_bytes"].get<double>())
        << row;
  }
  // Nothing left behind in the directory but the frame and the report.
  int files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(out.path())) ++files;
  EXPECT_EQ(files, 2);
  EXPECT_NE(runCli("bench codecs " + out.file("none.exr")).status, 0);
}

TEST_F(Reports, RelightBenchRefusesFilesOfAnotherImageByName) {
  TempDir out;
  const std::string model = out.file("m.h5"), other = out.file("other.h5");
  ASSERT_EQ(runCli("compress " + transport() + " --method global --quiet --out " + model).status,
            0);
  ASSERT_EQ(runCli("precompute --scene plant --size 24x24 --cubemap 8 --quiet --out " +
                   out.file("t24.h5"))
                .status,
            0);
  ASSERT_EQ(
      runCli("compress " + out.file("t24.h5") + " --method global --quiet --out " + other).status,
      0);
  expectFailure("bench relight " + model + " --baseline " + other + " --frames 1",
                "other.h5: covers");
  expectFailure("bench relight " + model + " --transport " + out.file("t24.h5") + " --frames 1",
                "t24.h5: covers");
}

TEST_F(Reports, EvalRefusesUnknownMethodsBeforeWorking) {
  TempDir out;
  expectFailure("eval " + transport() + " --methods global,wavelets --out " + out.file("r"),
                "--methods 'wavelets'");
  expectFailure("eval " + out.file("missing.h5") + " --out " + out.file("r"), "missing.h5");
}

TEST_F(Reports, QuantizationTablesHoldTheBoundsTheFitsPromise) {
  TempDir out;
  const std::string report = out.file("q");
  const RunResult r = runCli("bench quantization " + transport() + " --env sky --out " + report +
                             " --sh-orders 16,25 --methods global,cpca --cpca-clusters 4 --quiet"
                             " --json " +
                             out.file("q.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* f : {"sh.csv", "models.csv", "summary.md"})
    EXPECT_TRUE(fs::exists(fs::path(report) / f)) << f;
  const auto json = nlohmann::json::parse(std::ifstream(out.file("q.json")));
  ASSERT_EQ(json["sh"].size(), 6u);  // 2 orders x (uls, cls, ceb)
  for (const auto& row : json["sh"]) {
    // CLS and CEB keep |c|^2 within E_c (eq. 17); every stored variant is finite.
    if (row["fit"] != "uls") {
      EXPECT_LE(row["max_norm_to_bound"].get<double>(), 1 + 1e-5);
    }
    for (const char* s : {"f32", "f16", "i8"}) {
      EXPECT_TRUE(row["stored"][s]["psnr"].is_number()) << row["fit"] << " " << s;
      EXPECT_LT(row["stored"][s]["rel_l2"].get<double>(), 1.0) << row["fit"] << " " << s;
    }
  }
  ASSERT_EQ(json["models"].size(), 2u);
  for (const auto& row : json["models"]) {
    // Orthonormal bases: no coefficient vector is longer than its row and cluster mean.
    EXPECT_LE(row["max_norm_to_bound"].get<double>(), 1 + 1e-4) << row["method"];
    const double f32 = row["stored"]["f32"]["rel_l2"], f16 = row["stored"]["f16"]["rel_l2"],
                 i8 = row["stored"]["i8"]["rel_l2"];
    EXPECT_NEAR(f16, f32, 1e-3) << row["method"];
    EXPECT_GE(i8, f32 * 0.99) << row["method"];
    EXPECT_GT(row["stored"]["f32"]["bytes"].get<double>(),
              row["stored"]["i8"]["bytes"].get<double>());
  }
  const RunResult bad =
      runCli("bench quantization " + transport() + " --out " + report + "2 --sh-orders 50");
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.output.find("--sh-orders '50'"), std::string::npos) << bad.output;
  expectFailure("bench quantization " + transport() + " --out " + report + "3 --sh-groups 0",
                "--sh-groups");
}

TEST_F(Reports, AnalyzeReportsSlopesBlockCostsAndAConsistentOptimum) {
  TempDir out;
  const std::string report = out.file("analysis");
  const RunResult r =
      runCli("analyze " + transport() + " --out " + report +
             " --blocks 2,4,8 --centre 16,20 --centre 8,8 --quiet --json " + out.file("a.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* f : {"dimensionality.csv", "slopes.csv", "block_cost.csv", "analysis.json",
                        "summary.md", "dimensionality.png", "block_cost.png"})
    EXPECT_TRUE(fs::exists(fs::path(report) / f)) << f;
  const auto j = nlohmann::json::parse(std::ifstream(out.file("a.json")));
  ASSERT_EQ(j["centres"].size(), 2u);
  EXPECT_EQ(j["centres"][0]["x"], 16);
  const double slope = j["mean_slope"], n = j["global_bases"];
  EXPECT_GT(slope, 0.0);
  EXPECT_NEAR(j["mu_r4"].get<double>(), std::pow(4.0, -slope), 1e-12);
  EXPECT_NEAR(j["mu_r2"].get<double>(), std::pow(2.0, -slope), 1e-12);
  const double mu = j["mu_r4"];
  EXPECT_NEAR(j["p_star_r4"].get<double>(), n * (4 * mu - 1) / (1 - mu), 1e-6 * n);
  // The measured optimum is the cheapest block of the table.
  double cheapest = INFINITY;
  int side = 0;
  ASSERT_EQ(j["block_costs"].size(), 3u);
  for (const auto& b : j["block_costs"]) {
    const double total = b["cost_per_pixel"];
    EXPECT_NEAR(total, b["global_to_local"].get<double>() + b["local_to_pixel"].get<double>(),
                1e-9 * total);
    if (total < cheapest) cheapest = total, side = b["side"];
  }
  EXPECT_EQ(j["best_block_side"], side);
  expectFailure("analyze " + transport() + " --out " + out.file("x") + " --centre 99,3",
                "outside the 32x32 image");
  expectFailure("analyze " + transport() + " --out " + out.file("x") + " --centre 3", "X,Y");
}

TEST_F(Reports, ScalingReportsEverySizeWithItsRatioAndPrediction) {
  TempDir out;
  const std::string report = out.file("scaling");
  const RunResult r = runCli(
      "bench scaling --scene plant --sizes 16,32 --cubemap 4 --frames 2 "
      "--quiet --out " +
      report + " --json " + out.file("s.json"));
  ASSERT_EQ(r.status, 0) << r.output;
  for (const char* f : {"scaling.csv", "summary.md", "scaling.png"})
    EXPECT_TRUE(fs::exists(fs::path(report) / f)) << f;
  EXPECT_FALSE(fs::exists(fs::path(report) / "transport_16.h5")) << "transports are removed";
  const auto j = nlohmann::json::parse(std::ifstream(out.file("s.json")));
  ASSERT_EQ(j["sizes"].size(), 2u);
  const auto& a = j["sizes"][0];
  const auto& b = j["sizes"][1];
  EXPECT_EQ(a["pixels"], 256);
  EXPECT_EQ(b["pixels"], 1024);
  EXPECT_NEAR(b["cost_ratio"].get<double>(),
              b["total_cost"].get<double>() / a["total_cost"].get<double>(), 1e-9);
  const double mu = a["mu"];
  EXPECT_NEAR(b["predicted_ratio"].get<double>(), 4 * mu * mu, 1e-12);
  EXPECT_NEAR(b["total_cost"].get<double>(),
              b["cost_per_pixel"].get<double>() * b["occupied_pixels"].get<double>(),
              1e-6 * b["total_cost"].get<double>());
  EXPECT_GT(b["ms_per_frame"].get<double>(), 0.0);
  expectFailure("bench scaling --scene plant --sizes 16,3 --out " + report, "--sizes '3'");
}

}  // namespace
}  // namespace acpca
