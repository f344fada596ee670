// Smooth shading normals for meshes that bring none (design: docs/scenes.md).
#include <cmath>
#include <map>
#include <numbers>

#include "precompute/scene.h"

namespace acpca {

void smoothNormals(TriangleMesh& mesh, double creaseDegrees) {
  const size_t count = mesh.triangles.size();
  // Vertices at the same position are one vertex here: files often split them
  // along UV seams, which must not become shading creases.
  std::map<std::array<float, 3>, int> positionId;
  std::vector<int> idOf(mesh.vertices.size());
  for (size_t v = 0; v < mesh.vertices.size(); ++v) {
    const auto& p = mesh.vertices[v];
    idOf[v] = positionId.emplace(std::array<float, 3>{p.x(), p.y(), p.z()}, positionId.size())
                  .first->second;
  }
  // Area-weighted face normals (the cross product's length is twice the area).
  std::vector<Eigen::Vector3d> faceNormal(count);
  std::vector<std::vector<int>> trianglesAt(positionId.size());
  for (size_t t = 0; t < count; ++t) {
    const auto& tri = mesh.triangles[t];
    const Eigen::Vector3d a = mesh.vertices[tri[0]].cast<double>(),
                          b = mesh.vertices[tri[1]].cast<double>(),
                          c = mesh.vertices[tri[2]].cast<double>();
    faceNormal[t] = (b - a).cross(c - a);
    for (int k = 0; k < 3; ++k) trianglesAt[idOf[tri[k]]].push_back(static_cast<int>(t));
  }
  const double cosCrease = std::cos(creaseDegrees * std::numbers::pi / 180);
  mesh.normals.assign(3 * count, Eigen::Vector3f::Zero());
  for (size_t t = 0; t < count; ++t) {
    const Eigen::Vector3d own = faceNormal[t].normalized();
    for (int k = 0; k < 3; ++k) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int other : trianglesAt[idOf[mesh.triangles[t][k]]]) {
        const double length = faceNormal[other].norm();
        if (length > 0 && faceNormal[other].dot(own) >= cosCrease * length)
          sum += faceNormal[other];
      }
      // A zero-area triangle has no normal of its own and covers nothing (the
      // renderer leaves it out): any unit vector keeps the mesh valid.
      if (!(sum.norm() > 0)) sum = Eigen::Vector3d::UnitY();
      mesh.normals[3 * t + k] = sum.normalized().cast<float>();
    }
  }
}

}  // namespace acpca
