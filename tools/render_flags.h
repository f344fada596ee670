#pragma once
// The flags that say how a scene's rows are rendered and compressed, shared by
// precompute and build (rendering) and by compress and build (compression).
#include <CLI/CLI.hpp>
#include <string>

#include "cluster/compress.h"
#include "precompute/scene.h"
#include "precompute/transport_renderer.h"

namespace acpca::cli {

struct RenderFlags {
  std::string scene, size, camera, precision = "f16", antialiasing = "adaptive";
  int cubemap = 32, spp = kDefaultSamplesPerPixel, texelRays = 1;
  int bounces = 0, indirectSamples = kDefaultIndirectSamples;
  double indirectCache = kDefaultIndirectCacheCell;
  bool force = false;

  void add(CLI::App& app);
  /// Parsed (UserError on bad names); threads as given.
  PrecomputeOptions options(int threads) const;
  /// The scene with --size and --camera applied, validated.
  Scene loadScene() const;
};

struct CompressFlags {
  std::string method, coeffs = "f32", bases = "f32";
  double tolerance = 0.999, globalEnergy = 0.999;
  int clusters = 10, block = 0, sampleRows = 16384, clusteringDims = kDefaultClusteringDims;
  unsigned long long seed = 1;
  bool exactQuadTree = false, allocateRanks = false, force = false;

  /// streamed: build's subset (adaptive-quad by default; no CPCA options).
  void add(CLI::App& app, bool streamed);
  CompressOptions options() const;
};

}  // namespace acpca::cli
