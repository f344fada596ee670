#pragma once
// Streaming all rows of a transport file: blocks are read in order by one
// thread (HDF5 is not thread-safe) and processed in parallel (TBB), with a
// bounded number of blocks in memory.
#include <functional>

#include "transport/transport_file.h"

namespace acpca {

/// Rows per block for about `bytes` of float rows.
long long rowsPerBlock(const TransportReader& transport, long long bytes = 8ll << 20);

/// Calls process(first, count, rows) for consecutive blocks covering every row;
/// rows holds count x rowLength floats. Block boundaries do not depend on the
/// thread count, so per-block results are deterministic.
void streamRowBlocks(const TransportReader& transport, long long blockRows,
                     const std::function<void(long long, long long, const float*)>& process);

}  // namespace acpca
