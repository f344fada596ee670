#include "eval/error_measures.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>

#include "tests/temp_dir.h"

namespace acpca {
namespace {

TEST(Evaluation, TheDefaultSetFindsItsHdrisAlongTheSearchPath) {
  test::TempDir a, b;
  for (const char* name : {"b.exr", "a.hdr", "notes.txt"}) std::ofstream(a.file(name)) << "x";
  std::ofstream(b.file("c.exr")) << "x";
  const char* saved = std::getenv("ACPCA_HDRI_PATH");
  const std::string previous = saved ? saved : "";
  setenv("ACPCA_HDRI_PATH", (a.path().string() + ":" + b.path().string()).c_str(), 1);
  EXPECT_EQ(hdriSearchPath(), (std::vector<std::string>{a.path().string(), b.path().string()}));
  // Two analytic maps, then the first three maps along the path, by name.
  EXPECT_EQ(defaultEvaluationSet(),
            (std::vector<std::string>{"sky", "sun:50,30,4,1000", a.file("a.hdr"), a.file("b.exr"),
                                      b.file("c.exr")}));
  setenv("ACPCA_HDRI_PATH", "", 1);
  EXPECT_EQ(defaultEvaluationSet(), (std::vector<std::string>{"sky", "sun:50,30,4,1000"}));
  if (saved)
    setenv("ACPCA_HDRI_PATH", previous.c_str(), 1);
  else
    unsetenv("ACPCA_HDRI_PATH");
}

TEST(Evaluation, ErrorMeasures) {
  const std::vector<float> ref{1, 2, 3, 4}, same = ref, off{1, 2, 3, 5};
  EXPECT_EQ(relativeL2(same, ref), 0);
  EXPECT_NEAR(relativeL2(off, ref), 1 / std::sqrt(30.0), 1e-12);
  EXPECT_NEAR(psnr(off, ref), 20 * std::log10(4 / std::sqrt(0.25)), 1e-9);
  EXPECT_NEAR(aggregateError({0.03, 0.04}), std::sqrt((0.0009 + 0.0016) / 2), 1e-12);
}

TEST(Evaluation, MedianIsTheMiddleValueAndTheUpperOfAnEvenCount) {
  EXPECT_EQ(median({3, 1, 2}), 2);
  EXPECT_EQ(median({4, 1, 3, 2}), 3);
  EXPECT_EQ(median({}), 0);
}

TEST(Evaluation, CostAtErrorInterpolatesTheParetoFrontInLogLog) {
  // cost = 100 / error on the front, plus a dominated setting that must be ignored.
  std::vector<ErrorCostPoint> points{{0.001, 100000}, {0.01, 10000}, {0.1, 1000}, {0.02, 50000}};
  EXPECT_NEAR(costAtError(points, 0.01), 10000, 1e-6);
  EXPECT_NEAR(costAtError(points, 0.03), 100.0 / 0.03, 1e-6);  // on the line cost = 100 / error
  EXPECT_LT(costAtError(points, 0.5), 0);                      // beyond the sweep
  EXPECT_LT(costAtError(points, 0.0001), 0);                   // below the sweep
}

TEST(Evaluation, CostBoundAtErrorIsTheCheapestSettingAlreadyThatAccurate) {
  // Every setting below 1%: reaching 1% costs at most the cheapest of them.
  const std::vector<ErrorCostPoint> accurate{{0.008, 420}, {0.006, 760}, {0.009, 500}};
  EXPECT_LT(costAtError(accurate, 0.01), 0);
  EXPECT_EQ(costBoundAtError(accurate, 0.01), 420);
  EXPECT_EQ(costBoundAtError(accurate, 0.007), 760);  // only one setting that accurate
  EXPECT_LT(costBoundAtError(accurate, 0.005), 0);    // none
}

}  // namespace
}  // namespace acpca
