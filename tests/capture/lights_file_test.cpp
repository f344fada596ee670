// Lights files: JSON and CSV, positions turned into directions, and every
// mistake refused with the file and the line or entry it is on.
#include <gtest/gtest.h>

#include "capture/lights_file.h"
#include "core/error.h"

namespace acpca {
namespace {

/// The message of the UserError that parsing `text` throws ("" if none).
std::string errorOf(const std::string& text, const std::string& path = "set/lights.csv") {
  try {
    parseLightsFile(text, path);
  } catch (const UserError& e) {
    return e.what();
  }
  return "";
}

TEST(LightsFile, ReadsCsvWithAndWithoutColours) {
  const LightsFile f =
      parseLightsFile("# a light stage\nimage,x,y,z\nolat_000.png, 0, 2, 0\nolat_001.png,1,0,0\n",
                      "set/lights.csv");
  ASSERT_EQ(f.lights.size(), 2u);
  EXPECT_EQ(f.lights[0].image, "olat_000.png");
  EXPECT_EQ(f.lights[0].imagePath, "set/olat_000.png");
  EXPECT_EQ(f.lights[0].direction, Eigen::Vector3d(0, 1, 0));  // normalised
  EXPECT_EQ(f.lights[0].irradiance, Eigen::Vector3d(1, 1, 1));
  EXPECT_FALSE(f.cellsGiven());

  const LightsFile c = parseLightsFile(
      "image,x,y,z,r,g,b,solid_angle\r\na.exr,0,0,1,2,3,4,0.5\r\nb.exr,0,0,-1,1,1,1,0.5\r\n",
      "lights.csv");
  EXPECT_EQ(c.lights[0].irradiance, Eigen::Vector3d(2, 3, 4));
  EXPECT_EQ(c.lights[0].imagePath, "a.exr");
  EXPECT_TRUE(c.cellsGiven());
  EXPECT_EQ(c.lights[0].solidAngle, 0.5);
}

TEST(LightsFile, ReadsJsonDirectionsAndPositions) {
  const LightsFile f = parseLightsFile(
      R"({"center": [0, 1, 0], "lights": [
            {"image": "a.exr", "direction": [0, 0, 3], "intensity": 2},
            {"image": "b.exr", "position": [0, 1, -5], "intensity": [1, 2, 3]}]})",
      "/data/lights.json");
  ASSERT_EQ(f.lights.size(), 2u);
  EXPECT_EQ(f.lights[0].direction, Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(f.lights[0].irradiance, Eigen::Vector3d(2, 2, 2));
  EXPECT_EQ(f.lights[1].direction, Eigen::Vector3d(0, 0, -1));  // from the centre to the lamp
  EXPECT_EQ(f.lights[1].irradiance, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(f.lights[1].imagePath, "/data/b.exr");
}

TEST(LightsFile, NamesTheLineOfEachMistake) {
  const std::string header = "image,x,y,z\n";
  EXPECT_EQ(errorOf(header + "a.png,0,0,0\n"),
            "set/lights.csv line 2: the light's direction is zero (it must point from the subject "
            "toward the light)");
  EXPECT_NE(errorOf(header + "a.png,0,1,0\nb.png,0,1,0\n")
                .find("line 3: the same direction as "
                      "set/lights.csv line 2"),
            std::string::npos);
  EXPECT_NE(errorOf(header + "a.png,0,1\n").find("line 2: 3 values, the header names 4"),
            std::string::npos);
  EXPECT_NE(errorOf(header + "a.png,0,1,0,7\n").find("line 2: 5 values"), std::string::npos);
  EXPECT_NE(errorOf(header + "a.png,0,up,0\n").find("line 2: y 'up' is not a finite number"),
            std::string::npos);
  EXPECT_NE(errorOf(header + "a.png,0,nan,0\n").find("line 2: y 'nan'"), std::string::npos);
  EXPECT_NE(errorOf("image,x,y\na.png,0,1\n").find("line 1: the header must name"),
            std::string::npos);
  EXPECT_NE(errorOf("image,x,y,z,r\n").find("give all of r, g and b"), std::string::npos);
  EXPECT_NE(errorOf("image,x,y,z,w\n").find("unknown column 'w'"), std::string::npos);
  EXPECT_NE(errorOf("image,x,y,z,r,g,b\na.png,0,1,0,1,0,1\n").find("intensity must be > 0"),
            std::string::npos);
  EXPECT_NE(errorOf("image,x,y,z,solid_angle\na.png,0,1,0,0.1\nb.png,1,0,0,-1\n")
                .find("line 3: give every light's solid_angle"),
            std::string::npos);
  EXPECT_NE(errorOf(header).find("lists no lights"), std::string::npos);
  // One light's cell would be the whole sphere: every relight its image scaled.
  EXPECT_NE(errorOf(header + "a.png,0,1,0\n")
                .find("set/lights.csv: 1 light(s); a light set needs at least 2"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"lights": [{"image": "a", "direction": [0, 1, 0]}]})", "l.json")
                .find("l.json: 1 light(s); a light set needs at least 2"),
            std::string::npos);
  EXPECT_NE(errorOf("").find("no header line"), std::string::npos);
  EXPECT_NE(errorOf(header + ",0,1,0\n").find("line 2: the image name is empty"),
            std::string::npos);
}

TEST(LightsFile, NamesTheEntryOfEachJsonMistake) {
  EXPECT_NE(errorOf(R"({"lights": [{"image": "a", "position": [0, 1, 0]}]})", "l.json")
                .find("l.json: lights[0]: a 'position' needs the subject's \"center\""),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"lights": [{"image": "a", "direction": [0, 1]}]})", "l.json")
                .find("lights[0].direction: expected 3 numbers"),
            std::string::npos);
  EXPECT_NE(
      errorOf(R"({"lights": [{"image": "a", "direction": [0, 1, 0], "colour": 1}]})", "l.json")
          .find("unknown key 'colour'"),
      std::string::npos);
  EXPECT_NE(
      errorOf(R"({"lights": [{"image": "a", "direction": [0, 1, 0], "position": [0, 1, 0]}]})",
              "l.json")
          .find("either 'direction' or 'position'"),
      std::string::npos);
  EXPECT_NE(errorOf(R"({"lights": [{"direction": [0, 1, 0]}]})", "l.json").find("'image'"),
            std::string::npos);
  EXPECT_NE(errorOf(R"({"lights": [)", "l.json").find("l.json: not valid JSON"), std::string::npos);
  EXPECT_NE(errorOf(R"({"light": []})", "l.json").find("unknown key 'light'"), std::string::npos);
}

}  // namespace
}  // namespace acpca
