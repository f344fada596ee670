// A multi-view batch's camera files read as their loaders read them: every
// covered pixel's position label, projected through transforms.json
// (OpenGL axes, camera to world) or through COLMAP's cameras.txt and
// images.txt (OpenCV axes, world to camera), lands on its pixel's centre.
// The projections here are written from the two formats' definitions, not
// with the camera code that made the files.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>
#include <Eigen/Geometry>

#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "tests/cli/run_cli.h"
#include "tests/cli/sphere_floor_scene.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

using test::TempDir;

/// A view's position and mask labels, read by channel name from labels.exr.
struct ViewLabels {
  int width = 0, height = 0;
  std::vector<Eigen::Vector3d> position;
  std::vector<float> mask;
};

ViewLabels readLabels(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << path;
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<float> values(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
  in->read_image(0, 0, 0, -1, OIIO::TypeDesc::FLOAT, values.data());
  const int px = spec.channelindex("P.X"), py = spec.channelindex("P.Y"),
            pz = spec.channelindex("P.Z"), a = spec.channelindex("A");
  EXPECT_TRUE(px >= 0 && py >= 0 && pz >= 0 && a >= 0) << path;
  ViewLabels labels{spec.width, spec.height, {}, {}};
  for (size_t p = 0; p < static_cast<size_t>(spec.width) * spec.height; ++p) {
    const float* v = &values[p * spec.nchannels];
    labels.position.emplace_back(v[px], v[py], v[pz]);
    labels.mask.push_back(v[a]);
  }
  return labels;
}

/// The farthest any covered pixel's position lands from its centre, through
/// `project` (world point to image point; false behind the camera).
double worstReprojection(
    const ViewLabels& labels,
    const std::function<bool(const Eigen::Vector3d&, Eigen::Vector2d&)>& project) {
  double worst = 0;
  int covered = 0;
  for (int y = 0; y < labels.height; ++y)
    for (int x = 0; x < labels.width; ++x) {
      const size_t p = static_cast<size_t>(y) * labels.width + x;
      if (labels.mask[p] <= 0) continue;
      ++covered;
      Eigen::Vector2d image;
      if (!project(labels.position[p], image)) return 1e9;
      worst = std::max(worst, (image - Eigen::Vector2d(x + 0.5, y + 0.5)).norm());
    }
  EXPECT_GT(covered, labels.width * labels.height / 4);
  return worst;
}

/// Pinhole projection in OpenCV's axes (x right, y down, z forward), pixel
/// centres at +0.5 as nerfstudio and COLMAP both take them.
bool projectOpenCv(const Eigen::Vector3d& cameraPoint, double fx, double fy, double cx, double cy,
                   Eigen::Vector2d& image) {
  if (cameraPoint.z() <= 0) return false;
  image = {cx + fx * cameraPoint.x() / cameraPoint.z(),
           cy + fy * cameraPoint.y() / cameraPoint.z()};
  return true;
}

/// Every frame of a batch directory through transforms.json: the worst
/// reprojection over its frames.
double worstThroughTransforms(const std::string& dir) {
  const nlohmann::json t = nlohmann::json::parse(test::readFile(dir + "/transforms.json"));
  EXPECT_EQ(t.at("camera_model"), "OPENCV");
  double worst = 0;
  for (const auto& frame : t.at("frames")) {
    const auto& k = frame.contains("fl_x") ? frame : t;  // per frame where views differ
    Eigen::Matrix4d cameraToWorld;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) cameraToWorld(r, c) = frame.at("transform_matrix")[r][c];
    const Eigen::Matrix4d worldToCamera = cameraToWorld.inverse();
    const std::string picture = frame.at("file_path");
    EXPECT_TRUE(test::fs::exists(dir + "/" + picture)) << picture;
    const int view = frame.at("view");
    const ViewLabels labels = readLabels(dir + "/labels_v0" + std::to_string(view) + ".exr");
    EXPECT_EQ(k.at("w").get<int>(), labels.width);
    EXPECT_EQ(k.at("h").get<int>(), labels.height);
    worst = std::max(
        worst, worstReprojection(labels, [&](const Eigen::Vector3d& p, Eigen::Vector2d& image) {
          const Eigen::Vector4d gl = worldToCamera * p.homogeneous();
          // OpenGL's y up and z toward the viewer, flipped to OpenCV's.
          return projectOpenCv({gl.x(), -gl.y(), -gl.z()}, k.at("fl_x"), k.at("fl_y"), k.at("cx"),
                               k.at("cy"), image);
        }));
  }
  return worst;
}

/// The same through COLMAP's text model in DIR/sparse/0.
double worstThroughColmap(const std::string& dir) {
  std::map<int, std::array<double, 4>> intrinsics;  // camera id: fx, fy, cx, cy
  std::istringstream cameras(test::readFile(dir + "/sparse/0/cameras.txt"));
  for (std::string line; std::getline(cameras, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    int id, w, h;
    std::string model;
    std::array<double, 4> k;
    in >> id >> model >> w >> h >> k[0] >> k[1] >> k[2] >> k[3];
    EXPECT_EQ(model, "PINHOLE");
    intrinsics[id] = k;
  }
  std::istringstream images(test::readFile(dir + "/sparse/0/images.txt"));
  double worst = 0;
  int count = 0;
  for (std::string line; std::getline(images, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream in(line);
    int id, camera;
    double qw, qx, qy, qz, tx, ty, tz;
    std::string name;
    in >> id >> qw >> qx >> qy >> qz >> tx >> ty >> tz >> camera >> name;
    std::getline(images, line);  // the image's 2D points: none
    EXPECT_TRUE(line.empty()) << line;
    ++count;
    EXPECT_TRUE(test::fs::exists(dir + "/" + name)) << name;
    const Eigen::Matrix3d rotation = Eigen::Quaterniond(qw, qx, qy, qz).toRotationMatrix();
    const Eigen::Vector3d translation(tx, ty, tz);
    const std::array<double, 4>& k = intrinsics.at(camera);
    const ViewLabels labels = readLabels(dir + "/labels_v0" + std::to_string(camera - 1) + ".exr");
    worst = std::max(
        worst, worstReprojection(labels, [&](const Eigen::Vector3d& p, Eigen::Vector2d& image) {
          return projectOpenCv(rotation * p + translation, k[0], k[1], k[2], k[3], image);
        }));
  }
  EXPECT_GT(count, 0);
  return worst;
}

TEST(CameraFiles, PositionsProjectOntoTheirPixelsThroughTransformsAndColmap) {
  TempDir dir;
  const std::string scene = dir.file("orbit.json");
  std::ofstream(scene) << R"({"cameras": {"orbit": {"target": [0, 0.5, 0], "radius": 5,
      "elevation_deg": 20, "count": 3, "fov": 30, "width": 24, "height": 16}}, )"
                       << test::kSphereOnFloorObjects << "}";
  ASSERT_EQ(runCli("precompute --scene " + scene + " --cubemap 4 --spp 1 --quiet --out " +
                   dir.file("t.h5"))
                .status,
            0);
  const RunResult r = runCli("relight " + dir.file("t_v00.h5") + " " + dir.file("t_v01.h5") + " " +
                             dir.file("t_v02.h5") +
                             " --env sky --rotate 0:90:45 --aov position,mask,depth "
                             "--label-format both --format exr,png --colmap --quiet --out " +
                             dir.file("set"));
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_LT(worstThroughTransforms(dir.file("set")), 0.01);
  EXPECT_LT(worstThroughColmap(dir.file("set")), 0.01);
  const nlohmann::json t = nlohmann::json::parse(test::readFile(dir.file("set/transforms.json")));
  ASSERT_EQ(t.at("frames").size(), 6u);
  const auto& third = t.at("frames")[3];
  EXPECT_EQ(third.at("file_path"), "00003_v01_sky_y45.png");
  EXPECT_EQ(third.at("depth_file_path"), "labels_v01_depth.npy");
  EXPECT_EQ(third.at("mask_path"), "labels_v01_mask.png");
  EXPECT_EQ(third.at("yaw"), 45.0);
  EXPECT_EQ(third.at("sh9").size(), 9u);
  EXPECT_NEAR(t.at("camera_angle_x").get<double>(),
              2 * std::atan(1.5 * std::tan(std::numbers::pi / 12)), 1e-12);
  // The mask picture is round(255 x coverage), here 0 or 255 (one sample).
  const ViewLabels labels = readLabels(dir.file("set/labels_v01.exr"));
  auto mask = OIIO::ImageInput::open(dir.file("set/labels_v01_mask.png"));
  ASSERT_TRUE(mask);
  std::vector<unsigned char> codes(labels.mask.size());
  mask->read_image(0, 0, 0, -1, OIIO::TypeDesc::UINT8, codes.data());
  for (size_t p = 0; p < codes.size(); ++p) ASSERT_EQ(codes[p], labels.mask[p] > 0 ? 255 : 0) << p;
}

TEST(CameraFiles, ACameraRolledOffPlusYAndViewsOfTwoSizes) {
  TempDir dir;
  const std::string scene = dir.file("rolled.json");
  std::ofstream(scene) << R"({"cameras": [
      {"eye": [3, 2.5, 4], "target": [0, 0.4, 0], "up": [1, 1, 0.3], "fov": 35, "width": 20, "height": 12},
      {"eye": [-1, 6, 0.5], "target": [0, 0.5, 0], "up": [0, 0, -1], "fov": 25, "width": 16, "height": 18}],
      )" << test::kSphereOnFloorObjects
                       << "}";
  ASSERT_EQ(runCli("precompute --scene " + scene + " --cubemap 4 --spp 1 --quiet --out " +
                   dir.file("t.h5"))
                .status,
            0);
  const RunResult r =
      runCli("relight " + dir.file("t_v00.h5") + " " + dir.file("t_v01.h5") +
             " --env sky --aov position,mask --colmap --quiet --out " + dir.file("set"));
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json t = nlohmann::json::parse(test::readFile(dir.file("set/transforms.json")));
  EXPECT_FALSE(t.contains("fl_x"));  // the views differ: each frame has its own
  EXPECT_EQ(t.at("frames")[1].at("w"), 16);
  EXPECT_FALSE(t.at("frames")[0].contains("depth_file_path"));
  EXPECT_LT(worstThroughTransforms(dir.file("set")), 0.01);
  EXPECT_LT(worstThroughColmap(dir.file("set")), 0.01);
  // One image is not a dataset: no camera files, and --colmap is refused.
  expectFailure(
      "relight " + dir.file("t_v00.h5") + " --env sky --colmap --out " + dir.file("one.exr"),
      "--colmap: is written beside a batch's frames");
  EXPECT_FALSE(test::fs::exists(dir.file("one.exr")));
}

}  // namespace
}  // namespace acpca
