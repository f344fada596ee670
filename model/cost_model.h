#pragma once
// The rendering-cost model of [Mahajan07] (sec. 4): a cluster of p pixels with n
// local bases over N global bases costs n (p + N) multiply-adds per frame
// (eq. 17/19) and stores as many values. A per-cluster mean counts as one more
// basis.
#include <cstdint>

namespace acpca {

/// eq. 17/19: c = n (p + N).
inline double clusterCost(int n, long long p, int globalBases) {
  return static_cast<double>(n) * (static_cast<double>(p) + globalBases);
}

/// eq. 23: d = (1 - mu) n p + (1 - r mu) n N, for a patch of p pixels and n bases
/// split into r children of about p / r pixels and mu n bases each. Splitting
/// pays while d > 0.
inline double subdivisionMetric(double mu, int r, int n, long long p, int globalBases) {
  return (1 - mu) * n * static_cast<double>(p) +
         (1 - r * mu) * n * static_cast<double>(globalBases);
}

/// eq. 27: the optimal patch size p* = N (r mu - 1) / (1 - mu) (for mu in (1/r, 1)).
inline double optimalPatchSize(double mu, int r, int globalBases) {
  return globalBases * (r * mu - 1) / (1 - mu);
}

}  // namespace acpca
