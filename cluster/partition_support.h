#pragma once
// What the partitioning methods share: copies of a cluster's rows of global
// coefficients (whole or their leading columns) and an ordered parallel map.
#include <tbb/parallel_for.h>

#include <Eigen/Core>
#include <vector>

#include "cluster/partition.h"

namespace acpca {

/// Rows `rows` of G, their first `width` columns.
inline RowMatrixF gatherRows(const ClusterInput& in, const std::vector<int>& rows, int width) {
  RowMatrixF m(rows.size(), width);
  for (size_t i = 0; i < rows.size(); ++i) m.row(i) = in.coefficients->row(rows[i]).head(width);
  return m;
}

/// Runs f over items in parallel and concatenates their partitions in item
/// order, so the result does not depend on the thread count.
template <typename Item, typename F>
Partition concatInOrder(const std::vector<Item>& items, F&& f) {
  std::vector<Partition> parts(items.size());
  tbb::parallel_for(size_t(0), items.size(), [&](size_t i) { parts[i] = f(items[i]); });
  Partition all;
  for (auto& p : parts)
    for (auto& c : p) all.push_back(std::move(c));
  return all;
}

}  // namespace acpca
