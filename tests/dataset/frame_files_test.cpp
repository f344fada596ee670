// A batch's file names: the index first, wide enough to sort past 100,000
// frames, and the last guard against two frames meeting in one file.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "core/error.h"
#include "dataset/frame_files.h"

namespace acpca {
namespace {

TEST(FrameFiles, IndicesAreZeroPaddedSoNamesSortInBatchOrder) {
  EXPECT_EQ(frameIndexDigits(1), 5);
  EXPECT_EQ(frameIndexDigits(100000), 5);  // the last index is 99999
  EXPECT_EQ(frameIndexDigits(100001), 6);
  EXPECT_EQ(indexedFrameStem(42, 5, "sky_y15"), "00042_sky_y15");
  // Sorted as text, the names of a batch past 100,000 frames keep their order.
  const int digits = frameIndexDigits(123456);
  std::vector<std::string> names;
  for (long long i : {0LL, 9LL, 10LL, 99999LL, 100000LL, 123455LL})
    names.push_back(indexedFrameStem(i, digits, "b_y0"));
  EXPECT_TRUE(std::is_sorted(names.begin(), names.end()));
  EXPECT_EQ(names.back(), "123455_b_y0");
}

/// requireDistinctFiles over frames whose paths are `files[i]` and whose
/// lightings are "lighting i".
void checkFiles(const std::vector<std::vector<std::string>>& files) {
  requireDistinctFiles(
      files.size(), [&](size_t i) { return files[i]; },
      [](size_t i) { return "lighting " + std::to_string(i); });
}

TEST(FrameFiles, TwoFramesInOneFileAreRefusedNamingBothLightings) {
  EXPECT_NO_THROW(checkFiles({{"out/00000_x_y0.exr", "out/00000_x_y0_shading.exr"},
                              {"out/00001_x_y0.exr", "out/00001_x_y0_shading.exr"}}));
  // One path of three frames, and one frame's shading landing on another's frame.
  for (const auto& files : std::vector<std::vector<std::vector<std::string>>>{
           {{"out/x_y0.exr"}, {"out/sky_y0.exr"}, {"out/x_y0.exr"}},
           {{"out/a.exr", "out/x_y0.exr"}, {"out/sky_y0.exr"}, {"out/x_y0.exr", "out/b.exr"}}}) {
    try {
      checkFiles(files);
      FAIL() << "two frames were let into one file";
    } catch (const UserError& e) {
      const std::string message = e.what();
      for (const char* part : {"out/x_y0.exr", "lighting 0", "lighting 2"})
        EXPECT_NE(message.find(part), std::string::npos) << message;
      EXPECT_EQ(message.find("lighting 1"), std::string::npos) << message;
    }
  }
  // One frame writing one path twice is caught too.
  EXPECT_THROW(checkFiles({{"out/a.exr", "out/a.exr"}}), UserError);
}

}  // namespace
}  // namespace acpca
