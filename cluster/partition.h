#pragma once
// Ways of grouping transport rows into clusters (docs/design.md section 5): fixed
// image blocks, Sloan's CPCA, and [Mahajan07]'s adaptive quad-tree (r = 4) and
// binary CPCA (r = 2) subdivisions driven by the cost metric.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "cluster/global_basis.h"
#include "transport/camera.h"

namespace acpca {

/// Row indices of each cluster, each list sorted.
using Partition = std::vector<std::vector<int>>;

/// What the clustering methods see: the global coefficients of every row and
/// where each row sits in the image.
struct ClusterInput {
  const RowMatrixF* coefficients = nullptr;           ///< G, rows x N
  const std::vector<std::int32_t>* pixels = nullptr;  ///< linear pixel index of each row
  ImageSize size;
  double tolerance = 0.999;  ///< fraction of each cluster's energy its bases keep
  bool mean = false;         ///< clusters keep a mean (costs one more basis)
  /// CPCA assigns rows on the leading this many global coefficients (0: all).
  /// [Mahajan07] sec. 5.2 clusters on a reduced representation, the transport's
  /// globally strongest coefficients; the global coefficients are ordered by
  /// energy, so their head is that representation. Bases and ranks always use
  /// every coefficient.
  int clusteringDims = 0;
  int globalBases() const { return static_cast<int>(coefficients->cols()); }
  int clusteringWidth() const {
    return clusteringDims > 0 ? std::min(clusteringDims, globalBases()) : globalBases();
  }
  long long rows() const { return coefficients->rows(); }
};

/// Default of ClusterInput::clusteringDims for the CPCA-based methods.
inline constexpr int kDefaultClusteringDims = 256;

/// Bases a set of rows needs at the input's tolerance (eigenvalues only).
int rankOf(const ClusterInput& in, const std::vector<int>& rows);
/// n (p + N) with n counting the mean when kept (eq. 17/19).
double costOf(const ClusterInput& in, const std::vector<int>& rows, int rank);

Partition singleCluster(const ClusterInput& in);
/// Square blocks of `block` pixels per side; background pixels belong to none.
Partition fixedBlocks(const ClusterInput& in, int block);

struct QuadTreeOptions {
  int rootBlock = 64;  ///< the image is first cut into blocks of this side
  int minBlock = 2;    ///< blocks are not split below this side
  bool exact = false;  ///< bottom-up optimum instead of the paper's greedy test
};
/// [Mahajan07] sec. 5.3: each block splits in four while its children's exact
/// costs sum to less than its own (the greedy form of d > 0, eq. 23). With
/// exact, the whole tree is evaluated and each node keeps the cheaper of itself
/// and its children's best.
Partition adaptiveQuadTree(const ClusterInput& in, const QuadTreeOptions& options);

struct CpcaOptions {
  int clusters = 10;
  int iterationRank = 8;  ///< bases per cluster while assigning rows
  int iterations = 10;
  int candidates = 16;  ///< clusters (nearest by mean) each row is tested against
  std::uint64_t seed = 1;
  /// K = 2: start from the halves on either side of the first principal
  /// direction instead of k-means++ seeds.
  bool splitBySign = false;
};
/// Sloan et al. 2003: k-means++ seeding, then rows move to the cluster whose
/// mean and bases reconstruct them best, until nothing moves.
Partition cpca(const ClusterInput& in, const std::vector<int>& rows, const CpcaOptions& options);

struct BinaryOptions {
  int initialClusters = 8;
  CpcaOptions split;  ///< CPCA(K = 2) settings for each split
  /// Clusters of more rows than this are tested on the reduced representation
  /// (the clustering coefficients), smaller ones on every coefficient;
  /// 0: N, where the p x p problem becomes the smaller one.
  long long exactTestRows = 0;
};
/// [Mahajan07] sec. 5.2: a few CPCA clusters, each split in two by CPCA (started
/// from the sign of the first principal coefficient) while the halves' costs
/// sum to less than the whole's; recursively, the two halves in parallel.
/// Large clusters are split and judged on the reduced representation, as the
/// paper does for its first subdivisions; the rest on every coefficient.
Partition adaptiveBinary(const ClusterInput& in, const BinaryOptions& options);

}  // namespace acpca
