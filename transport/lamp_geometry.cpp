#include "transport/lamp_geometry.h"

#include <cmath>

#include "core/error.h"
#include "transport/hdf5_handles.h"

namespace acpca {

namespace {

/// The largest counts a file may claim: checked before anything is allocated.
constexpr long long kMaxSamplesPerRow = 1024;
constexpr long long kMaxSceneElements = 1LL << 31;
/// lamp_materials' columns: type, ks, Phong's exponent, GGX's alpha u, from
/// version 6 also alpha v (0: isotropic), nu, nv and the rotation in degrees.
constexpr hsize_t kMaterialColumns = 8, kIsotropicMaterialColumns = 4;

Vec3 vec3At(const std::vector<float>& values, long long i) {
  return {values[3 * i], values[3 * i + 1], values[3 * i + 2]};
}

bool allFinite(const std::vector<float>& values) {
  for (float v : values)
    if (!std::isfinite(v)) return false;
  return true;
}

/// A dataset's leading dimension, checked: the shape [n] or [n, columns].
long long countOf(hid_t f, const char* name, hsize_t columns, long long most,
                  const std::string& ctx) {
  const std::vector<hsize_t> shape = h5::datasetShape(f, name, ctx);
  const bool shaped = columns == 0 ? shape.size() == 1 : shape.size() == 2 && shape[1] == columns;
  if (!shaped || static_cast<long long>(shape[0]) > most)
    throw UserError(concat(ctx, ": dataset '", name, "' has the wrong shape"));
  return static_cast<long long>(shape[0]);
}

}  // namespace

Vec3 LampGeometry::tangentAt(long long s) const {
  if (!tangent.empty()) return vec3At(tangent, s);
  return tangentAcross(vec3At(normal, s), Vec3(Vec3::UnitX()));
}

void LampGeometry::validate(long long rows, const std::string& ctx) const {
  if (empty()) return;
  const auto bad = [&](const std::string& what) {
    return UserError(concat(ctx, ": the lamp samples ", what));
  };
  if (static_cast<long long>(sampleStart.size()) != rows + 1 || sampleStart.front() != 0 ||
      sampleStart.back() != samples())
    throw bad("do not cover the rows");
  for (long long r = 0; r < rows; ++r)
    if (sampleStart[r + 1] <= sampleStart[r] ||
        sampleStart[r + 1] - sampleStart[r] > kMaxSamplesPerRow)
      throw bad(concat("of row ", r, " are out of order"));
  const size_t n = static_cast<size_t>(samples());
  if (origin.size() != 3 * n || normal.size() != 3 * n || geometricNormal.size() != 3 * n ||
      (!tangent.empty() && tangent.size() != 3 * n) || material.size() != n)
    throw bad("differ in count");
  if (!allFinite(origin) || !allFinite(normal) || !allFinite(geometricNormal) ||
      !allFinite(tangent) || !allFinite(weight) || !allFinite(vertices) || !allFinite(spheres))
    throw bad("or surfaces hold a value that is not finite");
  for (int32_t m : material)
    if (m < 0 || m >= static_cast<int32_t>(materials.size())) throw bad("name no material");
  for (const Material& m : materials)
    if (const std::string problem = materialProblem(m); !problem.empty())
      throw bad(concat("have a ", kMaterialTypeNames.name(m.type), " material whose ", problem));
  if (tangent.empty())
    for (const Material& m : materials)
      if (m.anisotropic()) throw bad("have an anisotropic material but no tangents");
  const long long vertexCount = static_cast<long long>(vertices.size() / 3);
  if (vertices.size() % 3 != 0 || triangles.size() % 3 != 0 || spheres.size() % 4 != 0)
    throw bad("have surfaces of the wrong shape");
  for (int32_t v : triangles)
    if (v < 0 || v >= vertexCount) throw bad("have a triangle past the vertices");
  if (!(rayEpsilon >= 0 && std::isfinite(rayEpsilon))) throw bad("have a bad ray epsilon");
}

void writeLampGeometry(hid_t f, const LampGeometry& g, const std::string& ctx) {
  if (g.empty()) return;
  const hsize_t rows = g.sampleStart.size() - 1, n = static_cast<hsize_t>(g.samples());
  h5::writeTyped(f, "lamp_sample_start", {rows + 1}, H5T_NATIVE_INT64, g.sampleStart.data(), ctx);
  h5::writeDataset(f, "lamp_sample_origin", {n, 3}, g.origin.data(), ctx);
  h5::writeDataset(f, "lamp_sample_normal", {n, 3}, g.normal.data(), ctx);
  h5::writeDataset(f, "lamp_sample_geometric_normal", {n, 3}, g.geometricNormal.data(), ctx);
  if (!g.tangent.empty()) h5::writeDataset(f, "lamp_sample_tangent", {n, 3}, g.tangent.data(), ctx);
  h5::writeDataset(f, "lamp_sample_weight", {n}, g.weight.data(), ctx);
  h5::writeDataset(f, "lamp_sample_material", {n}, g.material.data(), ctx);
  std::vector<double> materials;
  for (const Material& m : g.materials)
    materials.insert(materials.end(), {static_cast<double>(m.type), m.specular, m.exponent,
                                       m.roughness, m.roughnessV, m.nu, m.nv, m.rotationDegrees});
  h5::writeDataset(f, "lamp_materials", {g.materials.size(), kMaterialColumns}, materials.data(),
                   ctx);
  h5::writeDataset(f, "scene_vertices", {g.vertices.size() / 3, 3}, g.vertices.data(), ctx);
  h5::writeDataset(f, "scene_triangles", {g.triangles.size() / 3, 3}, g.triangles.data(), ctx);
  h5::writeDataset(f, "scene_spheres", {g.spheres.size() / 4, 4}, g.spheres.data(), ctx);
  h5::writeAttribute(f, "lamp_ray_epsilon", static_cast<double>(g.rayEpsilon), ctx);
}

std::vector<Material> readLampMaterials(hid_t f, const std::string& ctx) {
  // Files from before tangents have four columns, and isotropic materials.
  const bool tangents = h5::hasDataset(f, "lamp_sample_tangent");
  const hsize_t columns = tangents ? kMaterialColumns : kIsotropicMaterialColumns;
  const long long count = countOf(f, "lamp_materials", columns, kMaxSceneElements, ctx);
  std::vector<double> table(columns * static_cast<size_t>(count));
  h5::readTyped(f, "lamp_materials", H5T_NATIVE_DOUBLE, table.data(), ctx);
  std::vector<Material> materials;
  for (long long m = 0; m < count; ++m) {
    const double* row = &table[columns * m];
    const double type = row[0];
    if (type != 0 && type != 1 && type != 2 && !(tangents && type == 3))
      throw UserError(concat(ctx, ": dataset 'lamp_materials' names material type ", type));
    Material material;
    material.type = static_cast<Material::Type>(static_cast<int>(type));
    material.specular = row[1];
    material.exponent = row[2];
    material.roughness = row[3];
    if (tangents) {
      material.roughnessV = row[4];
      material.nu = row[5], material.nv = row[6];
      material.rotationDegrees = row[7];
    }
    materials.push_back(material);
  }
  return materials;
}

bool hasLampGeometry(hid_t f) {
  return h5::hasDataset(f, "lamp_sample_start");
}

LampGeometry readLampGeometry(hid_t f, long long rows, const std::string& ctx) {
  LampGeometry g;
  if (!hasLampGeometry(f)) return g;
  if (countOf(f, "lamp_sample_start", 0, rows + 1, ctx) != rows + 1)
    throw UserError(concat(ctx, ": dataset 'lamp_sample_start' has the wrong shape"));
  const long long n = countOf(f, "lamp_sample_weight", 0, kMaxSamplesPerRow * rows, ctx);
  for (const char* name :
       {"lamp_sample_origin", "lamp_sample_normal", "lamp_sample_geometric_normal"})
    if (countOf(f, name, 3, n, ctx) != n)
      throw UserError(concat(ctx, ": dataset '", name, "' has the wrong shape"));
  if (countOf(f, "lamp_sample_material", 0, n, ctx) != n)
    throw UserError(concat(ctx, ": dataset 'lamp_sample_material' has the wrong shape"));
  const bool tangents = h5::hasDataset(f, "lamp_sample_tangent");
  if (tangents && countOf(f, "lamp_sample_tangent", 3, n, ctx) != n)
    throw UserError(concat(ctx, ": dataset 'lamp_sample_tangent' has the wrong shape"));
  const long long vertices = countOf(f, "scene_vertices", 3, kMaxSceneElements, ctx);
  const long long triangles = countOf(f, "scene_triangles", 3, kMaxSceneElements, ctx);
  const long long spheres = countOf(f, "scene_spheres", 4, kMaxSceneElements, ctx);
  g.sampleStart.resize(static_cast<size_t>(rows + 1));
  h5::readTyped(f, "lamp_sample_start", H5T_NATIVE_INT64, g.sampleStart.data(), ctx);
  const size_t un = static_cast<size_t>(n);
  g.origin.resize(3 * un), g.normal.resize(3 * un), g.geometricNormal.resize(3 * un);
  g.weight.resize(un), g.material.resize(un);
  h5::readDataset(f, "lamp_sample_origin", g.origin.data(), ctx);
  h5::readDataset(f, "lamp_sample_normal", g.normal.data(), ctx);
  h5::readDataset(f, "lamp_sample_geometric_normal", g.geometricNormal.data(), ctx);
  if (tangents) {
    g.tangent.resize(3 * un);
    h5::readDataset(f, "lamp_sample_tangent", g.tangent.data(), ctx);
  }
  h5::readDataset(f, "lamp_sample_weight", g.weight.data(), ctx);
  h5::readDataset(f, "lamp_sample_material", g.material.data(), ctx);
  g.materials = readLampMaterials(f, ctx);
  g.vertices.resize(3 * static_cast<size_t>(vertices));
  g.triangles.resize(3 * static_cast<size_t>(triangles));
  g.spheres.resize(4 * static_cast<size_t>(spheres));
  h5::readDataset(f, "scene_vertices", g.vertices.data(), ctx);
  h5::readDataset(f, "scene_triangles", g.triangles.data(), ctx);
  h5::readDataset(f, "scene_spheres", g.spheres.data(), ctx);
  g.rayEpsilon = static_cast<float>(h5::readDoubleAttribute(f, "lamp_ray_epsilon", ctx));
  g.validate(rows, ctx);
  return g;
}

}  // namespace acpca
