#pragma once
// The precompute's unit of work: the transport rows of one image row's
// occupied pixels (docs/design.md section 4). Inside the library only.
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "precompute/indirect_light.h"
#include "precompute/precompute_options.h"
#include "precompute/sample_patterns.h"
#include "precompute/shadow_rays.h"

namespace acpca {

/// Computes transport rows: the direct part by the lattice's shadow rays from
/// each traced camera sample, and with bounces the indirect part
/// (indirect_light.h) in the same row.
class ImageRowRenderer {
 public:
  ImageRowRenderer(const GBuffer& gbuffer, const ShadowRays& shadows, const CubeLattice& lattice,
                   Antialiasing mode, const IndirectLight* indirect);

  int rowLength() const { return channels_ * l_; }
  int height() const { return gbuffer_.size.height; }

  struct Counts {
    long long shadowRays = 0, pathRays = 0, supersampled = 0;
  };

  /// Fills out (one transport row per occupied pixel of image row y, left to
  /// right) and counts the rays traced.
  Counts render(int y, std::vector<float>& out) const;

  /// Adds pixel (x, y)'s transport row to target (zeroed, rowLength values)
  /// and counts its rays.
  void renderPixel(int x, int y, float* target, Counts& counts) const;

  /// The cache pre-pass over image row y: the cells its paths reach, in order.
  void collectCells(int y, std::unordered_map<std::uint64_t, PathVertex>& cells,
                    std::vector<std::uint64_t>& order) const;

 private:
  int hits(int x, int y) const;
  /// Seeds a camera sample's paths by where it is, so that they never depend
  /// on which thread renders them.
  std::uint64_t sampleSeed(int x, int y, int s) const;
  /// Adds weight x V x cos x (f / albedo) of one pixel sample to its row.
  long long traceDirect(const PixelSample& ps, float weight, float* row) const;

  const GBuffer& gbuffer_;
  const Antialiasing mode_;
  const ShadowRays& shadows_;
  const IndirectLight* indirect_;
  const int l_;
  const int channels_;
};

}  // namespace acpca
