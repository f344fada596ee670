#pragma once
// The camera files a batch writes for loaders that know only them
// (docs/datasets.md, "Cameras"): nerfstudio's transforms.json and COLMAP's
// text model, made from each view's camera and the batch's manifest.jsonl.
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "transport/camera.h"

namespace acpca {

/// A pinhole camera's intrinsics in pixels. Pixels are square, and pixel
/// (x, y) has its centre at (x + 0.5, y + 0.5), as nerfstudio and COLMAP take
/// it, so the principal point is the image's centre.
struct PinholeIntrinsics {
  double fx = 0, fy = 0, cx = 0, cy = 0;
  int width = 0, height = 0;
  /// Horizontal field of view in radians (NeRF-Synthetic's camera_angle_x).
  double angleX() const;
  bool operator==(const PinholeIntrinsics&) const = default;
};
PinholeIntrinsics pinholeIntrinsics(const Camera& camera);

/// Camera to world in OpenGL's axes (x right, y up, z toward the viewer), as
/// transforms.json keeps it.
Eigen::Matrix4d cameraToWorldOpenGl(const Camera& camera);

/// World to camera in OpenCV's axes (x right, y down, z forward), as COLMAP's
/// images.txt keeps it: camera point = rotation * world point + translation.
struct WorldToCamera {
  Eigen::Quaterniond rotation;  ///< unit, w >= 0
  Vec3 translation;
};
WorldToCamera worldToCameraOpenCv(const Camera& camera);

/// Writes DIRECTORY/transforms.json for the frames DIRECTORY/manifest.jsonl
/// lists, frame by frame (memory stays flat for any count), view v seen by
/// cameras[v]; with `colmap` also COLMAP's text model in DIRECTORY/sparse/0.
/// Each file appears under its name only once whole.
void writeCameraFiles(const std::string& directory, const std::vector<Camera>& cameras,
                      bool colmap);

}  // namespace acpca
