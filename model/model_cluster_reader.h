#pragma once
// A model file read for relighting without a copy of its large arrays in
// memory: the layout (header, cluster rows and offsets, means, steps) and the
// global basis at once, each cluster's bases and coefficients when asked,
// from any thread, straight into the caller's scratch. The relighter packs
// them into its own layout cluster by cluster (docs/architecture.md,
// "Relighting a model"); every value is checked as readModel checks it.
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "model/model.h"
#include "model/model_values.h"

namespace acpca {

/// What a thread reuses from cluster to cluster.
struct ClusterScratch {
  std::vector<float> bases;
  std::vector<float> coefficients;  ///< raw bytes of any precision, float-aligned
  std::vector<std::uint16_t> halves;
};

class ModelClusterReader {
 public:
  /// UserError naming path when the file is not a whole model of this build's
  /// versions, or its layout or global basis is inconsistent or non-finite.
  explicit ModelClusterReader(const std::string& path);
  ~ModelClusterReader();

  /// The model without its global basis, bases and coefficients (all empty):
  /// geometry, method, precisions, ranks, rows, offsets, means and steps.
  const Model& layout() const { return model_; }
  int globalBases() const { return globalBases_; }
  /// V_g as l rows of N values.
  const float* globalBasisRows() const { return globalBasis_.get(); }

  /// Cluster c's bases (rank rows of N, as floats) read into scratch: any
  /// thread, each cluster once, before its coefficients. UserError naming the
  /// file on a failed read or a non-finite basis, mean or step.
  const float* readBases(int c, ClusterScratch& scratch) const;
  /// Rows [first, first + rows) of cluster c's coefficients (row-major, in
  /// the model's precision) read into scratch: any thread, once each row.
  const void* readCoefficients(int c, long long first, long long rows,
                               ClusterScratch& scratch) const;
  /// Once every value is read: UserError when relit values could overflow
  /// (model_values.h).
  void checkRelitBound() const;

 private:
  struct Datasets;
  std::string path_;
  Model model_;
  int globalBases_ = 0;
  std::unique_ptr<float[]> globalBasis_;
  ClusterValues valuesOf(int c) const;

  double projectionBound_ = 0;
  mutable std::vector<ClusterBoundTerms> terms_;  ///< per cluster, set with its bases
  mutable std::mutex boundLock_;
  mutable double rowBound_ = 0;  ///< the largest row bound read so far
  std::unique_ptr<Datasets> sets_;
};

}  // namespace acpca
