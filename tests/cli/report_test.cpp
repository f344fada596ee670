// The report commands end to end on a tiny scene: every file they promise, one
// row per method and setting, numbers that hold together.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

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
             " --haar-terms 10,40 --frames 2 --quiet --json " +
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
  EXPECT_GE(perMethod["global"], 1);
  const auto settings = readCsv(report + "/settings.csv");
  const auto results = readCsv(report + "/results.csv");
  ASSERT_EQ(settings.size(), json["results"].size() + 1);
  ASSERT_EQ(results.size(), 2 * json["results"].size() + 1);
  EXPECT_EQ(results[0][0], "method");
  EXPECT_EQ(results[0][2], "env");
  EXPECT_EQ(results[0][3], "rel_l2");
  EXPECT_EQ(results[0][4], "psnr");

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
  std::stringstream summary;
  summary << std::ifstream(report + "/summary.md").rdbuf();
  EXPECT_NE(summary.str().find("## Who wins"), std::string::npos);
}

TEST_F(Reports, EvalRefusesUnknownMethodsBeforeWorking) {
  TempDir out;
  expectFailure("eval " + transport() + " --methods global,wavelets --out " + out.file("r"),
                "unknown method 'wavelets'");
  expectFailure("eval " + out.file("missing.h5") + " --out " + out.file("r"), "missing.h5");
}

}  // namespace
}  // namespace acpca
