#pragma once
// The surfaces a transport or model file stores (transport/lamp_geometry.h)
// in an Embree scene of their own, asked only whether segments are blocked:
// a lamp's shadow rays at relight time (docs/lighting.md, "Lamps").
#include <Eigen/Core>
#include <memory>

#include "transport/lamp_geometry.h"

namespace acpca {

class SceneOccluder {
 public:
  /// Builds the scene from the geometry's triangles and spheres (robust
  /// intersection, as the precompute's, so the same rays meet the same
  /// surfaces). A geometry of no surfaces blocks nothing.
  explicit SceneOccluder(const LampGeometry& geometry);
  ~SceneOccluder();
  SceneOccluder(const SceneOccluder&) = delete;
  SceneOccluder& operator=(const SceneOccluder&) = delete;

  /// Whether any surface lies on the ray from `origin` along the unit
  /// `direction` strictly between `nearest` and `farthest`. Thread safe.
  bool blocked(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float nearest,
               float farthest) const;

 private:
  struct Embree;
  std::unique_ptr<Embree> embree_;
};

}  // namespace acpca
