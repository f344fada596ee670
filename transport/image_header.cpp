#include "transport/image_header.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/text.h"
#include "transport/cube_lattice.h"
#include "transport/hdf5_handles.h"

namespace acpca {

namespace {

std::vector<double> toVector(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

Vec3 readVec3(hid_t f, const char* name, const std::string& ctx) {
  const auto v = h5::readDoubleArrayAttribute(f, name, ctx);
  if (v.size() != 3) throw UserError(concat(ctx, ": attribute '", name, "' must hold 3 numbers"));
  return {v[0], v[1], v[2]};
}

/// Object names as one attribute, a line each (a line break inside a name
/// becomes a space).
std::string joinedNames(const std::vector<std::string>& names) {
  std::string joined;
  for (size_t i = 0; i < names.size(); ++i) {
    std::string name = names[i];
    std::replace(name.begin(), name.end(), '\n', ' ');
    joined += (i ? "\n" : "") + name;
  }
  return joined;
}

/// The names of joinedNames' text (one empty name for empty text).
std::vector<std::string> splitNames(const std::string& joined) {
  return joined.empty() ? std::vector<std::string>{""} : splitText(joined, '\n');
}

}  // namespace

void writeImageHeader(hid_t f, const TransportHeader& h, const std::string& ctx) {
  h5::writeAttribute(f, "width", static_cast<long long>(h.camera.size.width), ctx);
  h5::writeAttribute(f, "height", static_cast<long long>(h.camera.size.height), ctx);
  h5::writeAttribute(f, "cubemap", static_cast<long long>(h.cubemapResolution), ctx);
  h5::writeAttribute(f, "scene", h.scene, ctx);
  h5::writeAttribute(f, "occupied_pixels", h.rows(), ctx);
  h5::writeAttribute(f, "camera_eye", toVector(h.camera.eye), ctx);
  h5::writeAttribute(f, "camera_target", toVector(h.camera.target), ctx);
  h5::writeAttribute(f, "camera_up", toVector(h.camera.up), ctx);
  h5::writeAttribute(f, "camera_fov_deg", h.camera.fovDegrees, ctx);
  // Written only for RGB rows, so files of scalar rows stay as they were.
  if (h.channels != 1) h5::writeAttribute(f, "channels", static_cast<long long>(h.channels), ctx);
  const hsize_t n = h.rows();
  h5::writeDataset(f, "pixels", {n}, h.pixels.data(), ctx);
  h5::writeDataset(f, "albedo", {n, 3}, h.albedo.data(), ctx);
  h5::writeDataset(f, "coverage", {n}, h.coverage.data(), ctx);
  if (!h.normals.empty() || n == 0) h5::writeDataset(f, "normal", {n, 3}, h.normals.data(), ctx);
  if (!h.positions.empty()) h5::writeDataset(f, "position", {n, 3}, h.positions.data(), ctx);
  if (!h.objects.empty() || !h.objectNames.empty()) {
    h5::writeDataset(f, "object", {n}, h.objects.data(), ctx);
    h5::writeAttribute(f, "object_names", joinedNames(h.objectNames), ctx);
  }
}

TransportHeader readImageHeader(hid_t f, bool requireNormals, const std::string& ctx) {
  TransportHeader h;
  const long long width = h5::readIntAttribute(f, "width", ctx);
  const long long height = h5::readIntAttribute(f, "height", ctx);
  if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide)
    throw UserError(concat(ctx, ": image size ", width, "x", height, " is out of range"));
  h.camera.size = {static_cast<int>(width), static_cast<int>(height)};
  const long long cubemap = h5::readIntAttribute(f, "cubemap", ctx);
  if (cubemap < 1 || cubemap > CubeLattice::kMaxResolution)
    throw UserError(concat(ctx, ": cube-map resolution ", cubemap, " is out of range"));
  h.cubemapResolution = static_cast<int>(cubemap);
  h.scene = h5::readStringAttribute(f, "scene", ctx);
  h.camera.eye = readVec3(f, "camera_eye", ctx);
  h.camera.target = readVec3(f, "camera_target", ctx);
  h.camera.up = readVec3(f, "camera_up", ctx);
  h.camera.fovDegrees = h5::readDoubleAttribute(f, "camera_fov_deg", ctx);
  if (h5::hasAttribute(f, "channels")) {
    const long long channels = h5::readIntAttribute(f, "channels", ctx);
    if (channels != 1 && channels != 3)
      throw UserError(concat(ctx, ": attribute 'channels' is ", channels, ", not 1 or 3"));
    h.channels = static_cast<int>(channels);
  }

  // Every shape is checked against the header before anything is allocated.
  const long long n = h5::readIntAttribute(f, "occupied_pixels", ctx);
  if (n < 0 || n > h.camera.size.pixels())
    throw UserError(concat(ctx, ": ", n, " occupied pixels in a ", width, "x", height, " image"));
  const hsize_t un = static_cast<hsize_t>(n);
  const auto expectShape = [&](const char* name, std::vector<hsize_t> want) {
    if (h5::datasetShape(f, name, ctx) != want)
      throw UserError(concat(ctx, ": dataset '", name, "' has the wrong shape"));
  };
  expectShape("pixels", {un});
  expectShape("albedo", {un, 3});
  expectShape("coverage", {un});
  const bool withNormals = requireNormals || h5::hasDataset(f, "normal");
  if (withNormals) expectShape("normal", {un, 3});
  const bool withPositions = h5::hasDataset(f, "position");
  if (withPositions) expectShape("position", {un, 3});
  const bool withObjects = h5::hasDataset(f, "object");
  if (withObjects) expectShape("object", {un});
  h.pixels.resize(n);
  h.albedo.resize(3 * n);
  h.coverage.resize(n);
  h5::readDataset(f, "pixels", h.pixels.data(), ctx);
  h5::readDataset(f, "albedo", h.albedo.data(), ctx);
  h5::readDataset(f, "coverage", h.coverage.data(), ctx);
  if (withNormals) {
    h.normals.resize(3 * n);
    h5::readDataset(f, "normal", h.normals.data(), ctx);
    for (float x : h.normals)
      if (!std::isfinite(x)) throw UserError(concat(ctx, ": dataset 'normal' is not finite"));
  }
  if (withObjects) {
    h.objects.resize(n);
    h5::readDataset(f, "object", h.objects.data(), ctx);
    h.objectNames = splitNames(h5::readStringAttribute(f, "object_names", ctx));
  }
  if (withPositions) {
    h.positions.resize(3 * n);
    h5::readDataset(f, "position", h.positions.data(), ctx);
    for (float x : h.positions)
      if (!std::isfinite(x)) throw UserError(concat(ctx, ": dataset 'position' is not finite"));
  }
  return h;
}

}  // namespace acpca
