#include "transport/row_stream.h"

#include <tbb/task_arena.h>

#include <vector>

#include "core/ordered_pipeline.h"

namespace acpca {

long long rowsPerBlock(const TransportReader& transport, long long bytes) {
  return std::max<long long>(1, bytes / (4ll * transport.rowLength()));
}

void streamRowBlocks(const TransportReader& transport, long long blockRows,
                     const std::function<void(long long, long long, const float*)>& process) {
  struct Block {
    long long first = 0, count = 0;
    std::vector<float> rows;
  };
  const long long total = transport.rows();
  const int l = transport.rowLength();
  long long next = 0;
  runOrderedPipeline<Block>(
      2 * tbb::this_task_arena::max_concurrency(),
      [&](Block& b) {  // HDF5 is not thread-safe: one reader, in order
        if (next >= total) return false;
        b.first = next;
        b.count = std::min(blockRows, total - next);
        b.rows.resize(static_cast<size_t>(b.count) * l);
        transport.readRows(b.first, b.count, b.rows.data());
        next += b.count;
        return true;
      },
      [&](Block& b) { process(b.first, b.count, b.rows.data()); }, [](Block&) {});
}

}  // namespace acpca
