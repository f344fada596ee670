#pragma once
// The ground truth: B = albedo x (T L), exactly, from a transport file. Many
// lightings share one pass over T (one matrix product per block of rows).
#include <vector>

#include "lighting/environment.h"
#include "transport/transport_file.h"

namespace acpca {

/// Per occupied pixel RGB (rows x 3, albedo applied) for each lighting, in the
/// file's row order. Streams T in blocks; parallel over blocks with TBB, the
/// same result for any thread count.
std::vector<std::vector<float>> denseRelight(const TransportReader& transport,
                                             const std::vector<LatticeLighting>& lightings);

}  // namespace acpca
