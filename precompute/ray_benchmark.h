#pragma once
// Occlusion-ray throughput of the precompute against minimal raw Embree loops
// over the same scene points and lattice directions (the renderer's yardstick).
#include <string>
#include <vector>

#include "core/table.h"
#include "precompute/scene.h"

namespace acpca {

struct RayRate {
  std::string name;
  long long rays = 0;
  double seconds = 0;
  double raysPerSecond() const { return seconds > 0 ? rays / seconds : 0; }
};

struct RayBenchmarkReport {
  int threads = 0;
  long long triangles = 0;
  int imageRows = 0;
  RayRate precompute;             ///< the real transport pass (BRDF, accumulation, all)
  std::vector<RayRate> rawLoops;  ///< bare Embree loops
  const RayRate& bestRawLoop() const;
  /// precompute rays/s over the best raw loop's.
  double ratioToBest() const;
  /// A row per loop (rays, M rays/s, per core) and the ratio, as text.
  std::string table() const;
  /// What `bench rays --json` writes: threads, triangles, the precompute's rays
  /// per second, the raw loops (name, rays, rays_per_second), the best and the ratio.
  nlohmann::json json() const;
};

/// Runs each loop over the middle `imageRows` rows of the scene's image with
/// `threads` threads (0: all), every loop `repeats` times, keeping the fastest.
RayBenchmarkReport runRayBenchmark(const Scene& scene, int cubemapResolution, int threads,
                                   int imageRows, int repeats);

}  // namespace acpca
