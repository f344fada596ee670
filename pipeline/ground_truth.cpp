#include "pipeline/ground_truth.h"

#include "transport/cube_lattice.h"
#include "transport/row_layout.h"

namespace acpca {

GroundTruth loadGroundTruth(const std::vector<std::string>& specs) {
  GroundTruth g;
  for (const auto& spec : specs) g.environments.push_back(loadEnvironment(spec));
  return g;
}

void layOutGroundTruth(GroundTruth& g, int cubemapResolution, int channels) {
  const CubeLattice lattice(cubemapResolution);
  for (const auto& env : g.environments) {
    std::vector<double> lighting(3 * static_cast<size_t>(lattice.size()), 0.0);
    env->integrate(lattice, Eigen::Matrix3d::Identity(), lighting);
    g.lightings.push_back(std::move(lighting));
  }
  g.onRows.resize(static_cast<Eigen::Index>(channels) * lattice.size(), 3 * g.maps());
  for (int m = 0; m < g.maps(); ++m)
    g.onRows.middleCols(3 * m, 3) = lightingOnRows<float>(g.lightings[m], lattice.size(), channels);
}

}  // namespace acpca
