#pragma once
// The ground truth of a streamed build: lightings whose dense relight
// B = albedo (T L) is computed from each tile's rendered rows, since no
// transport file holds T.
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "lighting/environment.h"

namespace acpca {

/// The lightings of the ground truth, integrated onto the lattice once.
struct GroundTruth {
  std::vector<std::unique_ptr<Environment>> environments;
  std::vector<std::vector<double>> lightings;
  Eigen::MatrixXf onRows;  ///< rowLength x 3M: column 3m + c is map m's channel c on the rows
  int maps() const { return static_cast<int>(environments.size()); }
};

/// The environments, before any work (a bad spec is refused first).
GroundTruth loadGroundTruth(const std::vector<std::string>& specs);
/// Integrated onto the lattice and laid out as the rows meet them.
void layOutGroundTruth(GroundTruth& g, int cubemapResolution, int channels);

}  // namespace acpca
