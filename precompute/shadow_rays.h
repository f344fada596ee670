#pragma once
// The lattice's shadow rays from one surface point (internal to the renderer):
// every texel ray above the point's horizons is traced, 16 at a time, and each
// one that escapes is handed to a callback. The direct precompute and the
// indirect light's path vertices share it.
#include <embree3/rtcore.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "precompute/embree_scene.h"
#include "precompute/sample_patterns.h"

namespace acpca {

class ShadowRays {
 public:
  ShadowRays(const EmbreeScene& scene, const TexelDirections& dirs, const CubeLattice& lattice)
      : scene_(scene), dirs_(dirs), blocks_(texelBlocks(lattice)) {
    // A cone around each block's directions, to skip blocks wholly below a
    // point's horizon with one dot product.
    for (const auto& block : blocks_) {
      Eigen::Vector3f centre = Eigen::Vector3f::Zero();
      forEachDirection(block, [&](const Eigen::Vector3f& d) { centre += d; });
      centre.normalize();
      float blockMinCos = 1;
      forEachDirection(block, [&](const Eigen::Vector3f& d) {
        blockMinCos = std::min(blockMinCos, centre.dot(d));
      });
      const float sinSpread = std::sqrt(std::max(0.0f, 1 - blockMinCos * blockMinCos)) + 1e-4f;
      cones_.push_back({centre, blockMinCos < 0 ? 2.0f : sinSpread});
    }
  }

  const EmbreeScene& scene() const { return scene_; }
  const TexelDirections& directions() const { return dirs_; }

  /// Traces, from origin, every texel ray above both the shading horizon (n)
  /// and the geometric one (ng: from below it the surface itself is in the way,
  /// docs/scenes.md, "Shading normals"), as rtcOccluded16 packets of a 4x4
  /// block of neighbouring texels, and calls escaped(texel, q, cos) for each
  /// ray q (texel * raysPerTexel + k) that leaves the scene, cos = n . d_q.
  /// "Above the shading horizon" is n . d > minCos (0, or below zero to reach
  /// under it). Returns the rays traced.
  template <typename Escaped>
  long long trace(const Eigen::Vector3f& origin, const Eigen::Vector3f& n,
                  const Eigen::Vector3f& ng, float minCos, Escaped&& escaped) const {
    const bool flat = n == ng;  // one horizon to test
    // Below minCos by more than a block's spread, the whole block is skipped.
    const float below = std::asin(std::min(1.0f, -minCos));
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) RTCRay16 ray;
    alignas(64) int valid[16];
    for (int i = 0; i < 16; ++i) {
      ray.org_x[i] = origin.x(), ray.org_y[i] = origin.y(), ray.org_z[i] = origin.z();
      ray.tnear[i] = scene_.rayEpsilon(), ray.time[i] = 0, ray.mask[i] = ~0u;
      ray.id[i] = i, ray.flags[i] = 0;
    }
    long long rays = 0;
    float cosine[16];
    size_t slot[16];
    const int k = dirs_.raysPerTexel;
    for (size_t b = 0; b < blocks_.size(); ++b) {
      // All of the block is below the horizon when n is more than 90 degrees
      // plus the block's spread away from its axis.
      const float skipBelow =
          minCos == 0 ? -cones_[b].sinSpread
                      : -std::sin(std::min(std::asin(std::min(1.0f, cones_[b].sinSpread)) + below,
                                           float(M_PI / 2)));
      if (n.dot(cones_[b].axis) < skipBelow) continue;
      const auto& block = blocks_[b];
      for (int r = 0; r < k; ++r) {
        int active = 0;
        for (int i = 0; i < 16; ++i) {
          const int j = block[i] >= 0 ? block[i] : block[0];
          const size_t q = static_cast<size_t>(j) * k + r;
          slot[i] = q;
          cosine[i] = n.x() * dirs_.x[q] + n.y() * dirs_.y[q] + n.z() * dirs_.z[q];
          const bool above =
              cosine[i] > minCos &&
              (flat || ng.x() * dirs_.x[q] + ng.y() * dirs_.y[q] + ng.z() * dirs_.z[q] > 0);
          valid[i] = block[i] >= 0 && above ? -1 : 0;
          active += valid[i] != 0;
        }
        if (active == 0) continue;
        for (int i = 0; i < 16; ++i) {
          ray.dir_x[i] = dirs_.x[slot[i]], ray.dir_y[i] = dirs_.y[slot[i]];
          ray.dir_z[i] = dirs_.z[slot[i]];
          ray.tfar[i] = std::numeric_limits<float>::infinity();
        }
        rtcOccluded16(valid, scene_.handle(), &context, &ray);
        rays += active;
        for (int i = 0; i < 16; ++i)  // occluded rays come back with tfar = -inf
          if (valid[i] && ray.tfar[i] >= 0) escaped(block[i], slot[i], cosine[i]);
      }
    }
    return rays;
  }

 private:
  template <typename F>
  void forEachDirection(const std::array<int, 16>& block, F&& f) const {
    for (int j : block)
      if (j >= 0)
        for (int r = 0; r < dirs_.raysPerTexel; ++r) {
          const size_t q = static_cast<size_t>(j) * dirs_.raysPerTexel + r;
          f(Eigen::Vector3f(dirs_.x[q], dirs_.y[q], dirs_.z[q]));
        }
  }

  struct Cone {
    Eigen::Vector3f axis;
    float sinSpread;  ///< every direction d of the block has d.axis >= cos(spread)
  };

  const EmbreeScene& scene_;
  const TexelDirections& dirs_;
  std::vector<std::array<int, 16>> blocks_;
  std::vector<Cone> cones_;
};

}  // namespace acpca
