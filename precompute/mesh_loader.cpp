// Model files through assimp (mesh_import.h): OBJ, glTF, Collada, PLY and the
// other formats it reads. Parts are gathered per material, in the file's coordinates (node
// transforms applied), with the file's vertex normals as shading normals or
// smooth ones of our own, and the material's base colour and texture.
#include <algorithm>
#include <filesystem>
#include <limits>
#include <map>

#include "core/error.h"
#include "core/warning.h"
#include "precompute/mesh_import.h"
#include "precompute/scene.h"

namespace acpca {

namespace fs = std::filesystem;

namespace {

/// A file material as a diffuse albedo: its colour and texture, and the
/// texture-coordinate set the texture reads.
struct FileMaterial {
  std::string name;
  Eigen::Vector3f color{1, 1, 1};
  std::shared_ptr<const Texture> texture;
};

/// The materials' textures, each image read once however many materials use it.
class MaterialReader {
 public:
  explicit MaterialReader(const std::string& path) : path_(path) {}

  FileMaterial read(const ImportedMaterial& m, unsigned index) {
    FileMaterial out;
    out.name = m.name.empty() ? concat("material ", index) : m.name;
    if (m.hasColor) out.color = {m.color[0], m.color[1], m.color[2]};
    if (m.textureReference.empty()) return out;
    try {
      auto& cached = cache_[m.textureReference];
      if (!cached) cached = load(m);
      out.texture = cached;
    } catch (const UserError& e) {
      // A missing or broken image is common in downloaded models.
      warn(concat(e.what(), "; material '", out.name, "' keeps its base colour"));
      return out;
    }
    if (m.textureTransformed)
      warn(concat(path_, ": material '", out.name,
                  "': its texture transform (KHR_texture_transform) is ignored"));
    return out;
  }

 private:
  std::shared_ptr<const Texture> load(const ImportedMaterial& m) {
    if (m.embedded) {
      const std::string name = concat(path_, ": embedded texture '", m.textureReference, "'");
      if (m.embeddedHeight == 0)  // compressed: the image file's bytes
        return loadTextureFromMemory(name, m.formatHint, m.embeddedBytes.data(),
                                     m.embeddedBytes.size());
      // Raw 8-bit BGRA texels, top row first, sRGB-encoded like any 8-bit image.
      const size_t texels = size_t(m.embeddedWidth) * m.embeddedHeight;
      if (m.embeddedBytes.size() != 4 * texels)
        throw UserError(concat(name, ": ", m.embeddedBytes.size(), " bytes for ", m.embeddedWidth,
                               "x", m.embeddedHeight, " texels"));
      std::vector<float> rgb;
      rgb.reserve(3 * texels);
      for (size_t t = 0; t < texels; ++t)
        for (int c : {2, 1, 0})
          rgb.push_back(static_cast<float>(srgbToLinear(m.embeddedBytes[4 * t + c] / 255.0)));
      return std::make_shared<const Texture>(name, int(m.embeddedWidth), int(m.embeddedHeight),
                                             std::move(rgb));
    }
    // Paths are relative to the model file; exporters on Windows write '\'.
    std::string relative = m.textureReference;
    for (char& c : relative)
      if (c == '\\') c = '/';
    return loadTexture((fs::path(path_).parent_path() / relative).string());
  }

  std::string path_;
  std::map<std::string, std::shared_ptr<const Texture>> cache_;
};

/// What gather builds: one mesh of every part, each triangle tagged with its
/// group (material, has texture coordinates); uvs for every corner, (0, 0)
/// where the part has none (those are dropped when groups are split).
struct Gathered {
  TriangleMesh all;
  std::vector<std::pair<unsigned, bool>> groupOfTriangle;
  std::vector<FileMaterial> materials;
  int partsWithoutNormals = 0;
  int texturedPartsWithoutUvs = 0;
};

/// Adds every part the importer returned, checking what it could not: a
/// material and vertices for every index, and the arrays' lengths. With
/// `normals`, each corner also gets the file's vertex normal.
void gather(const ImportedModel& model, bool normals, Gathered& out) {
  TriangleMesh& mesh = out.all;
  for (const ImportedPart& part : model.parts) {
    const std::string what = concat("part '", part.name, "'");
    if (part.material >= out.materials.size())
      throw UserError(
          concat(what, " names material ", part.material, " of ", out.materials.size()));
    const size_t vertices = part.positions.size() / 3;
    if (part.positions.size() % 3 != 0 ||
        (!part.normals.empty() && part.normals.size() != 3 * vertices) ||
        (!part.uvs.empty() && part.uvs.size() != 2 * vertices) ||
        (!part.tangents.empty() && part.tangents.size() != 3 * vertices) ||
        part.corners.size() % 3 != 0)
      throw UserError(concat(what, ": its vertex arrays do not match in length"));
    if (mesh.vertices.size() + vertices > size_t(std::numeric_limits<int>::max()))
      throw UserError(concat(what, ": more vertices than the renderer indexes"));
    for (const std::uint32_t c : part.corners)
      if (c >= vertices)
        throw UserError(concat(what, ": a triangle indexes vertex ", c, " of ", vertices));
    const FileMaterial& material = out.materials[part.material];
    // Coordinates are kept wherever the part has them (a scene file may give
    // its own texture); the file's texture needs them.
    const bool textured = !part.uvs.empty();
    if (material.texture && !textured) ++out.texturedPartsWithoutUvs;
    const int offset = static_cast<int>(mesh.vertices.size());
    for (size_t v = 0; v < vertices; ++v)
      mesh.vertices.emplace_back(part.positions[3 * v], part.positions[3 * v + 1],
                                 part.positions[3 * v + 2]);
    const bool hasNormals = normals && !part.normals.empty();
    if (normals && !hasNormals) ++out.partsWithoutNormals;
    for (size_t t = 0; t < part.corners.size(); t += 3) {
      const std::uint32_t* corner = &part.corners[t];
      mesh.triangles.emplace_back(offset + int(corner[0]), offset + int(corner[1]),
                                  offset + int(corner[2]));
      out.groupOfTriangle.emplace_back(part.material, textured);
      for (int k = 0; k < 3; ++k) {
        const size_t v = corner[k];
        mesh.uvs.emplace_back(textured ? part.uvs[2 * v] : 0.0f,
                              textured ? part.uvs[2 * v + 1] : 0.0f);
        // Every corner gets one; zero where the part has none (tangentsAcross).
        mesh.tangents.push_back(part.tangents.empty() ? Eigen::Vector3f::Zero()
                                                      : Eigen::Vector3f(part.tangents[3 * v],
                                                                        part.tangents[3 * v + 1],
                                                                        part.tangents[3 * v + 2]));
        if (!normals) continue;
        mesh.normals.push_back(hasNormals
                                   ? Eigen::Vector3f(part.normals[3 * v], part.normals[3 * v + 1],
                                                     part.normals[3 * v + 2])
                                   : Eigen::Vector3f::Zero());
      }
    }
  }
}

/// Zero or non-finite normals in the file (degenerate faces) take the smooth
/// normal of their corner; returns how many.
long long repairFileNormals(TriangleMesh& mesh, double creaseDegrees) {
  TriangleMesh smooth;
  long long replaced = 0;
  for (size_t i = 0; i < mesh.normals.size(); ++i) {
    auto& n = mesh.normals[i];
    if (n.allFinite() && n.norm() > 1e-12f) {
      n.normalize();
      continue;
    }
    if (replaced++ == 0) {
      smooth = mesh;
      smoothNormals(smooth, creaseDegrees);
    }
    n = smooth.normals[i];
  }
  return replaced;
}

/// Tangents that are undefined (no texture coordinates, degenerate ones) or
/// parallel to their corner's normal become zero: the stated fallback,
/// world +X across the normal, is taken where they are (docs/scenes.md,
/// "Tangents"). Returns how many corners have none.
long long clearUnusableTangents(TriangleMesh& mesh) {
  long long cleared = 0;
  for (size_t c = 0; c < mesh.tangents.size(); ++c) {
    Eigen::Vector3f& t = mesh.tangents[c];
    const Eigen::Vector3i& tri = mesh.triangles[c / 3];
    const Eigen::Vector3f n = mesh.normals.empty()
                                  ? (mesh.vertices[tri[1]] - mesh.vertices[tri[0]])
                                        .cross(mesh.vertices[tri[2]] - mesh.vertices[tri[0]])
                                        .normalized()
                                  : mesh.normals[c].normalized();
    const bool usable =
        t.allFinite() && n.allFinite() && (t - n.dot(t) * n).norm() > 1e-4f * t.norm();
    if (!usable) t.setZero(), ++cleared;
  }
  return cleared;
}

/// The triangles of one group as their own mesh (vertices renumbered).
TriangleMesh groupMesh(const Gathered& g, std::pair<unsigned, bool> group) {
  TriangleMesh mesh;
  std::vector<int> renumbered(g.all.vertices.size(), -1);
  for (size_t t = 0; t < g.all.triangles.size(); ++t) {
    if (g.groupOfTriangle[t] != group) continue;
    Eigen::Vector3i tri;
    for (int k = 0; k < 3; ++k) {
      int& v = renumbered[g.all.triangles[t][k]];
      if (v < 0) {
        v = static_cast<int>(mesh.vertices.size());
        mesh.vertices.push_back(g.all.vertices[g.all.triangles[t][k]]);
      }
      tri[k] = v;
      if (!g.all.normals.empty()) mesh.normals.push_back(g.all.normals[3 * t + k]);
      mesh.tangents.push_back(g.all.tangents[3 * t + k]);
      if (group.second) mesh.uvs.push_back(g.all.uvs[3 * t + k]);
    }
    mesh.triangles.push_back(tri);
  }
  return mesh;
}

}  // namespace

std::vector<TriangleMesh> loadMeshFile(const std::string& path, NormalMode normals,
                                       double creaseDegrees, double importSeconds) {
  if (!fs::is_regular_file(path)) throw UserError(concat(path, ": mesh file not found"));
  const ImportedModel model = importModelIsolated(path, importSeconds);
  Gathered gathered;
  MaterialReader reader(path);
  for (unsigned m = 0; m < model.materials.size(); ++m)
    gathered.materials.push_back(reader.read(model.materials[m], m));
  if (gathered.materials.empty()) gathered.materials.emplace_back();  // formats without any
  try {
    gather(model, normals == NormalMode::File, gathered);
  } catch (const UserError& e) {
    throw UserError(concat(path, ": ", e.what()));
  }
  if (gathered.texturedPartsWithoutUvs > 0)
    warn(concat(path, ": ", gathered.texturedPartsWithoutUvs,
                " textured part(s) have no texture coordinates; their base colour is used"));
  if (normals == NormalMode::File && gathered.partsWithoutNormals > 0) {
    warn(concat(path, ": no vertex normals in ", gathered.partsWithoutNormals,
                " part(s); smooth normals computed (crease angle ", creaseDegrees, " degrees)"));
    normals = NormalMode::Smooth;
  }
  TriangleMesh& all = gathered.all;
  if (all.triangles.empty()) throw UserError(concat(path, ": the mesh has no triangles"));
  for (const auto& v : all.vertices)
    if (!v.allFinite()) throw UserError(concat(path, ": the mesh has NaN or infinite vertices"));
  for (const auto& uv : all.uvs)
    if (!uv.allFinite())
      throw UserError(concat(path, ": the mesh has NaN or infinite texture coordinates"));
  // Normals over the whole model, so smoothing crosses material boundaries.
  if (normals == NormalMode::File) {
    if (const long long replaced = repairFileNormals(all, creaseDegrees))
      warn(concat(path, ": ", replaced,
                  " zero or non-finite vertex normals replaced by smooth ones"));
  }
  if (normals == NormalMode::Smooth) smoothNormals(all, creaseDegrees);
  if (normals == NormalMode::Flat) all.normals.clear();
  clearUnusableTangents(all);

  std::map<std::pair<unsigned, bool>, int> groups;  // ordered: same meshes every run
  for (const auto& group : gathered.groupOfTriangle) groups[group] = 0;
  const std::string file = fs::path(path).filename().string();
  std::vector<TriangleMesh> meshes;
  for (const auto& [group, unused] : groups) {
    TriangleMesh mesh = groupMesh(gathered, group);
    const FileMaterial& material = gathered.materials[group.first];
    mesh.name = concat(file, "/", material.name);
    mesh.material.type = Material::Type::Diffuse;
    mesh.material.albedo = material.color;
    if (group.second) mesh.albedoTexture = material.texture;  // nullptr without one
    // Whether a part's tangents are usable matters only once a scene file
    // makes it anisotropic (scene_json.cpp warns then).
    if (std::all_of(mesh.tangents.begin(), mesh.tangents.end(),
                    [](const Eigen::Vector3f& t) { return t.isZero(); }))
      mesh.tangents.clear();
    meshes.push_back(std::move(mesh));
  }
  return meshes;
}

}  // namespace acpca
