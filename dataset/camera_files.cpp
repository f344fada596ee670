#include "dataset/camera_files.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/text.h"

namespace acpca {

namespace {

namespace fs = std::filesystem;

/// A number as text that reads back to the same double.
std::string exact(double value) {
  return formatted("%.17g", value);
}

/// The file a loader shows as the frame: its PNG where it has one (what
/// every image library reads), else the first of its outputs.
std::string framePicture(const nlohmann::json& outputs) {
  for (const auto& path : outputs)
    if (fs::path(path.get<std::string>()).extension() == ".png") return path.get<std::string>();
  return outputs.at(0).get<std::string>();
}

/// The view's label file ending in `suffix` among a frame's, or empty.
std::string labelEnding(const nlohmann::json& line, const std::string& suffix) {
  if (!line.contains("labels")) return "";
  for (const auto& path : line.at("labels")) {
    const std::string name = path.get<std::string>();
    if (name.size() >= suffix.size() && name.ends_with(suffix)) return name;
  }
  return "";
}

nlohmann::ordered_json intrinsicsJson(const PinholeIntrinsics& k) {
  return {{"fl_x", k.fx},  {"fl_y", k.fy}, {"cx", k.cx}, {"cy", k.cy}, {"w", k.width},
          {"h", k.height}, {"k1", 0.0},    {"k2", 0.0},  {"p1", 0.0},  {"p2", 0.0}};
}

nlohmann::ordered_json matrixJson(const Eigen::Matrix4d& m) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  // + 0.0: no "-0.0" in the file.
  for (int r = 0; r < 4; ++r)
    rows.push_back({m(r, 0) + 0.0, m(r, 1) + 0.0, m(r, 2) + 0.0, m(r, 3) + 0.0});
  return rows;
}

/// transforms.json's entry for one manifest line: the frame's picture and
/// pose, its view's label files nerfstudio reads (a depth .npy, a mask PNG),
/// then the lighting it was relit under, as the manifest holds it.
nlohmann::ordered_json transformsFrame(const nlohmann::json& line,
                                       const std::vector<Camera>& cameras,
                                       bool perFrameIntrinsics) {
  const size_t view = line.value("view", size_t{0});
  if (view >= cameras.size())
    throw UserError(concat("manifest.jsonl: frame ", line.value("frame", -1), " names view ", view,
                           " of ", cameras.size()));
  nlohmann::ordered_json frame = {
      {"file_path", framePicture(line.at("outputs"))},
      {"transform_matrix", matrixJson(cameraToWorldOpenGl(cameras[view]))}};
  if (perFrameIntrinsics) frame.update(intrinsicsJson(pinholeIntrinsics(cameras[view])));
  if (const std::string depth = labelEnding(line, "_depth.npy"); !depth.empty())
    frame["depth_file_path"] = depth;
  if (const std::string mask = labelEnding(line, "_mask.png"); !mask.empty())
    frame["mask_path"] = mask;
  frame["view"] = view;
  for (const char* key : {"frame", "sample", "env", "env_sha256", "yaw", "pitch", "roll",
                          "exposure", "lights", "sh9"})
    if (line.contains(key)) frame[key] = line.at(key);
  return frame;
}

/// COLMAP's cameras.txt: a PINHOLE camera per view, CAMERA_ID = view + 1.
std::string colmapCameras(const std::vector<Camera>& cameras) {
  std::string text =
      "# Camera list with one line of data per camera:\n"
      "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
      "# Number of cameras: " +
      std::to_string(cameras.size()) + "\n";
  for (size_t v = 0; v < cameras.size(); ++v) {
    const PinholeIntrinsics k = pinholeIntrinsics(cameras[v]);
    text += concat(v + 1, " PINHOLE ", k.width, " ", k.height, " ", exact(k.fx), " ", exact(k.fy),
                   " ", exact(k.cx), " ", exact(k.cy), "\n");
  }
  return text;
}

/// COLMAP's images.txt lines of one frame (IMAGE_ID = frame + 1), its
/// second line empty: no 2D points.
std::string colmapImage(const nlohmann::json& line, const Camera& camera, size_t view) {
  const WorldToCamera pose = worldToCameraOpenCv(camera);
  const Eigen::Quaterniond& q = pose.rotation;
  const Vec3& t = pose.translation;
  return concat(line.at("frame").get<long long>() + 1, " ", exact(q.w()), " ", exact(q.x()), " ",
                exact(q.y()), " ", exact(q.z()), " ", exact(t.x()), " ", exact(t.y()), " ",
                exact(t.z()), " ", view + 1, " ", framePicture(line.at("outputs")), "\n\n");
}

/// transforms.json's fields before its frames: the intrinsics, when every
/// view shares them (else each frame carries its own).
nlohmann::ordered_json transformsHead(const std::vector<Camera>& cameras,
                                      bool& perFrameIntrinsics) {
  const PinholeIntrinsics first = pinholeIntrinsics(cameras.at(0));
  perFrameIntrinsics = false;
  for (const Camera& c : cameras) perFrameIntrinsics |= !(pinholeIntrinsics(c) == first);
  // OPENCV with zero distortion: what nerfstudio's own tools write, so
  // every reader of theirs takes it.
  nlohmann::ordered_json head = {{"camera_model", "OPENCV"}};
  if (!perFrameIntrinsics) {
    head.update(intrinsicsJson(first));
    head["camera_angle_x"] = first.angleX();
  }
  head["views"] = cameras.size();
  return head;
}

}  // namespace

double PinholeIntrinsics::angleX() const {
  return 2 * std::atan(0.5 * width / fx);
}

PinholeIntrinsics pinholeIntrinsics(const Camera& camera) {
  // Square pixels of pixelScale: fy = 1 / (2 tan(fov / 2) / height).
  const double focal =
      0.5 * camera.size.height / std::tan(0.5 * camera.fovDegrees * std::numbers::pi / 180.0);
  return {focal,
          focal,
          0.5 * camera.size.width,
          0.5 * camera.size.height,
          camera.size.width,
          camera.size.height};
}

Eigen::Matrix4d cameraToWorldOpenGl(const Camera& camera) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<3, 1>(0, 0) = camera.right();
  m.block<3, 1>(0, 1) = camera.imageUp();
  m.block<3, 1>(0, 2) = -camera.forward();
  m.block<3, 1>(0, 3) = camera.eye;
  return m;
}

WorldToCamera worldToCameraOpenCv(const Camera& camera) {
  Eigen::Matrix3d cameraToWorld;
  cameraToWorld << camera.right(), -camera.imageUp(), camera.forward();
  const Eigen::Matrix3d worldToCamera = cameraToWorld.transpose();
  Eigen::Quaterniond q(worldToCamera);
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return {q, -worldToCamera * camera.eye};
}

void writeCameraFiles(const std::string& directory, const std::vector<Camera>& cameras,
                      bool colmap) {
  const fs::path dir(directory);
  std::ifstream manifest(dir / "manifest.jsonl");
  if (!manifest) throw UserError(concat((dir / "manifest.jsonl").string(), ": cannot be read"));
  bool perFrameIntrinsics = false;
  std::string head = transformsHead(cameras, perFrameIntrinsics).dump(2);
  head.resize(head.find_last_not_of("\n}") + 1);  // reopened: the frames follow
  AtomicOutput transforms((dir / "transforms.json").string());
  std::ofstream out(transforms.tempPath());
  out << head << ",\n  \"frames\": [";
  std::optional<AtomicOutput> images;
  std::ofstream imagesOut;
  if (colmap) {
    createOutputDirectory((dir / "sparse" / "0").string());
    images.emplace((dir / "sparse" / "0" / "images.txt").string());
    imagesOut.open(images->tempPath());
    imagesOut << "# Image list with two lines of data per image:\n"
                 "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
                 "#   POINTS2D[] as (X, Y, POINT3D_ID)\n";
  }
  const char* separator = "\n";
  for (std::string text; std::getline(manifest, text);) {
    const nlohmann::json line = nlohmann::json::parse(text);
    const nlohmann::ordered_json frame = transformsFrame(line, cameras, perFrameIntrinsics);
    out << separator << "    " << frame.dump();
    separator = ",\n";
    const auto view = frame.at("view").get<size_t>();
    if (colmap) imagesOut << colmapImage(line, cameras[view], view);
  }
  out << "\n  ]\n}\n";
  out.close();
  if (!out)
    throw WriteError(concat(transforms.finalPath(), ": cannot be written (is the disk full?)"));
  if (colmap) {
    imagesOut.close();
    if (!imagesOut)
      throw WriteError(concat(images->finalPath(), ": cannot be written (is the disk full?)"));
    writeTextFile((dir / "sparse" / "0" / "cameras.txt").string(), colmapCameras(cameras));
    writeTextFile((dir / "sparse" / "0" / "points3D.txt").string(),
                  "# 3D point list with one line of data per point: none (the cameras are "
                  "known, no points were matched)\n");
    images->commit();
  }
  transforms.commit();
}

}  // namespace acpca
