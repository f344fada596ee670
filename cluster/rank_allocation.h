#pragma once
// Ranks from one error budget over all clusters (beyond the paper): each basis
// goes where it removes the most error per unit of cost.
#include <Eigen/Core>
#include <vector>

namespace acpca {

/// Ranks for an error budget: starting from none, repeatedly add to the cluster
/// whose next eigenvalue per unit cost, lambda / (p + N), is largest, until the
/// dropped energy is at most `budget`. Spectra must be descending.
std::vector<int> allocateRanks(const std::vector<Eigen::VectorXd>& spectra,
                               const std::vector<long long>& clusterSizes, int globalBases,
                               double budget);

}  // namespace acpca
