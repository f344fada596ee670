#include "cluster/rank_allocation.h"

#include <queue>

namespace acpca {

std::vector<int> allocateRanks(const std::vector<Eigen::VectorXd>& spectra,
                               const std::vector<long long>& clusterSizes, int globalBases,
                               double budget) {
  const size_t c = spectra.size();
  std::vector<int> ranks(c, 0);
  double dropped = 0;
  for (const auto& s : spectra) dropped += s.sum();
  // Max-heap on the value of each cluster's next basis; ties broken by index
  // so the result is deterministic.
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry> next;
  const auto push = [&](int i) {
    if (ranks[i] < spectra[i].size() && spectra[i][ranks[i]] > 0)
      next.push({spectra[i][ranks[i]] / (double(clusterSizes[i]) + globalBases), -i});
  };
  for (size_t i = 0; i < c; ++i) push(static_cast<int>(i));
  while (dropped > budget && !next.empty()) {
    const int i = -next.top().second;
    next.pop();
    dropped -= spectra[i][ranks[i]];
    ++ranks[i];
    push(i);
  }
  return ranks;
}

}  // namespace acpca
