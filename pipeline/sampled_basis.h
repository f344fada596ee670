#pragma once
// The streamed build's global basis: fitted to a sample of rendered rows (the
// rows compress samples from a file), and shared by rank 0 with every rank.
#include <utility>

#include "cluster/global_basis.h"
#include "precompute/transport_renderer.h"

namespace acpca {

/// Renders the sampled rows and fits the global basis to them, as
/// computeGlobalBasis does from a transport file (same rows, same values);
/// adds the occlusion and path rays traced to `rays`.
GlobalBasis fitBasis(const RowSource& source, const GlobalBasisOptions& options,
                     std::pair<long long, long long>& rays);

/// Rank 0's basis on every rank: it alone renders the sample and fits the
/// basis, so every rank projects with the same values.
void shareBasis(GlobalBasis& basis);

}  // namespace acpca
