// The evaluation library called directly, as a program other than the CLI
// would: the sweep, the equal-error comparison, the report and the studies.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/text.h"
#include "eval/analyze_study.h"
#include "eval/error_measures.h"
#include "eval/eval_study.h"
#include "eval/method_comparison.h"
#include "eval/method_sweep.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

namespace fs = std::filesystem;

class EvalLibrary : public test::SmallPlantSuite {};

TEST_F(EvalLibrary, SweepMeasuresEverySettingAgainstTheDenseRelight) {
  const TransportReader t(path());
  const EvaluationData data = loadEvaluationData(t, {"sky", "constant:1"});
  ASSERT_EQ(data.truth.size(), 2u);
  SweepSettings s;
  s.methods = {"global", "block"};
  s.globalEnergies = {1.0};
  s.tolerances = {1.0};
  s.blockSizes = {8};
  std::vector<std::string> logged;
  s.log = [&](const std::string& line) { logged.push_back(line); };
  const auto rows = sweepMethods(data, s);
  ASSERT_GE(rows.size(), 2u);                 // global (and its nested truncations), block B=8
  EXPECT_EQ(logged.size(), rows.size() + 1);  // one line per setting, one for the basis
  for (const auto& r : rows) {
    ASSERT_EQ(r.errors.size(), 2u);
    EXPECT_NEAR(r.imageError, aggregateError(r.errors), 1e-12);
    if (r.setting == "N" || r.setting == "B=8") {
      // Keeping every basis reproduces T: the relit images are the dense ones.
      EXPECT_LT(r.imageError, 1e-4) << r.method << " " << r.setting;
      EXPECT_LT(r.transportError, 1e-4);
    }
  }
  const Table table = methodsTable(rows);
  EXPECT_EQ(table.rows(), rows.size());
  EXPECT_EQ(table.columns().front(), "method");
  EXPECT_NE(methodComparisonText(rows, {}).find("cost @ 1%"), std::string::npos);
}

TEST(MethodComparison, TargetsOutsideASweepAreBoundsOrDashesNeverNan) {
  const auto row = [](const char* method, double error, double cost) {
    SweepResult r;
    r.method = method;
    r.imageError = error;
    r.costPerPixel = cost;
    return r;
  };
  // global and adaptive binary bracket 1%; both only overshoot 3% (bounds);
  // adaptive-quad reaches neither.
  const std::vector<SweepResult> rows{
      row("global", 0.02, 400), row("global", 0.005, 1600), row("adaptive-binary", 0.012, 100),
      row("adaptive-binary", 0.008, 300), row("adaptive-quad", 0.05, 50)};
  const std::string text = methodComparisonText(rows, {});
  EXPECT_EQ(text.find("nan"), std::string::npos) << text;
  EXPECT_NE(text.find("<= 400.0"), std::string::npos) << text;  // global at 3%
  EXPECT_NE(text.find("<= 100.0"), std::string::npos) << text;  // adaptive binary at 3%
  // 1%: log-log between the bracketing settings of each method.
  const double global =
      400 * std::pow(1600.0 / 400, std::log(0.01 / 0.02) / std::log(0.005 / 0.02));
  const double binary = 100 * std::pow(3.0, std::log(0.01 / 0.012) / std::log(0.008 / 0.012));
  EXPECT_NE(
      text.find(formatted("adaptive-binary        / global  : %.3f @1%%  - @3%%", binary / global)),
      std::string::npos)
      << text;
  EXPECT_NE(text.find("adaptive-quad          / global  : - @1%  - @3%"), std::string::npos)
      << text;
}

TEST_F(EvalLibrary, UnknownMethodsAndBadCountsAreParameterErrors) {
  EvalOptions o;
  o.methods = {"dense", "wavelets"};
  try {
    validateEvalOptions(o);
    FAIL();
  } catch (const ParameterError& e) {
    EXPECT_EQ(e.parameter(), "methods");
    EXPECT_EQ(e.value(), "wavelets");
  }
  o.methods = {"haar"};
  o.haarTerms = {0};
  EXPECT_THROW(validateEvalOptions(o), ParameterError);
  o.haarTerms = {10};
  o.shOrders = {10};  // not a square
  EXPECT_THROW(validateEvalOptions(o), ParameterError);
}

TEST_F(EvalLibrary, EvaluationWritesItsReportAndReturnsTheSameRows) {
  test::TempDir dir;
  const TransportReader t(path());
  EvalOptions o;
  o.envs = {"sky"};
  o.methods = {"dense", "global", "haar"};
  o.sweep.globalEnergies = {0.999};
  o.sweep.tolerances = {0.99};
  o.sweep.timingFrames = 1;
  o.haarTerms = {10};
  const EvalReport report = runEvaluation(t, o, dir.path().string());
  std::ifstream settings(dir.file("settings.csv"));
  int lines = 0;
  for (std::string line; std::getline(settings, line);) ++lines;
  EXPECT_EQ(lines, static_cast<int>(report.results.size()) + 1);
  EXPECT_TRUE(fs::exists(dir.file("summary.md")));
  EXPECT_TRUE(fs::exists(dir.file("images/truth.png")));
  for (const auto& r : report.results) EXPECT_TRUE(std::isfinite(r.imageError)) << r.method;
}

TEST_F(EvalLibrary, AnalysisFindsTheCheapestBlockItReports) {
  test::TempDir dir;
  const TransportReader t(path());
  AnalyzeOptions o;
  o.blocks = {4, 8, 16};
  const StudyOutput out = runAnalysis(t, o, dir.path().string());
  const auto& blocks = out.json["block_costs"];
  ASSERT_EQ(blocks.size(), 3u);
  double best = INFINITY;
  int bestSide = 0;
  for (const auto& b : blocks) {
    const double cost = b["cost_per_pixel"];
    EXPECT_NEAR(cost, b["global_to_local"].get<double>() + b["local_to_pixel"].get<double>(), 1e-9);
    if (cost < best) best = cost, bestSide = b["side"];
  }
  EXPECT_EQ(out.json["best_block_side"], bestSide);
  EXPECT_NE(out.summary.find("Measured optimum"), std::string::npos);
  AnalyzeOptions zeroBlock;
  zeroBlock.blocks = {0};
  EXPECT_THROW(validateAnalyzeOptions(zeroBlock), ParameterError);
}

}  // namespace
}  // namespace acpca
