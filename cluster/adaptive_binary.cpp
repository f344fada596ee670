// [Mahajan07] sec. 5.2: adaptive binary CPCA.
#include <tbb/parallel_invoke.h>

#include <numeric>

#include "cluster/partition.h"
#include "cluster/partition_support.h"
#include "cluster/pca.h"
#include "model/cost_model.h"

namespace acpca {

namespace {

/// What a split's costs are measured on: the reduced representation (the
/// clustering coefficients) while a cluster is large, every coefficient below.
/// The paper does its first subdivisions on a reduced representation because a
/// PCA of a large cluster over the whole lighting is too slow; here the exact
/// test of a cluster of p rows costs a p x p Gram matrix, so it starts once p
/// is below the global basis count N.
enum class Measure { Reduced, Exact };

struct Judged {
  Measure measure;
  double cost;  ///< eq. 17/19 under that measure
};

class BinarySplitter {
 public:
  BinarySplitter(const ClusterInput& in, const BinaryOptions& o)
      : in_(in),
        full_(in),
        exactRows_(o.exactTestRows > 0 ? o.exactTestRows : in.globalBases()),
        two_(o.split) {
    two_.clusters = 2;
    full_.clusteringDims = 0;
    // Each split starts from the two sides of the cluster's first principal
    // direction: as cheap as k-means++ seeds at 256x256 and 1-8% lower image
    // error at g = 0.999 (docs/results.md), and it does not depend on a seed.
    two_.splitBySign = true;
  }

  Measure measureFor(size_t rows) const {
    return static_cast<long long>(rows) > exactRows_ ? Measure::Reduced : Measure::Exact;
  }

  double cost(const std::vector<int>& rows, Measure m) const {
    const int width = m == Measure::Exact ? in_.globalBases() : in_.clusteringWidth();
    const int rank = rankToTolerance(gatherRows(in_, rows, width), in_.tolerance, in_.mean);
    return clusterCost(rank + (in_.mean ? 1 : 0), static_cast<long long>(rows.size()), width);
  }

  /// Splits `rows` in two by CPCA while the halves cost less than the whole
  /// (eq. 23 with the halves' costs); the halves refine in parallel and are
  /// appended in order, so the result does not depend on the thread count.
  void refine(std::vector<int> rows, Judged self, Partition& out) const {
    if (rows.size() >= 2) {
      const Measure m = measureFor(rows.size());
      if (self.measure != m) self = {m, cost(rows, m)};
      // Small clusters split on every coefficient, as the paper shifts to the
      // full transport once clusters are small; large ones on the reduced rows.
      Partition halves = cpca(m == Measure::Exact ? full_ : in_, rows, two_);
      if (halves.size() == 2) {
        double c[2];
        tbb::parallel_invoke([&] { c[0] = cost(halves[0], m); },
                             [&] { c[1] = cost(halves[1], m); });
        if (c[0] + c[1] < self.cost) {
          Partition right;
          tbb::parallel_invoke(
              [&] {
                refine(std::move(halves[0]), {m, c[0]}, out);
              },
              [&] {
                refine(std::move(halves[1]), {m, c[1]}, right);
              });
          for (auto& cluster : right) out.push_back(std::move(cluster));
          return;
        }
      }
    }
    out.push_back(std::move(rows));
  }

 private:
  const ClusterInput& in_;
  ClusterInput full_;  ///< the same rows, clustered on every coefficient
  long long exactRows_;
  CpcaOptions two_;
};

}  // namespace

Partition adaptiveBinary(const ClusterInput& in, const BinaryOptions& options) {
  CpcaOptions initial = options.split;
  initial.clusters = options.initialClusters;
  std::vector<int> all(in.rows());
  std::iota(all.begin(), all.end(), 0);
  const Partition start = cpca(in, all, initial);
  const BinarySplitter splitter(in, options);
  return concatInOrder(start, [&](const std::vector<int>& rows) {
    Partition out;
    const Measure m = splitter.measureFor(rows.size());
    splitter.refine(rows, {m, splitter.cost(rows, m)}, out);
    return out;
  });
}

}  // namespace acpca
