// A batch's specs are parsed once: the plan parses every light and format,
// the lightings are loaded once each, and relighting takes the plan (the
// counters of lighting/spec_parsing.h spied on across a whole run).
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "dataset/batch_relight.h"
#include "lighting/spec_parsing.h"
#include "tests/temp_dir.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

struct Counts {
  long long lights, sweeps, lightings, formats;
};

Counts countsNow() {
  const SpecParseCounts& c = specParseCounts();
  return {c.lights.load(), c.lightSweeps.load(), c.lightings.load(), c.formats.load()};
}

Counts since(const Counts& before) {
  const Counts now = countsNow();
  return {now.lights - before.lights, now.sweeps - before.sweeps, now.lightings - before.lightings,
          now.formats - before.formats};
}

TEST(BatchPlan, ARunParsesEachLightLightingAndFormatSpecOnce) {
  test::TempDir dir;
  BatchRelightOptions a;
  a.input = test::fixture("small-plant");
  a.envs = {"sky", "constant:0.5"};
  // A sweep of four positions and a fixed sphere: four light sets.
  a.lights = {"point:-2:2:1,3,1,40", "sphere:0,3,2,0.2,100"};
  a.format = "exr,png";
  a.out = dir.file("frames");
  const Counts before = countsNow();
  const BatchPlan plan = planBatchRelight(a);
  ASSERT_EQ(plan.lightSets.size(), 4u);
  ASSERT_EQ(plan.formats.size(), 2u);
  const BatchRelightResult result = relightBatch(a, plan);
  EXPECT_EQ(result.frames, 2 * 4);
  const Counts run = since(before);
  EXPECT_EQ(run.sweeps, 2) << "each --light expanded once";
  EXPECT_EQ(run.lights, 4 + 1) << "each expanded light parsed once";
  EXPECT_EQ(run.lightings, 2) << "each map loaded once";
  EXPECT_EQ(run.formats, 1) << "the format list parsed once";

  // The manifest writes the plan's lights, in the grammar they parse back by.
  std::ifstream in(dir.file("frames/manifest.jsonl"));
  const std::string manifest((std::istreambuf_iterator<char>(in)),
                             std::istreambuf_iterator<char>());
  for (const auto& set : plan.lightSets)
    for (const LocalLight& light : set)
      EXPECT_NE(manifest.find(light.canonicalSpec()), std::string::npos) << light.spec;
}

TEST(BatchPlan, TheOneCallFormPlansOnceToo) {
  test::TempDir dir;
  BatchRelightOptions a;
  a.input = test::fixture("small-plant");
  a.envs = {"sky"};
  a.lights = {"spot:0,3,0,0,-1,0,30,80"};
  a.out = dir.file("frame.exr");
  const Counts before = countsNow();
  relightBatch(a);
  const Counts run = since(before);
  EXPECT_EQ(run.sweeps, 1);
  EXPECT_EQ(run.lights, 1);
  EXPECT_EQ(run.lightings, 1);
  EXPECT_EQ(run.formats, 1);
}

}  // namespace
}  // namespace acpca
