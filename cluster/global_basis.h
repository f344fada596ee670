#pragma once
// The global basis (paper 003 sec. 4.1, 5.1): PCA of a random sample of the
// transport rows, truncated to a target energy, and the projection of every row
// onto it, G = T V_g, streamed from the file (the whole T never sits in memory).
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "precompute/transport/transport_file.h"

namespace acpca {

using RowMatrixF = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

struct GlobalBasisOptions {
  double energy = 0.999;   ///< fraction of the sample's energy kept (1: every direction)
  int sampleRows = 16384;  ///< rows in the sample the basis is computed from
  std::uint64_t seed = 1;
};

struct GlobalBasis {
  Eigen::MatrixXf basis;     ///< l x N, orthonormal columns; zero on unseen directions
  int activeDirections = 0;  ///< lattice directions some pixel sees (non-zero columns)
  std::vector<int> active;   ///< their indices, increasing
  int sampledRows = 0;
  double sampleEnergyKept = 0;   ///< fraction of the sample's energy in the basis
  double heldOutEnergyKept = 0;  ///< the same on an independent sample of rows
  int globalBases() const { return static_cast<int>(basis.cols()); }
};

/// Streams the file once to find the seen directions and gather the sample.
GlobalBasis computeGlobalBasis(const TransportReader& transport, const GlobalBasisOptions& options);

struct GlobalProjection {
  RowMatrixF coefficients;         ///< G: rows x N
  Eigen::VectorXd rowEnergy;       ///< |t_p|^2 of every row
  Eigen::VectorXd residualEnergy;  ///< |t_p|^2 - |g_p|^2: what the basis misses, per row
                                   ///< (rounding noise of either sign; use sums)
  double transportEnergy() const { return rowEnergy.sum(); }
};

/// G = T V_g for every row, with per-row energies (parallel, deterministic).
/// Only the seen directions enter the products: the others are zero in every row.
GlobalProjection projectOntoBasis(const TransportReader& transport, const GlobalBasis& basis);

}  // namespace acpca
