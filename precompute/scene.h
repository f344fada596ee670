#pragma once
// A renderable scene: a camera, triangle meshes and analytic spheres, each with a
// material. Built-in scenes (builtin_scenes.cpp) and JSON files (scene_json.cpp)
// both produce one.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/enum_names.h"
#include "precompute/texture.h"
#include "transport/camera.h"
#include "transport/material.h"

namespace acpca {

struct TriangleMesh {
  std::string name;
  std::vector<Eigen::Vector3f> vertices;
  std::vector<Eigen::Vector3i> triangles;
  Material material;
  /// Shading normals, three per triangle (one per corner, so creases can keep
  /// their edge), interpolated across each triangle; empty: flat shading with
  /// the geometric normal.
  std::vector<Eigen::Vector3f> normals;
  /// Tangents, three per triangle like the normals (the file's, or from its
  /// texture coordinates), interpolated and then taken across the shading
  /// normal; empty: world +X across the normal (+Z where the normal is
  /// along X), as for planes (docs/scenes.md, "Tangents").
  std::vector<Eigen::Vector3f> tangents;
  /// Texture coordinates, three per triangle like the normals (empty: none).
  std::vector<Eigen::Vector2f> uvs;
  /// Multiplies material.albedo at each point (the file's base colour or
  /// diffuse texture); needs uvs. Shared: meshes of one file may use one image.
  std::shared_ptr<const Texture> albedoTexture;
};

/// A mesh with a name and a material and no triangles yet.
inline TriangleMesh emptyMesh(std::string name, const Material& material) {
  TriangleMesh mesh;
  mesh.name = std::move(name);
  mesh.material = material;
  return mesh;
}

/// Where a mesh's shading normals come from: the file's own, computed smooth
/// across edges sharper than no crease angle, or none (flat).
enum class NormalMode { File, Smooth, Flat };
inline constexpr EnumNames<NormalMode, 3> kNormalModeNames{
    "normals",
    {{{NormalMode::File, "file"}, {NormalMode::Smooth, "smooth"}, {NormalMode::Flat, "flat"}}}};
/// Edges whose faces meet at more than this stay sharp when normals are smoothed.
inline constexpr double kDefaultCreaseDegrees = 60;

/// Per-corner normals averaging, at each corner, the area-weighted normals of
/// the triangles around its vertex that lie within `creaseDegrees` of the
/// corner's own triangle (vertices at the same position count as one).
void smoothNormals(TriangleMesh& mesh, double creaseDegrees = kDefaultCreaseDegrees);

struct Sphere {
  Vec3 center{0, 0, 0};
  double radius = 1;
  Material material;
};

struct Scene {
  std::string name;
  Camera camera;
  std::vector<TriangleMesh> meshes;
  std::vector<Sphere> spheres;
  /// The files it was read from (scene file, meshes, textures): what no
  /// output may replace. Empty for a built-in scene.
  std::vector<std::string> files;
  /// Several views of the scene ("cameras" in a scene file; docs/scenes.md,
  /// "Several views"): each is precomputed on its own, camera set to it.
  /// Empty: `camera` alone.
  std::vector<Camera> views;

  long long triangleCount() const;
  /// Each object's name in the order the ray tracer numbers them (meshes,
  /// then spheres): what a pixel's object id indexes.
  std::vector<std::string> objectNames() const;
  /// The scene seen from view k (camera set to it); k = 0 with no views is
  /// the scene itself.
  Scene view(size_t k) const;
  size_t viewCount() const { return views.empty() ? 1 : views.size(); }
  /// The bounding box of all geometry (empty for an empty scene).
  Eigen::AlignedBox3d bounds() const;
  /// Diagonal of the bounding box of all geometry (sets ray offsets).
  double extent() const;
  /// Throws UserError naming the object and what is wrong: non-finite or
  /// out-of-range values, indices outside a mesh, an empty scene.
  void validate() const;
  /// The same camera at a pixel grid `width` wide, its height following the
  /// aspect (at least 1), validated.
  Scene atWidth(int width) const;
};

/// Builders for the primitives that scenes are made of.
TriangleMesh makeQuad(const Vec3& center, const Vec3& normal, double size, const Material& m,
                      const std::string& name);
TriangleMesh makeBox(const Vec3& lo, const Vec3& hi, const Material& m, const std::string& name);
/// Appends mesh b to mesh a (materials must agree; a keeps its own).
void appendMesh(TriangleMesh& a, const TriangleMesh& b);

/// Name and one-line description of a built-in scene.
struct BuiltinSceneInfo {
  std::string name;
  std::string description;
};
std::vector<BuiltinSceneInfo> builtinScenes();
bool isBuiltinScene(const std::string& name);
/// Throws UserError if the name is unknown.
Scene makeBuiltinScene(const std::string& name);
/// The procedural potted plant (plant.cpp); fixed seed, so always the same.
Scene makePlantScene();

/// The box a framing camera fits: every object's, leaving out flat ones
/// (floors, backdrops) when anything else is there.
Eigen::AlignedBox3d framedBounds(const Scene& scene);
/// The scene's camera (fov and size kept) moved to look at the centre of
/// framedBounds from `fromDirection`, just far enough that the bounding sphere
/// times `margin` fits the narrower field of view; +Y up (-Z looking straight
/// up or down).
Camera frameCamera(const Scene& scene, const Vec3& fromDirection, double margin = 1.05);
/// "auto": frame the scene from its own camera's direction; "auto:THETA,PHI":
/// from that direction (degrees, as directionFromAngles); "": leave it.
/// Throws ParameterError ("camera") for anything else.
void applyCameraSpec(Scene& scene, const std::string& spec);

/// Built-in name or path to a scene JSON file (docs/scenes.md).
Scene loadScene(const std::string& nameOrPath);
Scene loadSceneJson(const std::string& path);
/// Loads a model file (OBJ, glTF, Collada, PLY and the other formats assimp
/// reads) in the file's coordinates, node transforms applied: one mesh per
/// material of the file, each diffuse with the file's base colour (glTF
/// baseColorFactor, else the diffuse colour: OBJ Kd, Collada diffuse) times
/// its base-colour or diffuse texture when it has one and texture coordinates.
/// Shading normals: the file's with NormalMode::File (smooth ones, with a
/// warning, when it has none), computed with Smooth, none with Flat.
/// assimp reads the file in a child process given `importSeconds` (negative:
/// a minute plus a second per MiB; precompute/mesh_import.h).
std::vector<TriangleMesh> loadMeshFile(const std::string& path,
                                       NormalMode normals = NormalMode::File,
                                       double creaseDegrees = kDefaultCreaseDegrees,
                                       double importSeconds = -1);

}  // namespace acpca
