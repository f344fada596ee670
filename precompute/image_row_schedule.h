#pragma once
// Which image rows are rendered when and where, and the order their transport
// rows are handed on: a pipeline over image rows (computed in parallel,
// delivered in order, so the output never depends on the thread count), the
// same dealt over an MPI job's ranks, and the indirect cache's pre-pass.
// Inside the library only.
#include <functional>
#include <vector>

#include "precompute/image_row_renderer.h"
#include "precompute/precompute_options.h"

namespace acpca {

/// Renders these image rows (in parallel, `threads` of them) and hands each
/// one's transport rows to `sink` in the order given; `onStart(y)` is called
/// from one thread as image row y is taken up. Returns the counts and the
/// seconds spent (transportSeconds).
PrecomputeStats renderImageRows(const ImageRowRenderer& renderer, const std::vector<int>& rows,
                                int threads, const std::function<void(std::vector<float>&)>& sink,
                                const std::function<void(int)>& onStart = {});

/// Every image row's transport rows handed to `write` in image order on rank
/// 0, the rows of an MPI job's other ranks received from them; the other ranks
/// render their own rows and send them to rank 0. A single process renders
/// and writes them all. Returns this rank's counts.
PrecomputeStats renderAndGatherImageRows(
    const ImageRowRenderer& renderer, int threads,
    const std::function<void(const std::vector<float>&)>& write, const PrecomputeOptions& options);

/// The indirect cache's pre-pass: every image row's path vertices, in
/// parallel, merged into the cache in image order (so its cells and their
/// points never depend on the thread count), then every cell's visibility
/// traced; its figures go to stats.
void buildIndirectCache(const ImageRowRenderer& renderer, IndirectLight& indirect, int threads,
                        PrecomputeStats& stats, const PrecomputeOptions& options);

}  // namespace acpca
