#pragma once
// Shadow rays gathered into the occluder's packets: neighbouring samples'
// rays to one lamp run close together, and a packet shares their walk
// through the scene. Each ray carries a tag and what it brings, handed to
// `reached` when nothing blocks it, in the order the rays were added.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <utility>

#include "occlusion/scene_occluder.h"

namespace acpca {

template <typename Reached>
class ShadowRayBatch {
 public:
  /// Rays start `nearest` along their direction (the file's ray epsilon).
  ShadowRayBatch(const SceneOccluder& occluder, float nearest, Reached reached)
      : occluder_(occluder), nearest_(nearest), reached_(std::move(reached)) {}
  ShadowRayBatch(const ShadowRayBatch&) = delete;
  ShadowRayBatch& operator=(const ShadowRayBatch&) = delete;
  ~ShadowRayBatch() = default;  // callers flush: `reached` may refer to what dies first

  /// Queues a ray along the unit `direction`, stopped at `farthest`.
  void add(const Eigen::Vector3f& origin, const Eigen::Vector3f& direction, float farthest,
           std::int64_t tag, double light) {
    const int i = packet_.count++;
    packet_.ox[i] = origin.x(), packet_.oy[i] = origin.y(), packet_.oz[i] = origin.z();
    packet_.dx[i] = direction.x(), packet_.dy[i] = direction.y(), packet_.dz[i] = direction.z();
    packet_.nearest[i] = nearest_, packet_.farthest[i] = farthest;
    pending_[i] = {tag, light};
    ++rays_;
    if (packet_.count == SceneOccluder::kPacket) flush();
  }

  /// How many rays were added.
  long long rays() const { return rays_; }

  /// Traces what is queued.
  void flush() {
    if (packet_.count == 0) return;
    occluder_.trace(packet_);
    for (int i = 0; i < packet_.count; ++i)
      if (!packet_.blocked[i]) reached_(pending_[i].first, pending_[i].second);
    packet_.count = 0;
  }

 private:
  const SceneOccluder& occluder_;
  float nearest_;
  Reached reached_;
  SceneOccluder::Packet packet_;
  long long rays_ = 0;
  std::array<std::pair<std::int64_t, double>, SceneOccluder::kPacket> pending_;
};

}  // namespace acpca
