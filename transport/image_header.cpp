#include "transport/image_header.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/text.h"
#include "transport/cube_lattice.h"
#include "transport/hdf5_handles.h"
#include "transport/lamp_geometry.h"

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

constexpr const char* kCellSourceNames[] = {"capped-voronoi", "given"};

void writeLightSet(hid_t f, const LightSet& lights, const std::string& ctx) {
  const hsize_t n = lights.size();
  std::vector<double> directions, irradiance;
  for (int k = 0; k < lights.size(); ++k)
    for (int c = 0; c < 3; ++c) {
      directions.push_back(lights.directions[k][c]);
      irradiance.push_back(lights.irradiance[k][c]);
    }
  h5::writeDataset(f, "light_direction", {n, 3}, directions.data(), ctx);
  h5::writeDataset(f, "light_solid_angle", {n}, lights.solidAngles.data(), ctx);
  h5::writeDataset(f, "light_irradiance", {n, 3}, irradiance.data(), ctx);
  h5::writeAttribute(f, "light_cells",
                     std::string(kCellSourceNames[static_cast<int>(lights.cells)]), ctx);
  if (lights.cells == CellSource::CappedVoronoi)
    h5::writeAttribute(f, "light_cell_cap_deg", lights.capDegrees, ctx);
}

/// The light set of a file whose "cubemap" attribute is 0, checked.
LightSet readLightSet(hid_t f, const std::string& ctx) {
  const std::vector<hsize_t> shape = h5::datasetShape(f, "light_direction", ctx);
  if (shape.size() != 2 || shape[1] != 3 || shape[0] < 1 || shape[0] > kMaxLights)
    throw UserError(concat(ctx, ": dataset 'light_direction' has the wrong shape"));
  const hsize_t n = shape[0];
  if (h5::datasetShape(f, "light_solid_angle", ctx) != std::vector<hsize_t>{n} ||
      h5::datasetShape(f, "light_irradiance", ctx) != std::vector<hsize_t>{n, 3})
    throw UserError(concat(ctx, ": the light datasets differ in count"));
  std::vector<double> directions(3 * n), irradiance(3 * n);
  LightSet lights;
  lights.solidAngles.resize(n);
  h5::readTyped(f, "light_direction", H5T_NATIVE_DOUBLE, directions.data(), ctx);
  h5::readTyped(f, "light_solid_angle", H5T_NATIVE_DOUBLE, lights.solidAngles.data(), ctx);
  h5::readTyped(f, "light_irradiance", H5T_NATIVE_DOUBLE, irradiance.data(), ctx);
  for (hsize_t k = 0; k < n; ++k) {
    lights.directions.emplace_back(directions[3 * k], directions[3 * k + 1], directions[3 * k + 2]);
    lights.irradiance.emplace_back(irradiance[3 * k], irradiance[3 * k + 1], irradiance[3 * k + 2]);
  }
  const std::string cells = h5::readStringAttribute(f, "light_cells", ctx);
  if (cells == kCellSourceNames[0]) {
    lights.cells = CellSource::CappedVoronoi;
    lights.capDegrees = h5::readDoubleAttribute(f, "light_cell_cap_deg", ctx);
  } else if (cells == kCellSourceNames[1]) {
    lights.cells = CellSource::Given;
  } else {
    throw UserError(
        concat(ctx, ": attribute 'light_cells' is '", cells, "', not capped-voronoi or given"));
  }
  lights.validate(ctx);
  return lights;
}

}  // namespace

void writeImageHeader(hid_t f, const TransportHeader& h, const std::string& ctx) {
  h5::writeAttribute(f, "width", static_cast<long long>(h.camera.size.width), ctx);
  h5::writeAttribute(f, "height", static_cast<long long>(h.camera.size.height), ctx);
  h5::writeAttribute(f, "cubemap", static_cast<long long>(h.cubemapResolution), ctx);
  h5::writeAttribute(f, "scene", h.scene, ctx);
  h5::writeAttribute(f, "occupied_pixels", h.rows(), ctx);
  if (h.isLightSet()) {
    writeLightSet(f, h.lights, ctx);  // captured: no camera
  } else {
    h5::writeAttribute(f, "camera_eye", toVector(h.camera.eye), ctx);
    h5::writeAttribute(f, "camera_target", toVector(h.camera.target), ctx);
    h5::writeAttribute(f, "camera_up", toVector(h.camera.up), ctx);
    h5::writeAttribute(f, "camera_fov_deg", h.camera.fovDegrees, ctx);
  }
  // Written only for RGB rows, so files of scalar rows stay as they were.
  if (h.channels != 1) h5::writeAttribute(f, "channels", static_cast<long long>(h.channels), ctx);
  // Written only with indirect light (a model holds them too from version 7:
  // a lamp's exact path needs to know the rows hold bounced light).
  if (h.bounces > 0) {
    h5::writeAttribute(f, "bounces", static_cast<long long>(h.bounces), ctx);
    h5::writeAttribute(f, "indirect_samples", static_cast<long long>(h.indirectSamples), ctx);
    h5::writeAttribute(f, "indirect_cache_cell", h.indirectCacheCell, ctx);
  }
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
  writeLampGeometry(f, h.lamps, ctx);
}

bool fileHoldsLightSet(const std::string& path) {
  try {
    const h5::Handle file = h5::openFileReadOnly(path);
    return h5::hasAttribute(file.get(), "cubemap") &&
           h5::readIntAttribute(file.get(), "cubemap", path) == 0;
  } catch (const UserError&) {
    return false;
  }
}

TransportHeader readImageHeaderAttributes(hid_t f, bool requireNormals, const std::string& ctx,
                                          PixelDatasets& datasets) {
  TransportHeader h;
  const long long width = h5::readIntAttribute(f, "width", ctx);
  const long long height = h5::readIntAttribute(f, "height", ctx);
  if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide)
    throw UserError(concat(ctx, ": image size ", width, "x", height, " is out of range"));
  h.camera.size = {static_cast<int>(width), static_cast<int>(height)};
  const long long cubemap = h5::readIntAttribute(f, "cubemap", ctx);
  // 0: a light set's file (transport version 4, model version 6).
  if (cubemap < 0 || cubemap > CubeLattice::kMaxResolution)
    throw UserError(concat(ctx, ": cube-map resolution ", cubemap, " is out of range"));
  h.cubemapResolution = static_cast<int>(cubemap);
  h.scene = h5::readStringAttribute(f, "scene", ctx);
  if (cubemap == 0) {
    h.lights = readLightSet(f, ctx);
    requireNormals = false;
  } else {
    h.camera.eye = readVec3(f, "camera_eye", ctx);
    h.camera.target = readVec3(f, "camera_target", ctx);
    h.camera.up = readVec3(f, "camera_up", ctx);
    h.camera.fovDegrees = h5::readDoubleAttribute(f, "camera_fov_deg", ctx);
  }
  if (h5::hasAttribute(f, "channels")) {
    const long long channels = h5::readIntAttribute(f, "channels", ctx);
    if (channels != 1 && channels != 3)
      throw UserError(concat(ctx, ": attribute 'channels' is ", channels, ", not 1 or 3"));
    h.channels = static_cast<int>(channels);
  }

  if (h5::hasAttribute(f, "bounces")) {
    h.bounces =
        static_cast<int>(std::clamp(h5::readIntAttribute(f, "bounces", ctx), -1LL, 1LL << 20));
    h.indirectSamples = static_cast<int>(
        std::clamp(h5::readIntAttribute(f, "indirect_samples", ctx), -1LL, 1LL << 30));
    h.indirectCacheCell = h5::readDoubleAttribute(f, "indirect_cache_cell", ctx);
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
  if (withObjects) {
    expectShape("object", {un});
    h.objectNames = splitNames(h5::readStringAttribute(f, "object_names", ctx));
  }
  // As TransportHeader's has*(): a file without rows gives every array.
  const bool lamps = hasLampGeometry(f);
  datasets = {n,
              n == 0 || withNormals,
              n == 0 || withPositions,
              n == 0 || withObjects,
              lamps,
              h5::hasDataset(f, "lamp_sample_tangent"),
              lamps ? readLampMaterials(f, ctx) : std::vector<Material>{}};
  return h;
}

TransportHeader readImageHeader(hid_t f, bool requireNormals, const std::string& ctx) {
  PixelDatasets datasets;
  TransportHeader h = readImageHeaderAttributes(f, requireNormals, ctx, datasets);
  const long long n = datasets.rows;
  h.pixels.resize(n);
  h.albedo.resize(3 * n);
  h.coverage.resize(n);
  h5::readDataset(f, "pixels", h.pixels.data(), ctx);
  h5::readDataset(f, "albedo", h.albedo.data(), ctx);
  h5::readDataset(f, "coverage", h.coverage.data(), ctx);
  if (h5::hasDataset(f, "normal")) {  // required ones were checked there
    h.normals.resize(3 * n);
    h5::readDataset(f, "normal", h.normals.data(), ctx);
    for (float x : h.normals)
      if (!std::isfinite(x)) throw UserError(concat(ctx, ": dataset 'normal' is not finite"));
  }
  if (h5::hasDataset(f, "object")) {
    h.objects.resize(n);
    h5::readDataset(f, "object", h.objects.data(), ctx);
  }
  if (h5::hasDataset(f, "position")) {
    h.positions.resize(3 * n);
    h5::readDataset(f, "position", h.positions.data(), ctx);
    for (float x : h.positions)
      if (!std::isfinite(x)) throw UserError(concat(ctx, ": dataset 'position' is not finite"));
  }
  h.lamps = readLampGeometry(f, n, ctx);
  return h;
}

}  // namespace acpca
