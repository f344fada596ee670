// Mesh files through assimp: OBJ, PLY, glTF and the other formats it reads. All
// parts are merged into one mesh in the file's coordinates (node transforms applied).
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <assimp/Importer.hpp>
#include <filesystem>

#include "core/error.h"
#include "precompute/render/scene.h"

namespace acpca {

namespace {

void collect(const aiScene* ai, const aiNode* node, const aiMatrix4x4& parent, TriangleMesh& out) {
  const aiMatrix4x4 transform = parent * node->mTransformation;
  for (unsigned i = 0; i < node->mNumMeshes; ++i) {
    const aiMesh* mesh = ai->mMeshes[node->mMeshes[i]];
    const int offset = static_cast<int>(out.vertices.size());
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D p = transform * mesh->mVertices[v];
      out.vertices.emplace_back(p.x, p.y, p.z);
    }
    for (unsigned t = 0; t < mesh->mNumFaces; ++t) {
      const aiFace& face = mesh->mFaces[t];
      if (face.mNumIndices != 3) continue;  // points and lines left by triangulation
      out.triangles.emplace_back(offset + face.mIndices[0], offset + face.mIndices[1],
                                 offset + face.mIndices[2]);
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) collect(ai, node->mChildren[c], transform, out);
}

}  // namespace

TriangleMesh loadMeshFile(const std::string& path) {
  if (!std::filesystem::is_regular_file(path))
    throw UserError(concat(path, ": mesh file not found"));
  Assimp::Importer importer;
  // No vertex joining or normal generation: we shade with geometric normals.
  const aiScene* ai = importer.ReadFile(path, aiProcess_Triangulate | aiProcess_SortByPType);
  if (!ai || !ai->mRootNode || (ai->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw UserError(concat(path, ": cannot read the mesh: ", importer.GetErrorString()));
  TriangleMesh mesh;
  mesh.name = std::filesystem::path(path).filename().string();
  collect(ai, ai->mRootNode, aiMatrix4x4(), mesh);
  if (mesh.triangles.empty()) throw UserError(concat(path, ": the mesh has no triangles"));
  for (const auto& v : mesh.vertices)
    if (!v.allFinite()) throw UserError(concat(path, ": the mesh has NaN or infinite vertices"));
  return mesh;
}

}  // namespace acpca
