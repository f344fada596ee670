#pragma once
// The columns of a cluster's reconstruction that local lights meet
// (docs/lighting.md, "Local lights"): for cluster c and a row element e (a
// texel, or channel x texel) some pixel sees, W_c^T V_g^T e_e (one value per
// basis) and mu_c . V_g^T e_e. A light that moves between frames touches
// mostly the texels it touched before, so the columns are kept across frames
// (a light path, the viewer) and only new ones are formed. Each column is
// computed by one fixed loop, so it has the same bytes whenever and beside
// whatever it is formed: images do not depend on what was relit before.
#include <cstdint>
#include <memory>
#include <mutex>
#include <vector>

#include "relight/packed_model.h"

namespace acpca {

class LocalLightColumns {
 public:
  explicit LocalLightColumns(std::shared_ptr<const PackedModel> model);

  /// Makes cluster c's columns for these seen slots (indices into
  /// PackedModel::seenTexels) present; safe to call for different clusters
  /// at once.
  void require(int cluster, const std::vector<int>& slots);
  /// Cluster c's column for a seen slot made present by require: ranks[c]
  /// values, then the mean term (0 without means).
  const float* column(int cluster, int slot) const {
    const Cluster& c = clusters_[cluster];
    return c.values.data() + static_cast<size_t>(c.columnOf[slot]) * (model_->ranks[cluster] + 1);
  }
  /// W_c^T z and mu_c . z for a vector z over the N global bases (the taps of
  /// a group summed in V_g's space first), written as a column is.
  void project(int cluster, const float* z, float* out) const;
  /// Makes rows of V_g present for these seen slots (one pass over V_g for
  /// those not yet kept); not while other calls run.
  void requireGlobalRows(const std::vector<int>& slots);
  /// Row s of V_g (N values) made present by requireGlobalRows: the global
  /// basis at seen slot s.
  const float* globalRow(int slot) const {
    return globalRows_.data() + static_cast<size_t>(rowOf_[slot]) * model_->globalBases;
  }
  /// Cluster c's rows in chunk order, and where each lies: chunk x 16 + lane.
  const std::vector<std::int32_t>& rowsOf(int cluster) const { return clusterRows_[cluster]; }
  const std::vector<std::size_t>& lanesOf(int cluster) const { return clusterLanes_[cluster]; }
  /// Per row element (texel, or channel x texel), its seen slot or -1.
  const std::vector<int>& seenIndex() const { return seenIndex_; }

  /// The model the columns are of.
  const std::shared_ptr<const PackedModel>& model() const { return model_; }

  /// Drops every kept column (memory: see kMaxKeptValues).
  void clear();
  /// Floats kept, over all clusters.
  long long keptValues() {
    std::lock_guard lock(clearing_);
    return kept_;
  }

  /// Past this many kept values (1 GiB of floats) the cache starts afresh.
  static constexpr long long kMaxKeptValues = 1LL << 28;

 private:
  struct Cluster {
    std::mutex mutex;
    std::vector<std::int32_t> columnOf;  ///< per seen slot, -1: not formed
    std::vector<float> values;
  };
  /// Columns of cluster c for `count` vectors over N (row i at z + i * N).
  void formColumns(int cluster, const float* z, size_t count, float* out) const;

  std::shared_ptr<const PackedModel> model_;
  std::vector<std::int32_t> rowOf_;  ///< per seen slot, its row in globalRows_ or -1
  std::vector<float> globalRows_;    ///< rows of V_g as asked for, N values each
  std::vector<Cluster> clusters_;
  std::vector<std::vector<std::int32_t>> clusterRows_;
  std::vector<std::vector<std::size_t>> clusterLanes_;
  std::vector<int> seenIndex_;
  std::mutex clearing_;
  long long kept_ = 0;  ///< guarded by clearing_
};

}  // namespace acpca
