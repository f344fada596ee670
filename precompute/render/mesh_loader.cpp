// Model files through assimp: OBJ, glTF, Collada, PLY and the other formats it
// reads. Parts are gathered per material, in the file's coordinates (node
// transforms applied), with the file's vertex normals as shading normals or
// smooth ones of our own, and the material's base colour and texture.
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <filesystem>
#include <map>

#include "core/error.h"
#include "core/warning.h"
#include "precompute/render/scene.h"

namespace acpca {

namespace fs = std::filesystem;

namespace {

/// A file material as a diffuse albedo: its colour and texture, and the
/// texture-coordinate set the texture reads.
struct FileMaterial {
  std::string name;
  Eigen::Vector3f color{1, 1, 1};
  std::shared_ptr<const Texture> texture;
  unsigned uvSet = 0;
};

class MaterialReader {
 public:
  MaterialReader(const aiScene* ai, const std::string& path) : ai_(ai), path_(path) {}

  FileMaterial read(unsigned index) {
    const aiMaterial* m = ai_->mMaterials[index];
    FileMaterial out;
    out.name = m->GetName().C_Str();
    if (out.name.empty()) out.name = concat("material ", index);
    // glTF's baseColorFactor, else the diffuse colour (OBJ Kd, Collada diffuse).
    aiColor4D color;
    if (m->Get(AI_MATKEY_BASE_COLOR, color) == AI_SUCCESS ||
        m->Get(AI_MATKEY_COLOR_DIFFUSE, color) == AI_SUCCESS)
      out.color = {color.r, color.g, color.b};
    for (aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE}) {
      if (m->GetTextureCount(type) == 0) continue;
      aiString file;
      unsigned uvSet = 0;
      if (m->GetTexture(type, 0, &file, nullptr, &uvSet) != AI_SUCCESS) continue;
      try {
        out.texture = texture(file.C_Str());
      } catch (const UserError& e) {
        // A missing or broken image is common in downloaded models.
        warn(concat(e.what(), "; material '", out.name, "' keeps its base colour"));
        break;
      }
      out.uvSet = uvSet;
      aiUVTransform transform;
      if (m->Get(AI_MATKEY_UVTRANSFORM(type, 0), transform) == AI_SUCCESS &&
          (transform.mTranslation != aiVector2D(0, 0) || transform.mScaling != aiVector2D(1, 1) ||
           transform.mRotation != 0))
        warn(concat(path_, ": material '", out.name,
                    "': its texture transform (KHR_texture_transform) is ignored"));
      break;
    }
    return out;
  }

 private:
  /// Each image once, however many materials use it.
  std::shared_ptr<const Texture> texture(const std::string& reference) {
    auto& cached = cache_[reference];
    if (!cached) cached = load(reference);
    return cached;
  }

  std::shared_ptr<const Texture> load(const std::string& reference) {
    if (const aiTexture* embedded = ai_->GetEmbeddedTexture(reference.c_str())) {
      const std::string name = concat(path_, ": embedded texture '", reference, "'");
      if (embedded->mHeight == 0)  // compressed: the image file's bytes
        return loadTextureFromMemory(name, embedded->achFormatHint, embedded->pcData,
                                     embedded->mWidth);
      // Raw 8-bit BGRA texels, top row first, sRGB-encoded like any 8-bit image.
      std::vector<float> rgb;
      rgb.reserve(3 * size_t(embedded->mWidth) * embedded->mHeight);
      for (size_t t = 0; t < size_t(embedded->mWidth) * embedded->mHeight; ++t)
        for (unsigned char c :
             {embedded->pcData[t].r, embedded->pcData[t].g, embedded->pcData[t].b})
          rgb.push_back(srgbToLinear(c / 255.0f));
      return std::make_shared<const Texture>(name, int(embedded->mWidth), int(embedded->mHeight),
                                             std::move(rgb));
    }
    // Paths are relative to the model file; exporters on Windows write '\'.
    std::string relative = reference;
    for (char& c : relative)
      if (c == '\\') c = '/';
    return loadTexture((fs::path(path_).parent_path() / relative).string());
  }

  const aiScene* ai_;
  std::string path_;
  std::map<std::string, std::shared_ptr<const Texture>> cache_;
};

/// What collect gathers: one mesh of every part, each triangle tagged with its
/// group (material, has texture coordinates); uvs for every corner, (0, 0)
/// where the part has none (those are dropped when groups are split).
struct Gathered {
  TriangleMesh all;
  std::vector<std::pair<unsigned, bool>> groupOfTriangle;
  std::vector<FileMaterial> materials;
  int partsWithoutNormals = 0;
  int texturedPartsWithoutUvs = 0;
};

/// Adds every mesh under `node`, in the file's coordinates. With `normals`, each
/// corner also gets the file's vertex normal (transformed by the inverse
/// transpose).
void collect(const aiScene* ai, const aiNode* node, const aiMatrix4x4& parent, bool normals,
             Gathered& out) {
  const aiMatrix4x4 transform = parent * node->mTransformation;
  aiMatrix3x3 normalTransform(transform);
  normalTransform.Inverse().Transpose();
  TriangleMesh& mesh = out.all;
  for (unsigned i = 0; i < node->mNumMeshes; ++i) {
    const aiMesh* part = ai->mMeshes[node->mMeshes[i]];
    if (part->mMaterialIndex >= out.materials.size())
      throw UserError(concat("part '", part->mName.C_Str(), "' names material ",
                             part->mMaterialIndex, " of ", out.materials.size()));
    const FileMaterial& material = out.materials[part->mMaterialIndex];
    // Coordinates are kept wherever the part has them (a scene file may give
    // its own texture); the file's texture needs them.
    const bool textured = part->HasTextureCoords(material.uvSet);
    if (material.texture && !textured) ++out.texturedPartsWithoutUvs;
    const int offset = static_cast<int>(mesh.vertices.size());
    for (unsigned v = 0; v < part->mNumVertices; ++v) {
      const aiVector3D p = transform * part->mVertices[v];
      mesh.vertices.emplace_back(p.x, p.y, p.z);
    }
    const bool hasNormals = normals && part->HasNormals();
    if (normals && !hasNormals) ++out.partsWithoutNormals;
    for (unsigned t = 0; t < part->mNumFaces; ++t) {
      const aiFace& face = part->mFaces[t];
      if (face.mNumIndices != 3) continue;  // points and lines left by triangulation
      const unsigned* corner = face.mIndices;
      mesh.triangles.emplace_back(offset + corner[0], offset + corner[1], offset + corner[2]);
      out.groupOfTriangle.emplace_back(part->mMaterialIndex, textured);
      for (int k = 0; k < 3; ++k) {
        const aiVector3D uv =
            textured ? part->mTextureCoords[material.uvSet][corner[k]] : aiVector3D(0, 0, 0);
        mesh.uvs.emplace_back(uv.x, uv.y);
        if (!normals) continue;
        const aiVector3D n =
            hasNormals ? normalTransform * part->mNormals[corner[k]] : aiVector3D(0, 0, 0);
        mesh.normals.emplace_back(n.x, n.y, n.z);
      }
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c)
    collect(ai, node->mChildren[c], transform, normals, out);
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
      if (group.second) mesh.uvs.push_back(g.all.uvs[3 * t + k]);
    }
    mesh.triangles.push_back(tri);
  }
  return mesh;
}

}  // namespace

std::vector<TriangleMesh> loadMeshFile(const std::string& path, NormalMode normals,
                                       double creaseDegrees) {
  if (!fs::is_regular_file(path)) throw UserError(concat(path, ": mesh file not found"));
  Assimp::Importer importer;
  // No vertex joining or normal generation: the file's normals or our own.
  const aiScene* ai = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_SortByPType);
  if (!ai || !ai->mRootNode || (ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw UserError(concat(path, ": cannot read the mesh: ", importer.GetErrorString()));
  Gathered gathered;
  MaterialReader reader(ai, path);
  for (unsigned m = 0; m < ai->mNumMaterials; ++m) gathered.materials.push_back(reader.read(m));
  if (gathered.materials.empty()) gathered.materials.emplace_back();  // formats without any
  try {
    collect(ai, ai->mRootNode, aiMatrix4x4(), normals == NormalMode::File, gathered);
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
    meshes.push_back(std::move(mesh));
  }
  return meshes;
}

}  // namespace acpca
