#include "precompute/transport/row_stream.h"

#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <vector>

namespace acpca {

long long rowsPerBlock(const TransportReader& transport, long long bytes) {
  return std::max<long long>(1, bytes / (4ll * transport.latticeSize()));
}

void streamRowBlocks(const TransportReader& transport, long long blockRows,
                     const std::function<void(long long, long long, const float*)>& process) {
  struct Block {
    long long first = 0, count = 0;
    std::vector<float> rows;
  };
  const long long total = transport.rows();
  const int l = transport.latticeSize();
  const int tokens = 2 * tbb::this_task_arena::max_concurrency();
  std::vector<Block> blocks(tokens);
  long long next = 0;
  int slot = 0;
  tbb::parallel_pipeline(
      tokens, tbb::make_filter<void, Block*>(tbb::filter_mode::serial_in_order,
                                             [&](tbb::flow_control& fc) -> Block* {
                                               if (next >= total) {
                                                 fc.stop();
                                                 return nullptr;
                                               }
                                               // At most `tokens` blocks are in flight, and they
                                               // finish in order, so a slot is free when reused.
                                               Block* b = &blocks[slot++ % tokens];
                                               b->first = next;
                                               b->count = std::min(blockRows, total - next);
                                               b->rows.resize(static_cast<size_t>(b->count) * l);
                                               transport.readRows(b->first, b->count,
                                                                  b->rows.data());
                                               next += b->count;
                                               return b;
                                             }) &
                  tbb::make_filter<Block*, Block*>(tbb::filter_mode::parallel,
                                                   [&](Block* b) {
                                                     process(b->first, b->count, b->rows.data());
                                                     return b;
                                                   }) &
                  tbb::make_filter<Block*, void>(tbb::filter_mode::serial_in_order, [](Block*) {}));
}

}  // namespace acpca
