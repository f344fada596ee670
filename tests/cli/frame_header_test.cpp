// Frames that describe themselves (docs/formats.md, "Frame metadata"): the
// header's camera against the position labels, OpenEXR's and OpenImageIO's
// own tools reading it, and the manifest and the headers saying the same.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "imageio/frame_metadata.h"
#include "tests/cli/run_cli.h"
#include "tests/cli/sphere_floor_scene.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

using test::TempDir;

std::vector<std::string> orbitViews(const TempDir& dir) {
  std::ofstream(dir.file("orbit.json"))
      << R"({"cameras": {"orbit": {"target": [0, 0.5, 0], "radius": 5, "elevation_deg": 20,
            "count": 3, "fov": 30, "width": 24, "height": 16}}, )"
      << test::kSphereOnFloorObjects << "}";
  const RunResult r = runCli("precompute --scene " + dir.file("orbit.json") +
                             " --cubemap 4 --spp 1 --quiet --out " + dir.file("t.h5"));
  EXPECT_EQ(r.status, 0) << r.output;
  return {dir.file("t_v00.h5"), dir.file("t_v01.h5"), dir.file("t_v02.h5")};
}

std::vector<float> channels(const std::string& path, const std::vector<std::string>& names,
                            int& width, int& height) {
  OIIO::ImageBuf image(path);
  const OIIO::ImageSpec& spec = image.spec();
  width = spec.width, height = spec.height;
  std::vector<float> all(static_cast<size_t>(width) * height * spec.nchannels);
  image.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, all.data());
  std::vector<float> out;
  for (size_t p = 0; p < all.size() / spec.nchannels; ++p)
    for (const std::string& name : names)
      out.push_back(all[p * spec.nchannels + spec.channelindex(name)]);
  return out;
}

// Every covered pixel's position label, projected through its frame's
// worldToNDC (OpenEXR's conventions: row vectors, divide by w, (0, 0) at the
// top left), lands on its pixel's centre: a camera check by the labels, not
// by our camera code.
TEST(FrameHeaders, PositionsLandOnTheirPixelCentresThroughWorldToNdc) {
  TempDir dir;
  const std::vector<std::string> views = orbitViews(dir);
  ASSERT_EQ(runCli("relight " + views[0] + " " + views[1] + " " + views[2] +
                   " --env sky --aov position,mask --quiet --out " + dir.file("set"))
                .status,
            0);
  for (int v = 0; v < 3; ++v) {
    const nlohmann::json header =
        readFrameMetadata(dir.file(concat("set/0000", v, "_v0", v, "_sky_y0.exr")));
    ASSERT_TRUE(header.contains("worldToNDC")) << header.dump();
    const std::vector<float> m = header["worldToNDC"].get<std::vector<float>>();
    int width = 0, height = 0;
    const std::vector<float> labels = channels(dir.file(concat("set/labels_v0", v, ".exr")),
                                               {"P.X", "P.Y", "P.Z", "A"}, width, height);
    double worst = 0;
    int covered = 0;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const float* l = &labels[4 * (static_cast<size_t>(y) * width + x)];
        if (l[3] < 1) continue;
        ++covered;
        double ndc[4] = {0, 0, 0, 0};
        for (int c = 0; c < 4; ++c)
          ndc[c] = l[0] * m[c] + l[1] * m[4 + c] + l[2] * m[8 + c] + m[12 + c];
        worst = std::max({worst, std::abs(ndc[0] / ndc[3] * width - (x + 0.5)),
                          std::abs(ndc[1] / ndc[3] * height - (y + 0.5))});
      }
    EXPECT_GT(covered, 50) << "view " << v;
    EXPECT_LT(worst, 0.01) << "view " << v << ": pixels off their centres";
  }
  // Each view's manifest line and its frame's header name the same view and frame.
  std::ifstream lines(dir.file("set/manifest.jsonl"));
  int frames = 0;
  for (std::string text; std::getline(lines, text); ++frames) {
    const nlohmann::json line = nlohmann::json::parse(text);
    const nlohmann::json header =
        readFrameMetadata(dir.file("set/" + line["outputs"][0].get<std::string>()));
    for (const char* key : {"view", "frame", "env", "yaw", "source", "source_sha256"})
      if (line.contains(key)) {
        EXPECT_EQ(header[key], line[key]) << key << " of " << text;
      }
    EXPECT_EQ(header["view"], frames);
  }
  EXPECT_EQ(frames, 3);
}

// OpenEXR's exrheader lists the attributes with their types; OpenImageIO
// reads the colour space tag; info prints the frame's lighting.
TEST(FrameHeaders, OpenExrAndOpenImageIoReadThem) {
  TempDir dir;
  const std::string frame = dir.file("f.exr");
  ASSERT_EQ(runCli(concat("relight ", test::fixture("small-plant"),
                          " --env sky --rotate 30 --exposure 0.5 --quiet --out ", frame))
                .status,
            0);
  const RunResult header = runShell("exrheader " + frame);
  ASSERT_EQ(header.status, 0) << header.output;
  for (const char* line :
       {"chromaticities (type chromaticities)",
        "colorInteropID (type string): \"lin_rec709_scene\"", "worldToCamera (type m44f)",
        "worldToNDC (type m44f)", "acpca:env (type string): \"sky\"", "acpca:yaw (type double): 30",
        "acpca:sh9 (type floatvector)", "acpca:method (type string)"})
    EXPECT_NE(header.output.find(line), std::string::npos) << line << "\n" << header.output;
  const RunResult oiio = runShell("oiiotool --info -v " + frame);
  EXPECT_NE(oiio.output.find("lin_rec709_scene"), std::string::npos) << oiio.output;
  const RunResult info = runCli("info " + frame);
  ASSERT_EQ(info.status, 0) << info.output;
  EXPECT_NE(info.output.find("lighting     sky at yaw 30, pitch 0, roll 0, exposure 0.5 EV"),
            std::string::npos)
      << info.output;
  const RunResult png = runCli(concat("relight ", test::fixture("small-plant"),
                                      " --env sky --rotate 30 --quiet --out ", dir.file("f.png")));
  ASSERT_EQ(png.status, 0) << png.output;
  const nlohmann::json fields = readFrameMetadata(dir.file("f.png"));
  EXPECT_EQ(fields["cICP"], nlohmann::json({1, 13, 0, 1}));
  EXPECT_EQ(fields["yaw"], 30);
}

// The lighting a manifest line lists is what its frame's header says,
// drawn maps, jittered exposures, turned over the sphere and lamps alike.
TEST(FrameHeaders, ManifestAndHeadersNeverDisagree) {
  TempDir dir;
  ASSERT_EQ(runCli(concat("relight ", test::fixture("small-plant"),
                          " --env sky --env sun:40,20,6,300 --env-sample 4 --seed 3",
                          " --exposure-jitter 1 --sample-rotation sphere",
                          " --light point:0.5,1.5,0.5,3 --format exr,png --quiet --out ",
                          dir.file("set")))
                .status,
            0);
  std::ifstream lines(dir.file("set/manifest.jsonl"));
  int frames = 0;
  for (std::string text; std::getline(lines, text);) {
    const nlohmann::json line = nlohmann::json::parse(text);
    for (const auto& output : line["outputs"]) {
      const std::string path = dir.file("set/" + output.get<std::string>());
      const nlohmann::json header = readFrameMetadata(path);
      const bool exr = path.ends_with(".exr");
      for (const char* key : {"env", "env_sha256", "yaw", "pitch", "roll", "exposure", "lights",
                              "sources", "sample", "frame", "sh9"}) {
        const nlohmann::json& expected = line[key];
        if (exr && std::string(key) == "sh9") {
          std::vector<double> flat;
          for (const auto& rgb : line[key])
            for (const auto& v : rgb) flat.push_back(v.get<double>());
          ASSERT_EQ(header[key].size(), flat.size()) << path;
          for (size_t k = 0; k < flat.size(); ++k)
            EXPECT_NEAR(header[key][k].get<double>(), flat[k], 1e-6 * std::abs(flat[k])) << path;
          continue;
        }
        if (expected.is_null() && exr) {
          EXPECT_FALSE(header.contains(key)) << path << " " << key;
          continue;
        }
        EXPECT_EQ(header[key], expected) << path << " " << key;
      }
    }
    ++frames;
  }
  EXPECT_EQ(frames, 4);
}

}  // namespace
}  // namespace acpca
