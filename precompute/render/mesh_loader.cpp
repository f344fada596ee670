// Mesh files through assimp: OBJ, PLY, glTF and the other formats it reads. All
// parts are merged into one mesh in the file's coordinates (node transforms applied),
// with the file's vertex normals as shading normals, or smooth ones of our own.
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <filesystem>

#include "core/error.h"
#include "core/warning.h"
#include "precompute/render/scene.h"

namespace acpca {

namespace {

/// Merges every mesh under `node` into `out`, in the file's coordinates. With
/// `normals`, each corner also gets the file's vertex normal (transformed by
/// the inverse transpose); `missingNormals` counts parts that have none.
void collect(const aiScene* ai, const aiNode* node, const aiMatrix4x4& parent, bool normals,
             TriangleMesh& out, int& missingNormals) {
  const aiMatrix4x4 transform = parent * node->mTransformation;
  aiMatrix3x3 normalTransform(transform);
  normalTransform.Inverse().Transpose();
  for (unsigned i = 0; i < node->mNumMeshes; ++i) {
    const aiMesh* mesh = ai->mMeshes[node->mMeshes[i]];
    const int offset = static_cast<int>(out.vertices.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D p = transform * mesh->mVertices[v];
      out.vertices.emplace_back(p.x, p.y, p.z);
    }
    const bool hasNormals = normals && mesh->HasNormals();
    if (normals && !hasNormals) ++missingNormals;
    for (unsigned t = 0; t < mesh->mNumFaces; ++t) {
      const aiFace& face = mesh->mFaces[t];
      if (face.mNumIndices != 3) continue;  // points and lines left by triangulation
      out.triangles.emplace_back(offset + face.mIndices[0], offset + face.mIndices[1],
                                 offset + face.mIndices[2]);
      if (!normals) continue;
      for (int k = 0; k < 3; ++k) {
        aiVector3D n =
            hasNormals ? normalTransform * mesh->mNormals[face.mIndices[k]] : aiVector3D(0, 0, 0);
        out.normals.emplace_back(n.x, n.y, n.z);
      }
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c)
    collect(ai, node->mChildren[c], transform, normals, out, missingNormals);
}

}  // namespace

TriangleMesh loadMeshFile(const std::string& path, NormalMode normals, double creaseDegrees) {
  if (!std::filesystem::is_regular_file(path))
    throw UserError(concat(path, ": mesh file not found"));
  Assimp::Importer importer;
  // No vertex joining or normal generation: the file's normals or our own.
  const aiScene* ai = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_SortByPType);
  if (!ai || !ai->mRootNode || (ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw UserError(concat(path, ": cannot read the mesh: ", importer.GetErrorString()));
  TriangleMesh mesh;
  mesh.name = std::filesystem::path(path).filename().string();
  int missingNormals = 0;
  collect(ai, ai->mRootNode, aiMatrix4x4(), normals == NormalMode::File, mesh, missingNormals);
  if (mesh.triangles.empty()) throw UserError(concat(path, ": the mesh has no triangles"));
  for (const auto& v : mesh.vertices)
    if (!v.allFinite()) throw UserError(concat(path, ": the mesh has NaN or infinite vertices"));
  if (normals == NormalMode::File && missingNormals > 0) {
    warn(concat(path, ": no vertex normals in ", missingNormals,
                " part(s); smooth normals computed (crease angle ", creaseDegrees, " degrees)"));
    normals = NormalMode::Smooth;
  }
  if (normals == NormalMode::File) {
    // Zero or non-finite normals in the file (degenerate faces) take the
    // smooth normal of their corner.
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
    if (replaced > 0)
      warn(concat(path, ": ", replaced,
                  " zero or non-finite vertex normals replaced by smooth ones"));
  }
  if (normals == NormalMode::Smooth) smoothNormals(mesh, creaseDegrees);
  if (normals == NormalMode::Flat) mesh.normals.clear();
  return mesh;
}

}  // namespace acpca
