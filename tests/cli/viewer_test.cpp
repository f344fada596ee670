// The viewer, driven without a person under Xvfb: what it shows is what the
// batch relight writes, its keys do what they say, and it refuses cleanly
// where it cannot run. The viewer lights a map's sun exactly once the map is
// let go (docs/lighting.md, "Lit exactly"), as the batch does.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "core/text.h"
#include "imageio/frame_metadata.h"
#include "lighting/local_light.h"
#include "model/model_file.h"
#include "tests/cli/run_cli.h"
#include "tests/test_support.h"
#include "viewer/view_input.h"

namespace acpca {
namespace {

using test::TempDir;

struct Picture {
  int width = 0, height = 0, channels = 0;
  std::vector<unsigned char> bytes;
  const unsigned char* at(int x, int y) const {
    return &bytes[(static_cast<size_t>(y) * width + x) * channels];
  }
};

Picture readPicture(const std::string& path) {
  Picture p;
  auto in = OIIO::ImageInput::open(path);
  if (!in) return p;
  p.width = in->spec().width;
  p.height = in->spec().height;
  p.channels = in->spec().nchannels;
  p.bytes.resize(static_cast<size_t>(p.width) * p.height * p.channels);
  in->read_image(0, 0, 0, -1, OIIO::TypeDesc::UINT8, p.bytes.data());
  return p;
}

/// Pixels of the window's image area (its top rows) that differ from `batch`.
int differingPixels(const Picture& screenshot, const Picture& batch) {
  int differ = 0;
  for (int y = 0; y < batch.height; ++y)
    for (int x = 0; x < batch.width; ++x)
      differ += !std::equal(batch.at(x, y), batch.at(x, y) + 3, screenshot.at(x, y));
  return differ;
}

class Viewer : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    const RunResult p = runCli("precompute --scene plant --size 48x40 --cubemap 8 --quiet --out " +
                               dir_->file("t.h5"));
    ASSERT_EQ(p.status, 0) << p.output;
    const RunResult c = runCli("compress " + dir_->file("t.h5") +
                               " --method adaptive-quad --coeffs f16 --quiet --out " + model());
    ASSERT_EQ(c.status, 0) << c.output;
  }
  static void TearDownTestSuite() { delete dir_; }
  void SetUp() override {
    if (!std::filesystem::exists("/usr/bin/xvfb-run"))
      GTEST_SKIP() << "xvfb-run is missing (scripts/setup.sh installs Debian's xvfb)";
  }
  static std::string model() { return dir_->file("m.h5"); }
  /// Runs the viewer on a virtual X display; Qt's own allocations are not ours
  /// to check under LeakSanitizer.
  static RunResult view(const std::string& args) {
    return runCli("view " + model() + " " + args,
                  "ASAN_OPTIONS=detect_leaks=0 xvfb-run -a -s '-screen 0 640x480x24'");
  }
  static TempDir* dir_;
};
TempDir* Viewer::dir_ = nullptr;

TEST_F(Viewer, SelfDrivingScreenshotEqualsTheBatchRelightOfItsLastRotation) {
  TempDir out;
  // Frames at yaw 10, 35, 60, 85 (pitch 5); the screenshot shows the last.
  const RunResult r = view("--env sky --rotate 10,5 --frames 4 --rotate-step 25 --screenshot " +
                           out.file("shot.png"));
  ASSERT_EQ(r.status, 0) << r.output;
  const RunResult b = runCli("relight " + model() + " --env sky --rotate 85,5,0 --quiet --out " +
                             out.file("b.png"));
  ASSERT_EQ(b.status, 0) << b.output;
  const Picture shot = readPicture(out.file("shot.png")), batch = readPicture(out.file("b.png"));
  ASSERT_EQ(batch.width, 48);
  ASSERT_EQ(shot.width, batch.width);
  ASSERT_GT(shot.height, batch.height) << "the status line sits below the image";
  EXPECT_EQ(differingPixels(shot, batch), 0);

  // A different rotation is visibly different (the comparison can fail).
  const RunResult other = runCli("relight " + model() +
                                 " --env sky --rotate 60,5,0 --quiet --out " + out.file("b60.png"));
  ASSERT_EQ(other.status, 0) << other.output;
  EXPECT_GT(differingPixels(shot, readPicture(out.file("b60.png"))), 100);
}

TEST_F(Viewer, ScriptedKeysToggleOverlaysAndSaveWritesTheBatchImage) {
  TempDir out;
  const std::string script = out.file("events.txt");
  std::ofstream(script) << "# turn, look at the overlays one at a time, then save\n"
                           "rotate 30\n"
                           "screenshot "
                        << out.file("plain.png")
                        << "\n"
                           "key c\nscreenshot "
                        << out.file("clusters.png")
                        << "\nkey c\n"
                           "key h\nscreenshot "
                        << out.file("heat.png")
                        << "\nkey h\n"
                           "key l\nscreenshot "
                        << out.file("inset.png")
                        << "\nkey l\n"
                           "drag 12 0\n"  // a quarter of 48 pixels: 90 degrees more yaw
                           "exposure 1.5\nrank 50\n"
                           "save "
                        << out.file("saved") << "\n";
  const RunResult r = view("--env sun:50,30,4,1000 --env sky --script " + script);
  ASSERT_EQ(r.status, 0) << r.output;

  const Picture plain = readPicture(out.file("plain.png"));
  ASSERT_EQ(plain.width, 48);
  const Picture clusters = readPicture(out.file("clusters.png"));
  // Boundaries are drawn in one colour over the image, nothing else changes.
  int boundary = 0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 48; ++x)
      if (!std::equal(plain.at(x, y), plain.at(x, y) + 3, clusters.at(x, y))) {
        ++boundary;
        EXPECT_EQ(clusters.at(x, y)[0], 255);
        EXPECT_EQ(clusters.at(x, y)[1], 230);
        EXPECT_EQ(clusters.at(x, y)[2], 0);
      }
  EXPECT_GT(boundary, 10);
  EXPECT_GT(differingPixels(readPicture(out.file("heat.png")), readPicture(out.file("plain.png"))),
            100);
  // The inset sits in the top-left corner and nowhere else.
  const Picture inset = readPicture(out.file("inset.png"));
  int outside = 0, inside = 0;
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 48; ++x) {
      const bool changed = !std::equal(plain.at(x, y), plain.at(x, y) + 3, inset.at(x, y));
      (x < 18 && y < 10 ? inside : outside) += changed;
    }
  EXPECT_EQ(outside, 0);
  EXPECT_GT(inside, 20);

  // The saved frame: yaw 30 + 90, exposure 1.5, half of each cluster's bases.
  const RunResult b = runCli("relight " + model() +
                             " --env sun:50,30,4,1000 --rotate 120 --exposure 1.5 --max-rank 50% "
                             "--format both --quiet --out " +
                             out.file("batch.png"));
  ASSERT_EQ(b.status, 0) << b.output;
  ASSERT_EQ(runCli("relight " + model() +
                   " --env sun:50,30,4,1000 --rotate 120 --exposure 1.5 --quiet --out " +
                   out.file("full.exr"))
                .status,
            0);
  const Picture saved = readPicture(out.file("saved.png")),
                batch = readPicture(out.file("batch.png"));
  ASSERT_EQ(saved.bytes.size(), batch.bytes.size());
  EXPECT_EQ(saved.bytes, batch.bytes);
  // Its header is relight's header for the same view (docs/formats.md, "Frame metadata").
  for (const char* ext : {".exr", ".png"}) {
    const nlohmann::json mine = readFrameMetadata(out.file(concat("saved", ext))),
                         theirs = readFrameMetadata(out.file(concat("batch", ext)));
    for (const char* key :
         {"env", "yaw", "pitch", "roll", "exposure", "lights", "sources", "source", "source_sha256",
          "method", "version", "colorInteropID", "worldToCamera", "worldToNDC"})
      EXPECT_EQ(mine[key], theirs[key]) << ext << " " << key;
    EXPECT_NEAR(mine["cost_per_pixel"].get<double>(), theirs["cost_per_pixel"].get<double>(),
                1e-9 * theirs["cost_per_pixel"].get<double>())
        << ext;
    EXPECT_LT(mine["cost_per_pixel"].get<double>(),
              readFrameMetadata(out.file("full.exr"))["cost_per_pixel"].get<double>())
        << "half of each cluster's bases cost less";
    const auto flat = [](const nlohmann::json& sh9) {
      std::vector<double> values;
      for (const auto& v : sh9.flatten()) values.push_back(v.get<double>());
      return values;
    };
    const std::vector<double> a = flat(mine["sh9"]), b = flat(theirs["sh9"]);
    ASSERT_EQ(a.size(), 27u) << ext;
    ASSERT_EQ(b.size(), 27u) << ext;
    for (size_t k = 0; k < a.size(); ++k) EXPECT_NEAR(a[k], b[k], 1e-5 * (1 + std::abs(b[k])));
  }
}

/// Where the lamp tests put a lamp: between the eye and the plant, above the
/// view's middle, and the pixel it is drawn at.
struct LampPlace {
  Vec3 position;
  Eigen::Vector2d drawn;
};
LampPlace lampPlace(const Camera& camera) {
  LampPlace p;
  p.position = camera.eye + 0.4 * (camera.target - camera.eye) +
               0.1 * (camera.target - camera.eye).norm() * camera.imageUp();
  double depth = 0;
  EXPECT_TRUE(camera.project(p.position, p.drawn, depth));
  return p;
}

// A light added by script, dragged from where it is drawn and wheeled nearer:
// it stays under the cursor, the saved frame is relight's image under the
// lights the viewer reports, and the lamp visibly changes the image.
TEST_F(Viewer, ADraggedLightGivesTheBatchImageOfWhereItWent) {
  TempDir out;
  const Camera camera = readModel(model()).geometry.camera;
  const auto [start, drawn] = lampPlace(camera);
  double depth = 0;
  const std::string script = out.file("events.txt");
  std::ofstream(script) << "light point:" << start.x() << "," << start.y() << "," << start.z()
                        << ",4\n"
                        << "dragfrom " << std::floor(drawn.x()) << " " << std::floor(drawn.y())
                        << " 6 -3\nwheel 1\nsave " << out.file("lamp") << "\n";
  const RunResult r = view("--env sky --script " + script);
  ASSERT_EQ(r.status, 0) << r.output;
  const size_t at = r.output.find(" under --light ");
  ASSERT_NE(at, std::string::npos) << r.output;
  const std::string spec = r.output.substr(at + 15, r.output.find('\n', at) - at - 15);
  const LocalLight moved = parseLocalLight(spec);
  Eigen::Vector2d now;
  ASSERT_TRUE(camera.project(moved.position, now, depth));
  EXPECT_NEAR(now.x() - drawn.x(), 6, 1e-6) << spec;
  EXPECT_NEAR(now.y() - drawn.y(), -3, 1e-6) << spec;

  const RunResult b = runCli("relight " + model() + " --env sky --light " + spec +
                             " --quiet --out " + out.file("batch.png"));
  ASSERT_EQ(b.status, 0) << b.output;
  const Picture saved = readPicture(out.file("lamp.png")),
                batch = readPicture(out.file("batch.png"));
  ASSERT_EQ(saved.width, 48);
  EXPECT_EQ(saved.bytes, batch.bytes);
  const RunResult sky =
      runCli("relight " + model() + " --env sky --quiet --out " + out.file("sky.png"));
  ASSERT_EQ(sky.status, 0) << sky.output;
  EXPECT_GT(differingPixels(saved, readPicture(out.file("sky.png"))), 100);
}

// A sphere lamp held by a script's press and dragged: lit as its point of the
// same power while held (the batch image of that point), at full quality once
// let go (the batch image of the sphere where it went).
TEST_F(Viewer, AHeldSphereLampPreviewsAsItsPointAndIsWholeWhenLetGo) {
  TempDir out;
  const Camera camera = readModel(model()).geometry.camera;
  const auto [start, drawn] = lampPlace(camera);
  double depth = 0;
  const std::string script = out.file("events.txt");
  std::ofstream(script) << "light sphere:" << start.x() << "," << start.y() << "," << start.z()
                        << ",0.05,400\n"
                        << "press " << std::floor(drawn.x()) << " " << std::floor(drawn.y())
                        << "\ndrag 6 -3\nsave " << out.file("held") << "\nrelease\nsave "
                        << out.file("let-go") << "\n";
  const RunResult r = view("--env sky --script " + script);
  ASSERT_EQ(r.status, 0) << r.output;
  const size_t at = r.output.rfind(" under --light ");
  ASSERT_NE(at, std::string::npos) << r.output;
  const LocalLight moved =
      parseLocalLight(r.output.substr(at + 15, r.output.find('\n', at) - at - 15));
  ASSERT_TRUE(moved.as<SphereLight>()) << r.output;
  Eigen::Vector2d now;
  ASSERT_TRUE(camera.project(moved.position, now, depth));
  EXPECT_NEAR(now.x() - drawn.x(), 6, 1e-6);
  LocalLight asPoint = moved;  // the point of the same power: L pi r^2
  asPoint.shape = PointLight{};
  asPoint.emission = moved.emission * (std::numbers::pi * 0.05 * 0.05);
  const std::string point = asPoint.canonicalSpec();
  for (const auto& [saved, spec] : {std::pair{std::string("held"), point},
                                    std::pair{std::string("let-go"), moved.canonicalSpec()}}) {
    const RunResult b = runCli("relight " + model() + " --env sky --light " + spec +
                               " --quiet --out " + out.file(saved + "-batch.png"));
    ASSERT_EQ(b.status, 0) << b.output;
    EXPECT_EQ(readPicture(out.file(saved + ".png")).bytes,
              readPicture(out.file(saved + "-batch.png")).bytes)
        << saved;
  }
  EXPECT_GT(differingPixels(readPicture(out.file("held.png")), readPicture(out.file("let-go.png"))),
            0);
}

// A map held by the mouse (pressed off any light, then turned): its sun lit
// as a point of the same power (the batch image of that point, a disc of
// kHeldDiscRadius); once let go, exactly (the batch image of the map).
TEST_F(Viewer, AHeldMapLightsItsSunAsAPointAndExactlyWhenLetGo) {
  TempDir out;
  const std::string script = out.file("events.txt");
  std::ofstream(script) << "press 0 0\nrotate 40\nsave " << out.file("held") << "\nrelease\nsave "
                        << out.file("let-go") << "\n";
  const RunResult r = view("--env sun:50,30,4,1000 --script " + script);
  ASSERT_EQ(r.status, 0) << r.output;
  const double kDegree = std::numbers::pi / 180;
  const double pointSize = 2 * kHeldDiscRadius / kDegree;
  const double pointRadiance = 1000 * (1 - std::cos(2 * kDegree)) / (1 - std::cos(kHeldDiscRadius));
  const std::string point =
      concat("sun:50,30,", shortestNumberText(pointSize), ",", shortestNumberText(pointRadiance));
  for (const auto& [saved, env] :
       {std::pair{std::string("held"), point},
        std::pair{std::string("let-go"), std::string("sun:50,30,4,1000")}}) {
    const RunResult b = runCli("relight " + model() + " --env " + env +
                               " --rotate 40 --quiet --out " + out.file(saved + "-batch.png"));
    ASSERT_EQ(b.status, 0) << b.output;
    EXPECT_EQ(differingPixels(readPicture(out.file(saved + ".png")),
                              readPicture(out.file(saved + "-batch.png"))),
              0)
        << saved;
  }
  // The 4-degree sun's penumbrae are not the point's hard edges.
  EXPECT_GT(differingPixels(readPicture(out.file("held.png")), readPicture(out.file("let-go.png"))),
            0);
}

TEST_F(Viewer, RefusesCleanlyWithoutADisplayOrAModel) {
  TempDir out;
  // Without a display: a message, exit 1, no crash (Qt would abort).
  expectFailure("view " + model() + " --env sky", "DISPLAY is not set",
                "env -u DISPLAY -u QT_QPA_PLATFORM");
  expectFailure("view " + model() + " --env sky", "nothing answers",
                "env -u QT_QPA_PLATFORM DISPLAY=:987");
  expectFailure("view " + dir_->file("t.h5") + " --env sky", "not a model file");
  const std::string script = out.file("bad.txt");
  std::ofstream(script) << "rotate 10\nspin 3\n";
  expectFailure("view " + model() + " --script " + script, "bad.txt:2");
  expectFailure("view " + model() + " --env sky --rank-percent 120", "--rank-percent");
}

}  // namespace
}  // namespace acpca
