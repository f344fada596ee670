#pragma once
// The global basis ([Mahajan07] sec. 4.1, 5.1): PCA of a random sample of the
// transport rows, truncated to a target energy, and the projection of every row
// onto it, G = T V_g, streamed from the file (the whole T never sits in memory).
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "cluster/pca.h"
#include "transport/transport_file.h"

namespace acpca {

struct GlobalBasisOptions {
  double energy = 0.999;   ///< fraction of the sample's energy kept (1: every direction)
  int sampleRows = 16384;  ///< rows in the sample the basis is computed from
  std::uint64_t seed = 1;
};

struct GlobalBasis {
  Eigen::MatrixXf basis;     ///< l x N, orthonormal columns; zero on unseen directions
  int activeDirections = 0;  ///< lattice directions some sampled row sees
  /// The directions the basis lives on, increasing: those some sampled row
  /// sees (the basis is zero on the others, so they never enter a product).
  std::vector<int> active;
  int sampledRows = 0;
  double sampleEnergyKept = 0;   ///< fraction of the sample's energy in the basis
  double heldOutEnergyKept = 0;  ///< the same on an independent sample of rows
  int globalBases() const { return static_cast<int>(basis.cols()); }
};

/// Which rows the basis is computed from and which it is checked on: distinct
/// row indices out of `total`, each list sorted, drawn from the seed alone, so
/// the file pass and the streamed build (which renders just these rows) pick
/// the same rows.
struct BasisSample {
  std::vector<long long> rows;     ///< options.sampleRows of them (or every row)
  std::vector<long long> heldOut;  ///< up to 4096, drawn independently
};
BasisSample chooseBasisSample(long long total, const GlobalBasisOptions& options);

/// PCA of the sampled rows (sample x l, in double) over the directions they
/// see, truncated to options.energy; heldOut (rows x l) measures how well the
/// basis carries rows it was not computed from.
GlobalBasis basisFromSample(const Eigen::MatrixXd& sample, const Eigen::MatrixXd& heldOut,
                            const GlobalBasisOptions& options);

/// Reads the sampled rows alone (a few percent of the file) and fits on them.
GlobalBasis computeGlobalBasis(const TransportReader& transport, const GlobalBasisOptions& options);

struct GlobalProjection {
  RowMatrixF coefficients;         ///< G: rows x N
  Eigen::VectorXd rowEnergy;       ///< |t_p|^2 of every row
  Eigen::VectorXd residualEnergy;  ///< |t_p|^2 - |g_p|^2: what the basis misses, per row
                                   ///< (rounding noise of either sign; use sums)
  double transportEnergy() const { return rowEnergy.sum(); }
};

/// G = T V_g for blocks of rows, with each row's energies: the one kernel of
/// the file pass below and of the streamed build's tiles.
class BasisProjector {
 public:
  BasisProjector(const GlobalBasis& basis, int latticeSize, int rowLength);
  ~BasisProjector();
  /// Projects rows (count x rowLength floats) into rows [first, first + count)
  /// of `out`, whose arrays the caller has sized.
  void project(const float* rows, long long count, GlobalProjection& out, long long first) const;
  /// A projection of its own for these rows.
  GlobalProjection project(const float* rows, long long count) const;

 private:
  class ZeroRunProduct;
  std::unique_ptr<const ZeroRunProduct> product_;
  std::vector<int> active_;
  int rowLength_ = 0;
  bool formResidual_ = false;
};

/// G = T V_g for every row, with per-row energies (parallel, deterministic).
GlobalProjection projectOntoBasis(const TransportReader& transport, const GlobalBasis& basis);

}  // namespace acpca
