#pragma once
// One tile of a streamed build: its rows rendered, projected onto the global
// basis and clustered on their own (the tile as adaptive-quad's root, or a
// group of pixels for CPCA and adaptive binary), with the energies its part
// of the model's errors is summed from.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "cluster/global_basis.h"
#include "core/text.h"
#include "model/model.h"
#include "pipeline/ground_truth.h"
#include "pipeline/streamed_build.h"
#include "pipeline/tile_plan.h"

namespace acpca {

/// The energies a tile's transport error is assembled from: |T|^2, what the
/// global basis misses, and everything the tile's model misses (the global
/// residual, its clusters' residuals and the quantization error).
struct TileEnergies {
  double energy = 0, globalResidual = 0, errorEnergy = 0;
  /// Per ground-truth lighting: sum over the tile's rows of |B_model - B|^2 and |B|^2.
  std::vector<double> truthDiff, truthNorm;
  std::map<std::string, double> attributes() const {
    std::map<std::string, double> a{
        {"energy", energy}, {"global_residual", globalResidual}, {"error_energy", errorEnergy}};
    for (size_t m = 0; m < truthDiff.size(); ++m)
      a[concat("truth_diff_", m)] = truthDiff[m], a[concat("truth_norm_", m)] = truthNorm[m];
    return a;
  }
};

/// CPCA and adaptive binary cluster rows wherever they are, so their tiles
/// are groups of pixels large enough to hold many clusters.
bool clustersTileGroups(Method m);

/// Tile side: adaptive-quad's root block; for block, whole blocks of about 64;
/// for CPCA and adaptive binary, groups of 256 unless told.
int tileSide(const BuildOptions& o);

/// A tile's clusters: its rows rendered, projected onto the global basis and
/// compressed with the tile as the root block; rows indexed in the image.
/// With a ground truth, its values for the tile's rows (map by map, row by
/// row, RGB) go into `truth`, and the model's error against them into energies.
Model compressTile(const Tile& tile, const RowSource& source, const BasisProjector& projector,
                   const GlobalBasis& basis, const BuildOptions& o, const GroundTruth& truthSet,
                   std::vector<float>& rows, std::vector<float>& truth, TileEnergies& energies,
                   std::pair<long long, long long>& rays);

}  // namespace acpca
