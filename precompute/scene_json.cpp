// Scene files: JSON with a camera and a list of objects (schema: docs/scenes.md).
// Every key is checked: unknown, missing or mistyped keys are errors naming the
// key and where it is.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>

#include "core/error.h"
#include "core/warning.h"
#include "precompute/scene.h"

namespace acpca {

namespace {

using nlohmann::json;
namespace fs = std::filesystem;

/// A JSON object being read, with its location for error messages.
class Reader {
 public:
  Reader(const json& value, std::string where) : value_(value), where_(std::move(where)) {
    if (!value_.is_object()) throw UserError(concat(where_, ": expected an object"));
  }

  /// Fails if the object has a key outside `allowed`.
  void allowOnly(const std::set<std::string>& allowed) const {
    for (const auto& item : value_.items())
      if (!allowed.count(item.key()))
        throw UserError(concat(where_, ": unknown key '", item.key(), "'"));
  }
  bool has(const std::string& key) const { return value_.contains(key); }
  std::string path(const std::string& key) const { return concat(where_, ".", key); }
  const json& at(const std::string& key) const {
    if (!has(key)) throw UserError(concat(where_, ": missing key '", key, "'"));
    return value_.at(key);
  }

  double number(const std::string& key) const {
    const json& v = at(key);
    if (!v.is_number() || !std::isfinite(v.get<double>()))
      throw UserError(concat(path(key), ": expected a finite number"));
    return v.get<double>();
  }
  /// number(key), refused unless lo <= value <= hi.
  double numberIn(const std::string& key, double lo, double hi) const {
    const double v = number(key);
    if (v < lo || v > hi)
      throw UserError(concat(path(key), ": ", v, " is outside [", lo, ", ", hi, "]"));
    return v;
  }
  std::string text(const std::string& key) const {
    const json& v = at(key);
    if (!v.is_string()) throw UserError(concat(path(key), ": expected a string"));
    return v.get<std::string>();
  }
  std::vector<double> numbers(const std::string& key, size_t count) const {
    const json& v = at(key);
    if (!v.is_array() || v.size() != count)
      throw UserError(concat(path(key), ": expected an array of ", count, " numbers"));
    std::vector<double> out;
    for (const auto& e : v) {
      if (!e.is_number() || !std::isfinite(e.get<double>()))
        throw UserError(concat(path(key), ": expected an array of ", count, " finite numbers"));
      out.push_back(e.get<double>());
    }
    return out;
  }
  Vec3 vec3(const std::string& key) const {
    const auto v = numbers(key, 3);
    return {v[0], v[1], v[2]};
  }
  Reader child(const std::string& key) const { return Reader(at(key), path(key)); }
  const std::string& where() const { return where_; }

 private:
  const json& value_;
  std::string where_;
};

int positiveInt(const Reader& r, const std::string& key) {
  const double v = r.number(key);
  if (v != std::floor(v) || v < 1 || v > kMaxImageSide)
    throw UserError(concat(r.path(key), ": expected an integer in 1..", kMaxImageSide));
  return static_cast<int>(v);
}

Camera readCamera(const Reader& r) {
  r.allowOnly({"eye", "target", "up", "fov", "width", "height"});
  Camera c;
  c.eye = r.vec3("eye");
  c.target = r.vec3("target");
  c.up = r.vec3("up");
  c.fovDegrees = r.number("fov");
  if (r.has("width")) c.size.width = positiveInt(r, "width");
  if (r.has("height")) c.size.height = positiveInt(r, "height");
  try {
    c.validate();
  } catch (const UserError& e) {
    throw UserError(concat(r.where(), ": ", e.what()));
  }
  return c;
}

/// Most views one scene file may hold.
constexpr int kMaxViews = 1000;

/// "cameras": a list of cameras, or {"orbit": {...}}: `count` cameras on a
/// circle of `radius` around `target`, `elevation_deg` above its horizontal
/// plane, the first on +Z of the target, turning toward +X (docs/scenes.md).
std::vector<Camera> readCameras(const json& value, const std::string& where) {
  std::vector<Camera> views;
  if (value.is_array()) {
    if (value.empty() || value.size() > kMaxViews)
      throw UserError(concat(where, ": expected 1..", kMaxViews, " cameras"));
    for (size_t i = 0; i < value.size(); ++i)
      views.push_back(readCamera(Reader(value[i], concat(where, "[", i, "]"))));
    return views;
  }
  const Reader cameras(value, where);
  cameras.allowOnly({"orbit"});
  const Reader orbit = cameras.child("orbit");
  orbit.allowOnly({"target", "radius", "elevation_deg", "count", "fov", "width", "height"});
  const double radius = orbit.number("radius");
  if (!(radius > 0)) throw UserError(concat(orbit.path("radius"), ": expected a positive number"));
  const double elevation = orbit.numberIn("elevation_deg", -89, 89) * std::numbers::pi / 180;
  const double count = orbit.number("count");
  if (count != std::floor(count) || count < 1 || count > kMaxViews)
    throw UserError(concat(orbit.path("count"), ": expected an integer in 1..", kMaxViews));
  Camera c;
  c.target = orbit.vec3("target");
  c.fovDegrees = orbit.number("fov");
  if (orbit.has("width")) c.size.width = positiveInt(orbit, "width");
  if (orbit.has("height")) c.size.height = positiveInt(orbit, "height");
  for (int k = 0; k < static_cast<int>(count); ++k) {
    const double azimuth = 2 * std::numbers::pi * k / count;
    c.eye = c.target + radius * Vec3(std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                                     std::cos(elevation) * std::cos(azimuth));
    try {
      c.validate();
    } catch (const UserError& e) {
      throw UserError(concat(orbit.where(), ": view ", k, ": ", e.what()));
    }
    views.push_back(c);
  }
  return views;
}

/// A material as the scene file gives it: the BRDF, and the albedo and texture
/// when it gives them (a mesh object keeps its file's colours otherwise).
struct MaterialSpec {
  Material material;
  bool colored = false;  ///< "albedo" or "texture" given
  std::shared_ptr<const Texture> texture;
};

/// Keys only some material types take, and which: named in the error when
/// another type has them, rather than "unknown key".
void refuseOtherKindsKeys(const Reader& r, const std::string& type) {
  static const std::vector<std::pair<std::string, std::set<std::string>>> owners = {
      {"specular", {"phong", "ggx", "ashikhmin-shirley"}},
      {"exponent", {"phong"}},
      {"roughness", {"ggx"}},
      {"anisotropy", {"ggx"}},
      {"roughness_u", {"ggx"}},
      {"roughness_v", {"ggx"}},
      {"nu", {"ashikhmin-shirley"}},
      {"nv", {"ashikhmin-shirley"}},
      {"rotation", {"ggx", "ashikhmin-shirley"}}};
  for (const auto& [key, types] : owners) {
    if (!r.has(key) || types.count(type)) continue;
    std::string list;
    for (const auto& t : types) list += (list.empty() ? "" : ", ") + t;
    throw UserError(
        concat(r.path(key), ": a ", type, " material has no '", key, "' (only ", list, ")"));
  }
}

/// An Ashikhmin-Shirley exponent: > 0, or the lobe has no peak.
double positiveExponent(const Reader& r, const std::string& key) {
  const double v = r.number(key);
  if (!(v > 0 && v <= 1e6)) throw UserError(concat(r.path(key), ": ", v, " is outside (0, 1e6]"));
  return v;
}

/// GGX: "roughness" alpha, made anisotropic by "anisotropy" t in [0, 1) as
/// Cycles' Principled BSDF does (alpha / aspect along the tangent, alpha x
/// aspect along the bitangent, aspect = sqrt(1 - 0.9 t)), or the two alphas
/// as "roughness_u" and "roughness_v".
void readGgx(const Reader& r, Material& m) {
  r.allowOnly({"type", "albedo", "texture", "specular", "roughness", "anisotropy", "roughness_u",
               "roughness_v", "rotation"});
  m.specular = r.numberIn("specular", 0, 1);
  const bool axes = r.has("roughness_u") || r.has("roughness_v");
  if (axes) {
    if (r.has("roughness") || r.has("anisotropy"))
      throw UserError(concat(r.where(),
                             ": give 'roughness' (and 'anisotropy') or 'roughness_u' and "
                             "'roughness_v', not both"));
    m.roughness = r.numberIn("roughness_u", kMinRoughness, kMaxRoughness);
    m.roughnessV = r.numberIn("roughness_v", kMinRoughness, kMaxRoughness);
    return;
  }
  m.roughness = r.numberIn("roughness", kMinRoughness, 1);
  if (!r.has("anisotropy")) return;
  const double t = r.number("anisotropy");
  if (!(t >= 0 && t < 1))
    throw UserError(concat(r.path("anisotropy"), ": ", t, " is outside [0, 1)"));
  const double alpha = m.roughness, aspect = std::sqrt(1 - 0.9 * t);
  m.roughness = std::max(kMinRoughness, alpha / aspect);
  m.roughnessV = std::max(kMinRoughness, alpha * aspect);
}

MaterialSpec readMaterial(const Reader& r, const fs::path& baseDir) {
  const std::string type = r.text("type");
  MaterialSpec spec;
  Material& m = spec.material;
  try {
    m.type = kMaterialTypeNames.parse(type);
  } catch (const ParameterError&) {
    throw UserError(concat(r.path("type"), ": unknown material type '", type, "' (",
                           kMaterialTypeNames.list(), ")"));
  }
  refuseOtherKindsKeys(r, type);
  if (m.type == Material::Type::Diffuse) r.allowOnly({"type", "albedo", "texture"});
  if (m.type == Material::Type::Phong) {
    r.allowOnly({"type", "albedo", "texture", "specular", "exponent"});
    m.specular = r.numberIn("specular", 0, 1);
    m.exponent = r.numberIn("exponent", 0, 1e6);
  }
  if (m.type == Material::Type::Ggx) readGgx(r, m);
  if (m.type == Material::Type::AshikhminShirley) {
    r.allowOnly({"type", "albedo", "texture", "specular", "nu", "nv", "rotation"});
    m.specular = r.numberIn("specular", 0, 1);
    m.nu = positiveExponent(r, "nu");
    m.nv = positiveExponent(r, "nv");
  }
  if (r.has("rotation")) m.rotationDegrees = r.numberIn("rotation", -3600, 3600);
  // A texture scales the albedo, which then defaults to white.
  if (r.has("texture")) {
    try {
      spec.texture = loadTexture((baseDir / r.text("texture")).string());
    } catch (const UserError& e) {
      throw UserError(concat(r.path("texture"), ": ", e.what()));
    }
    m.albedo.setOnes();
  }
  if (r.has("albedo")) {
    const Vec3 a = r.vec3("albedo");
    if ((a.array() < 0).any()) throw UserError(concat(r.path("albedo"), ": must be >= 0"));
    m.albedo = a.cast<float>();
  }
  spec.colored = r.has("albedo") || r.has("texture");
  return spec;
}

/// A shape's material: albedo or texture required.
MaterialSpec readShapeMaterial(const Reader& r, const fs::path& baseDir) {
  const Reader material = r.child("material");
  MaterialSpec spec = readMaterial(material, baseDir);
  if (!spec.colored) throw UserError(concat(material.where(), ": missing key 'albedo'"));
  return spec;
}

/// Gives a mesh loaded from a file the scene file's material: the BRDF always,
/// the colours when the scene file names them.
void overrideMaterial(TriangleMesh& mesh, const MaterialSpec& spec, const std::string& where) {
  const Material file = mesh.material;
  mesh.material = spec.material;
  if (spec.colored) {
    if (spec.texture && mesh.uvs.empty())
      throw UserError(concat(where, ": texture '", spec.texture->name(), "' but part '", mesh.name,
                             "' has no texture coordinates"));
    mesh.albedoTexture = spec.texture;
  } else {
    mesh.material.albedo = file.albedo;
  }
}

/// An anisotropic lobe on a part without tangents of its own (no texture
/// coordinates or normals to take them from, or degenerate ones) turns
/// about world +X across the normal there: said once per part.
void warnOfMissingTangents(const TriangleMesh& mesh, const std::string& where) {
  if (!mesh.material.anisotropic()) return;
  const auto missing = mesh.tangents.empty()
                           ? static_cast<long long>(3 * mesh.triangles.size())
                           : std::count_if(mesh.tangents.begin(), mesh.tangents.end(),
                                           [](const Eigen::Vector3f& t) { return t.isZero(); });
  if (missing == 0) return;
  warn(concat(where, ": part '", mesh.name, "' has no usable tangent at ", missing, " of ",
              3 * mesh.triangles.size(),
              " corners (no texture coordinates, or degenerate ones): its anisotropic "
              "lobe is turned from world +X across the normal there"));
}

/// Row-major 4x4 affine transform of a mesh object.
Eigen::Matrix4d readTransform(const Reader& r) {
  r.allowOnly({"scale", "rotate_y_deg", "translate", "matrix"});
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if (r.has("matrix")) {
    if (r.has("scale") || r.has("rotate_y_deg") || r.has("translate"))
      throw UserError(concat(r.where(), ": 'matrix' excludes scale, rotate_y_deg and translate"));
    const auto v = r.numbers("matrix", 16);
    for (int i = 0; i < 16; ++i) m(i / 4, i % 4) = v[i];
    if (m.row(3) != Eigen::RowVector4d(0, 0, 0, 1))
      throw UserError(concat(r.path("matrix"), ": the last row must be 0 0 0 1 (affine)"));
    return m;
  }
  Eigen::Vector3d scale(1, 1, 1);
  if (r.has("scale")) {
    if (r.at("scale").is_array())
      scale = r.vec3("scale");
    else
      scale.setConstant(r.number("scale"));
  }
  const double angle = r.has("rotate_y_deg") ? r.number("rotate_y_deg") * M_PI / 180 : 0.0;
  const Vec3 translate = r.has("translate") ? r.vec3("translate") : Vec3::Zero();
  const Eigen::Matrix3d rotation = Eigen::AngleAxisd(angle, Vec3::UnitY()).toRotationMatrix();
  m.topLeftCorner<3, 3>() = rotation * scale.asDiagonal();
  m.topRightCorner<3, 1>() = translate;
  return m;
}

void readObject(const Reader& r, const fs::path& baseDir, Scene& scene) {
  if (r.has("shape") == r.has("mesh"))
    throw UserError(concat(r.where(), ": give exactly one of 'shape' or 'mesh'"));
  if (r.has("mesh")) {
    r.allowOnly({"mesh", "transform", "material", "normals", "crease_angle"});
    const fs::path file = baseDir / r.text("mesh");
    NormalMode normals = NormalMode::File;
    if (r.has("normals")) {
      try {
        normals = kNormalModeNames.parse(r.text("normals"));
      } catch (const ParameterError& e) {
        throw UserError(concat(r.path("normals"), ": '", e.value(), "' ", e.problem()));
      }
    }
    const double crease =
        r.has("crease_angle") ? r.numberIn("crease_angle", 0, 180) : kDefaultCreaseDegrees;
    std::vector<TriangleMesh> parts;
    scene.files.push_back(file.string());
    try {
      parts = loadMeshFile(file.string(), normals, crease);
    } catch (const UserError& e) {
      throw UserError(concat(r.path("mesh"), ": ", e.what()));
    }
    if (r.has("material")) {
      const MaterialSpec spec = readMaterial(r.child("material"), baseDir);
      for (auto& mesh : parts) {
        overrideMaterial(mesh, spec, r.path("material"));
        warnOfMissingTangents(mesh, r.path("mesh"));
      }
    }
    if (r.has("transform")) {
      const Eigen::Matrix4d t = readTransform(r.child("transform"));
      // Normals follow the inverse transpose (non-uniform scale bends them).
      const Eigen::Matrix3d normalMatrix = t.topLeftCorner<3, 3>().inverse().transpose();
      for (auto& mesh : parts) {
        for (auto& v : mesh.vertices)
          v = (t.topLeftCorner<3, 3>() * v.cast<double>() + t.topRightCorner<3, 1>()).cast<float>();
        for (auto& n : mesh.normals)
          n = (normalMatrix * n.cast<double>()).normalized().cast<float>();
        // Tangents lie in the surface: they follow the matrix itself.
        for (auto& tangent : mesh.tangents)
          tangent = (t.topLeftCorner<3, 3>() * tangent.cast<double>()).cast<float>();
      }
    }
    for (auto& mesh : parts) scene.meshes.push_back(std::move(mesh));
    return;
  }
  const MaterialSpec spec = readShapeMaterial(r, baseDir);
  const Material& material = spec.material;
  const std::string shape = r.text("shape");
  if (shape == "sphere") {
    r.allowOnly({"shape", "center", "radius", "material"});
    if (spec.texture)
      throw UserError(concat(r.path("material"), ": spheres have no texture coordinates"));
    const double radius = r.number("radius");
    if (radius <= 0) throw UserError(concat(r.path("radius"), ": must be > 0"));
    scene.spheres.push_back({r.vec3("center"), radius, material});
  } else if (shape == "plane") {
    r.allowOnly({"shape", "center", "normal", "size", "material"});
    const Vec3 normal = r.vec3("normal");
    const double size = r.number("size");
    if (normal.norm() == 0) throw UserError(concat(r.path("normal"), ": must not be zero"));
    if (size <= 0) throw UserError(concat(r.path("size"), ": must be > 0"));
    TriangleMesh quad = makeQuad(r.vec3("center"), normal, size, material, r.where());
    quad.albedoTexture = spec.texture;
    scene.meshes.push_back(std::move(quad));
  } else {
    throw UserError(concat(r.path("shape"), ": unknown shape '", shape, "' (sphere or plane)"));
  }
}

}  // namespace

Scene loadSceneJson(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw UserError(concat(path, ": cannot open the scene file"));
  json doc;
  try {
    doc = json::parse(in);
  } catch (const json::exception& e) {
    throw UserError(concat(path, ": not valid JSON: ", e.what()));
  }
  const Reader root(doc, path);
  root.allowOnly({"camera", "cameras", "objects", "name"});
  Scene scene;
  scene.name = root.has("name") ? root.text("name") : fs::path(path).stem().string();
  if (root.has("camera") == root.has("cameras"))
    throw UserError(concat(path, ": give either 'camera' or 'cameras'"));
  if (root.has("cameras")) {
    scene.views = readCameras(root.at("cameras"), root.path("cameras"));
    scene.camera = scene.views[0];
  } else {
    scene.camera = readCamera(root.child("camera"));
  }
  const json& objects = root.at("objects");
  if (!objects.is_array() || objects.empty())
    throw UserError(concat(root.path("objects"), ": expected a non-empty array"));
  const fs::path baseDir = fs::path(path).parent_path();
  for (size_t i = 0; i < objects.size(); ++i)
    readObject(Reader(objects[i], concat(path, ": objects[", i, "]")), baseDir, scene);
  scene.files.push_back(path);
  for (const auto& mesh : scene.meshes)  // names of embedded textures are no files
    if (mesh.albedoTexture && fs::is_regular_file(mesh.albedoTexture->name()))
      scene.files.push_back(mesh.albedoTexture->name());
  scene.validate();
  return scene;
}

}  // namespace acpca
