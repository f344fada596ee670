#pragma once
// Light that bounces (internal to the renderer): the part of a pixel's row
// that reaches it off other surfaces, by paths traced from its camera samples
// with every lattice direction gathered at each path vertex (docs/scenes.md,
// "Interreflections").
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

#include "precompute/embree_scene.h"
#include "precompute/shadow_rays.h"

namespace acpca {

struct IndirectSettings {
  int bounces = 0;   ///< path vertices beyond the pixel's own surface
  int samples = 64;  ///< paths per traced camera sample
  /// The visibility cache's cell, as a fraction of the scene's extent; 0 traces
  /// every vertex's shadow rays (unbiased, slow).
  double cacheCell = 0;
  int channels = 1;  ///< 1: grey surfaces, one row; 3: R, G, B rows side by side
};

/// Whether bounced light keeps the colour of the lighting: every material and
/// texture of the scene is grey (R = G = B).
bool sceneIsGrey(const Scene& scene);

/// A surface point a path reached, and how it is seen from the path's
/// previous vertex.
struct PathVertex {
  Eigen::Vector3f origin;           ///< pushed off the surface towards the viewer's side
  Eigen::Vector3f normal;           ///< shading, on the viewer's side
  Eigen::Vector3f geometricNormal;  ///< facing the viewer
  Eigen::Vector3f tangent;          ///< across the shading normal, the material's rotation applied
  Eigen::Vector3f toViewer;
  Eigen::Vector3f albedo;
  int material = -1;
};

class IndirectLight {
 public:
  IndirectLight(const EmbreeScene& scene, const ShadowRays& shadows, int latticeSize,
                const Scene& source, const IndirectSettings& settings);

  const IndirectSettings& settings() const { return settings_; }

  /// The cache's pre-pass: the vertices of every path of a camera sample name
  /// the cells the main pass will look up; the first vertex of a cell in image
  /// order stands for it. Thread-safe: bands are collected in parallel.
  void collectCells(const PixelSample& ps, std::uint64_t seed,
                    std::unordered_map<std::uint64_t, PathVertex>& firstInBand,
                    std::vector<std::uint64_t>& order) const;
  /// Appends a band's cells not seen in earlier bands (bands in image order).
  void mergeCells(const std::unordered_map<std::uint64_t, PathVertex>& band,
                  const std::vector<std::uint64_t>& order);
  /// Traces every cell's visibility (in parallel), calling progress(points
  /// done, points) from the calling thread. Returns the rays traced.
  long long fillCache(const std::function<void(long long, long long)>& progress);
  long long cachedPoints() const { return static_cast<long long>(cellVertex_.size()); }

  /// Adds weight times the indirect light of one camera sample (seeded by its
  /// pixel and sample) to its row (channels x l values). Returns the closest-hit
  /// rays and shadow rays traced.
  struct Rays {
    long long paths = 0, shadow = 0;
  };
  Rays add(const PixelSample& ps, std::uint64_t seed, float weight, float* row) const;

 private:
  template <typename Visit>
  long long walk(const PixelSample& ps, std::uint64_t seed, Visit&& visit) const;
  std::uint64_t cellKey(const PathVertex& v) const;
  long long gatherExact(const PathVertex& v, const Eigen::Array3f& beta, float* row) const;
  void gatherCached(const std::uint64_t* bits, const PathVertex& v, const Eigen::Array3f& beta,
                    float* row) const;

  const EmbreeScene& scene_;
  const ShadowRays& shadows_;
  const int l_;
  const IndirectSettings settings_;
  Eigen::Vector3f lo_;
  float cell_ = 0;
  int words_ = 0;  ///< 64-bit words of visibility per cached point
  std::unordered_map<std::uint64_t, std::int64_t> cellIndex_;
  std::vector<PathVertex> cellVertex_;
  std::vector<std::uint64_t> visibility_;
};

}  // namespace acpca
