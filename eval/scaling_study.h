#pragma once
// `bench scaling`: one scene and camera at several resolutions, compressed
// adaptively at one tolerance; total cost against pixels beside the paper's
// prediction of 4 mu^2 per 4x pixels ([Mahajan07] sec. 4.4).
#include <functional>
#include <string>
#include <vector>

#include "core/study_output.h"

namespace acpca {

struct ScalingOptions {
  std::string sceneName;  ///< for the report
  /// Writes the scene's transport at `width` pixels wide (the height follows
  /// the scene's aspect) on a 6 x cubemap^2 lattice to `path`. The caller
  /// owns the renderer, so this library needs none.
  std::function<void(int width, int cubemap, const std::string& path)> precompute;
  std::string method = "adaptive-quad";
  std::vector<int> sizes{128, 256, 512, 1024};
  double tolerance = 0.999, globalEnergy = 0.999, energy = 0.9995;
  int cubemap = 32, frames = 20;
  bool keepTransports = false;
  StudyLog log;
};

void validateScalingOptions(const ScalingOptions& options);

/// Precomputes, compresses and times every size; writes scaling.csv, the plot
/// and summary.md into `outDir` (and the transports with keepTransports).
StudyOutput runScalingStudy(const ScalingOptions& options, const std::string& outDir);

}  // namespace acpca
