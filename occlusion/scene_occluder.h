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

  /// Up to kPacket rays at once (structure of arrays), traced as one packet:
  /// neighbouring pixels' rays to one lamp run close together, and a packet
  /// shares their walk through the scene. A ray is blocked when any surface
  /// lies on it from its origin along its unit direction strictly between
  /// `nearest` and `farthest`. Thread safe.
  static constexpr int kPacket = 16;
  struct Packet {
    int count = 0;
    float ox[kPacket], oy[kPacket], oz[kPacket], dx[kPacket], dy[kPacket], dz[kPacket];
    float nearest[kPacket], farthest[kPacket];
    bool blocked[kPacket];  ///< set by trace
  };
  void trace(Packet& packet) const;

 private:
  struct Embree;
  std::unique_ptr<Embree> embree_;
};

}  // namespace acpca
