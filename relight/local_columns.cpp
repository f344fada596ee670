#include "relight/local_columns.h"

#include <tbb/parallel_for.h>

#include <Eigen/Core>
#include <algorithm>
#include <array>

#include "core/half.h"
#include "relight/relight_kernels.h"

namespace acpca {

using kernels::kChunkRows;

LocalLightColumns::LocalLightColumns(std::shared_ptr<const PackedModel> model)
    : model_(std::move(model)),
      rowOf_(model_->seenTexels.size(), -1),
      clusters_(model_->clusters()),
      clusterRows_(model_->clusters()),
      clusterLanes_(model_->clusters()),
      seenIndex_(model_->geometry.rowLength(), -1) {
  const PackedModel& m = *model_;
  for (size_t j = 0; j < m.chunks.size(); ++j)
    for (int lane = 0; lane < kChunkRows; ++lane)
      if (const std::int32_t row = m.chunkRows[j * kChunkRows + lane]; row >= 0) {
        clusterRows_[m.chunks[j].cluster].push_back(row);
        clusterLanes_[m.chunks[j].cluster].push_back(j * kChunkRows + lane);
      }
  for (size_t i = 0; i < m.seenTexels.size(); ++i)
    seenIndex_[m.seenTexels[i]] = static_cast<int>(i);
}

void LocalLightColumns::requireGlobalRows(const std::vector<int>& slots) {
  // V_g is packed basis by basis (the environment relight's order); a column
  // needs it texel by texel: the new rows gathered in one pass over V_g.
  const PackedModel& m = *model_;
  const int n = m.globalBases;
  const long long seen = static_cast<long long>(m.seenTexels.size());
  std::vector<int> added;
  for (int slot : slots)
    if (rowOf_[slot] < 0) {
      rowOf_[slot] = static_cast<std::int32_t>(globalRows_.size() / n + added.size());
      added.push_back(slot);
    }
  if (added.empty()) return;
  const size_t first = globalRows_.size();
  globalRows_.resize(first + added.size() * n);
  tbb::parallel_for(0, n, [&](int g) {
    for (size_t i = 0; i < added.size(); ++i)
      globalRows_[first + i * n + g] = m.globalBasis[g * seen + added[i]];
  });
}

void LocalLightColumns::formColumns(int cluster, const float* z, size_t count, float* out) const {
  const PackedModel& m = *model_;
  const int n = m.globalBases, rank = m.ranks[cluster], stride = rank + 1;
  using Lanes = Eigen::Array<float, kChunkRows, 1>;
  for (int first = 0; first < rank; first += kChunkRows) {
    // W_c's bases first .. first + 15, N x 16, global index major; half
    // bases are widened row by row as they are read (exactly: any float
    // holds a half), so a cluster that needs a few new columns reads its
    // half bases once per four columns and converts nothing else.
    const long long at = m.basisOffset[cluster] + static_cast<long long>(first) * n;
    const bool half = m.basisPrecision == CoeffPrecision::F16;
    const std::uint16_t* wh = half ? m.basesF16.data() + at : nullptr;
    const float* wf = half ? nullptr : m.bases.data() + at;
    const auto row = [&](int i) -> Lanes {
      if (!half) return Eigen::Map<const Lanes>(wf + i * kChunkRows);
      Lanes r;
      halfToFloat16(wh + i * kChunkRows, r.data());
      return r;
    };
    const int lanes = std::min(kChunkRows, rank - first);
    // Sixteen sums in index order, one per basis, as whole-register
    // multiply-adds: the same bytes for any caller, alignment or batch of
    // columns. Four vectors at a time share each row of W.
    for (size_t v = 0; v < count; v += 4) {
      // A last group of fewer than four repeats its first vector: every
      // column goes through this one loop.
      std::array<const float*, 4> x;
      for (size_t k = 0; k < 4; ++k) x[k] = z + (v + k < count ? v + k : v) * n;
      Lanes s0 = Lanes::Zero(), s1 = Lanes::Zero(), s2 = Lanes::Zero(), s3 = Lanes::Zero();
      for (int i = 0; i < n; ++i) {
        const Lanes w = row(i);
        s0 += w * x[0][i], s1 += w * x[1][i], s2 += w * x[2][i], s3 += w * x[3][i];
      }
      const std::array<const Lanes*, 4> sums{&s0, &s1, &s2, &s3};
      for (size_t k = 0; k < 4 && v + k < count; ++k)
        std::copy_n(sums[k]->data(), lanes, out + (v + k) * stride + first);
    }
  }
  for (size_t v = 0; v < count; ++v) {
    double mean = 0;
    if (m.hasMean)
      for (int i = 0; i < n; ++i) mean += double(z[v * n + i]) * m.means[size_t(cluster) * n + i];
    out[v * stride + rank] = static_cast<float>(mean);
  }
}

void LocalLightColumns::require(int cluster, const std::vector<int>& slots) {
  Cluster& c = clusters_[cluster];
  const int stride = model_->ranks[cluster] + 1;
  std::lock_guard lock(c.mutex);
  if (c.columnOf.empty()) c.columnOf.assign(model_->seenTexels.size(), -1);
  std::vector<int> missing;
  for (int slot : slots)
    if (c.columnOf[slot] < 0 && std::find(missing.begin(), missing.end(), slot) == missing.end())
      missing.push_back(slot);
  if (missing.empty()) return;
  const int n = model_->globalBases;
  std::vector<float> rows(missing.size() * n);
  for (size_t i = 0; i < missing.size(); ++i)
    std::copy_n(globalRow(missing[i]), n, rows.begin() + i * n);
  const size_t first = c.values.size() / stride;
  c.values.resize(c.values.size() + missing.size() * stride);
  formColumns(cluster, rows.data(), missing.size(), c.values.data() + first * stride);
  for (size_t i = 0; i < missing.size(); ++i) c.columnOf[missing[i]] = static_cast<int>(first + i);
  std::lock_guard count(clearing_);
  kept_ += static_cast<long long>(missing.size()) * stride;
}

void LocalLightColumns::project(int cluster, const float* z, float* out) const {
  formColumns(cluster, z, 1, out);
}

void LocalLightColumns::clear() {
  std::fill(rowOf_.begin(), rowOf_.end(), -1);
  std::vector<float>().swap(globalRows_);
  for (Cluster& c : clusters_) {
    std::lock_guard lock(c.mutex);
    std::vector<std::int32_t>().swap(c.columnOf);
    std::vector<float>().swap(c.values);
  }
  std::lock_guard count(clearing_);
  kept_ = 0;
}

}  // namespace acpca
