#include "precompute/scene.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/error.h"

namespace acpca {

long long Scene::triangleCount() const {
  long long n = 0;
  for (const auto& m : meshes) n += static_cast<long long>(m.triangles.size());
  return n;
}

std::vector<std::string> Scene::objectNames() const {
  std::vector<std::string> names;
  for (size_t i = 0; i < meshes.size(); ++i)
    names.push_back(meshes[i].name.empty() ? concat("mesh ", i) : meshes[i].name);
  for (size_t i = 0; i < spheres.size(); ++i) names.push_back(concat("sphere ", i));
  return names;
}

Scene Scene::view(size_t k) const {
  ACPCA_CHECK(k < viewCount(), "view ", k, " of ", viewCount());
  Scene s = *this;
  if (!views.empty()) s.camera = views[k];
  s.views.clear();
  return s;
}

Eigen::AlignedBox3d Scene::bounds() const {
  Eigen::AlignedBox3d box;
  for (const auto& m : meshes)
    for (const auto& v : m.vertices) box.extend(v.cast<double>());
  for (const auto& s : spheres) {
    box.extend(s.center - Vec3::Constant(s.radius));
    box.extend(s.center + Vec3::Constant(s.radius));
  }
  return box;
}

double Scene::extent() const {
  const Eigen::AlignedBox3d box = bounds();
  return box.isEmpty() ? 1.0 : std::max(1e-6, box.diagonal().norm());
}

namespace {
void validateMaterial(const Material& m, const std::string& what) {
  if (!m.albedo.allFinite() || (m.albedo.array() < 0).any())
    throw UserError(concat(what, ": albedo must be finite and >= 0"));
  if (const std::string problem = materialProblem(m); !problem.empty())
    throw UserError(concat(what, ": ", kMaterialTypeNames.name(m.type), " ", problem));
}
}  // namespace

Scene Scene::atWidth(int width) const {
  Scene scaled = *this;
  scaled.camera.size = {
      width, std::max(1, static_cast<int>(
                             std::lround(double(width) * camera.size.height / camera.size.width)))};
  scaled.validate();
  return scaled;
}

void Scene::validate() const {
  camera.validate();
  if (meshes.empty() && spheres.empty()) throw UserError(concat("scene ", name, ": no objects"));
  for (const auto& m : meshes) {
    const std::string what = concat("scene ", name, ", mesh '", m.name, "'");
    validateMaterial(m.material, what);
    for (const auto& v : m.vertices)
      if (!v.allFinite()) throw UserError(concat(what, ": a vertex is NaN or infinite"));
    const int n = static_cast<int>(m.vertices.size());
    for (const auto& t : m.triangles)
      if ((t.array() < 0).any() || (t.array() >= n).any())
        throw UserError(concat(what, ": a triangle indexes a vertex that does not exist"));
    if (!m.normals.empty() && m.normals.size() != 3 * m.triangles.size())
      throw UserError(concat(what, ": ", m.normals.size(), " shading normals for ",
                             m.triangles.size(), " triangles (three per triangle)"));
    for (const auto& normal : m.normals)
      if (!normal.allFinite() || normal.norm() == 0)
        throw UserError(concat(what, ": a shading normal is zero, NaN or infinite"));
    if (!m.uvs.empty() && m.uvs.size() != 3 * m.triangles.size())
      throw UserError(concat(what, ": ", m.uvs.size(), " texture coordinates for ",
                             m.triangles.size(), " triangles (three per triangle)"));
    if (!m.tangents.empty() && m.tangents.size() != 3 * m.triangles.size())
      throw UserError(concat(what, ": ", m.tangents.size(), " tangents for ", m.triangles.size(),
                             " triangles (three per triangle)"));
    for (const auto& tangent : m.tangents)
      if (!tangent.allFinite()) throw UserError(concat(what, ": a tangent is NaN or infinite"));
    for (const auto& uv : m.uvs)
      if (!uv.allFinite())
        throw UserError(concat(what, ": a texture coordinate is NaN or infinite"));
    if (m.albedoTexture && m.uvs.empty())
      throw UserError(
          concat(what, ": texture '", m.albedoTexture->name(), "' but no texture coordinates"));
  }
  for (size_t i = 0; i < spheres.size(); ++i) {
    const std::string what = concat("scene ", name, ", sphere ", i);
    validateMaterial(spheres[i].material, what);
    if (!spheres[i].center.allFinite() ||
        !(spheres[i].radius > 0 && std::isfinite(spheres[i].radius)))
      throw UserError(concat(what, ": centre must be finite and radius > 0"));
  }
}

TriangleMesh makeQuad(const Vec3& center, const Vec3& normal, double size, const Material& m,
                      const std::string& name) {
  const Vec3 n = normal.normalized();
  const Vec3 helper = std::abs(n.y()) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  const Vec3 a = n.cross(helper).normalized() * (0.5 * size);
  const Vec3 b = n.cross(a);
  TriangleMesh mesh = emptyMesh(name, m);
  for (const Vec3& c :
       {Vec3(center - a - b), Vec3(center + a - b), Vec3(center + a + b), Vec3(center - a + b)})
    mesh.vertices.push_back(c.cast<float>());
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  // u along helper x n and v along n x u: seen from the front, a wall's image
  // stands upright (+Y up) and unmirrored.
  const Eigen::Vector2f uv[4] = {{1, 1}, {0, 1}, {0, 0}, {1, 0}};
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) mesh.uvs.push_back(uv[t[k]]);
  return mesh;
}

TriangleMesh makeBox(const Vec3& lo, const Vec3& hi, const Material& m, const std::string& name) {
  TriangleMesh mesh = emptyMesh(name, m);
  for (int i = 0; i < 8; ++i)
    mesh.vertices.emplace_back(float(i & 1 ? hi.x() : lo.x()), float(i & 2 ? hi.y() : lo.y()),
                               float(i & 4 ? hi.z() : lo.z()));
  // Two triangles per face, corners by bit pattern (x = 1, y = 2, z = 4).
  const int faces[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                           {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (const auto& f : faces) {
    mesh.triangles.emplace_back(f[0], f[1], f[2]);
    mesh.triangles.emplace_back(f[0], f[2], f[3]);
  }
  return mesh;
}

void appendMesh(TriangleMesh& a, const TriangleMesh& b) {
  ACPCA_CHECK(a.normals.empty() == b.normals.empty() || a.triangles.empty(),
              "appending meshes with and without shading normals");
  ACPCA_CHECK(a.uvs.empty() == b.uvs.empty() || a.triangles.empty(),
              "appending meshes with and without texture coordinates");
  ACPCA_CHECK(a.tangents.empty() == b.tangents.empty() || a.triangles.empty(),
              "appending meshes with and without tangents");
  ACPCA_CHECK(a.albedoTexture == b.albedoTexture, "appending meshes with different textures");
  const int offset = static_cast<int>(a.vertices.size());
  a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (const auto& t : b.triangles) a.triangles.push_back(t.array() + offset);
  a.normals.insert(a.normals.end(), b.normals.begin(), b.normals.end());
  a.uvs.insert(a.uvs.end(), b.uvs.begin(), b.uvs.end());
  a.tangents.insert(a.tangents.end(), b.tangents.begin(), b.tangents.end());
}

Scene loadScene(const std::string& nameOrPath) {
  if (isBuiltinScene(nameOrPath)) return makeBuiltinScene(nameOrPath);
  if (std::filesystem::exists(nameOrPath)) return loadSceneJson(nameOrPath);
  throw UserError(concat("scene '", nameOrPath,
                         "' is neither a built-in scene (see `adaptive-cpca scenes`) nor a file"));
}

}  // namespace acpca
