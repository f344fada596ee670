#include "relight/dense_relight.h"

#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <Eigen/Core>

#include "precompute/transport/error.h"

namespace acpca {

std::vector<std::vector<float>> denseRelight(const TransportReader& transport,
                                             const std::vector<LatticeLighting>& lightings) {
  const int l = transport.latticeSize();
  const long long rows = transport.rows();
  const int maps = static_cast<int>(lightings.size());
  // L: l x 3M, column 3m + c holds channel c of map m.
  Eigen::MatrixXf lighting(l, 3 * maps);
  for (int m = 0; m < maps; ++m) {
    ACPCA_CHECK(lightings[m].size() == 3u * l, "lighting ", m, " has ", lightings[m].size(),
                " values for a lattice of ", l);
    for (int j = 0; j < l; ++j)
      for (int c = 0; c < 3; ++c)
        lighting(j, 3 * m + c) = static_cast<float>(lightings[m][3 * j + c]);
  }
  std::vector<std::vector<float>> result(maps, std::vector<float>(3 * rows));
  if (rows == 0 || maps == 0) return result;

  using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  struct Block {
    long long first = 0, count = 0;
    RowMatrix rows;
  };
  const long long blockRows = std::max<long long>(1, (8ll << 20) / (4ll * l));  // ~8 MiB of T
  const int tokens = 2 * tbb::this_task_arena::max_concurrency();
  std::vector<Block> blocks(tokens);
  long long next = 0;
  int slot = 0;
  const auto& albedo = transport.header().albedo;
  tbb::parallel_pipeline(
      tokens, tbb::make_filter<void, Block*>(tbb::filter_mode::serial_in_order,
                                             [&](tbb::flow_control& fc) -> Block* {
                                               if (next >= rows) {
                                                 fc.stop();
                                                 return nullptr;
                                               }
                                               Block* b = &blocks[slot++ % tokens];
                                               b->first = next;
                                               b->count = std::min(blockRows, rows - next);
                                               b->rows.resize(b->count, l);
                                               transport.readRows(b->first, b->count,
                                                                  b->rows.data());
                                               next += b->count;
                                               return b;
                                             }) &
                  tbb::make_filter<Block*, void>(tbb::filter_mode::parallel, [&](Block* b) {
                    const Eigen::MatrixXf product = b->rows * lighting;  // count x 3M
                    for (long long r = 0; r < b->count; ++r) {
                      const long long row = b->first + r;
                      for (int m = 0; m < maps; ++m)
                        for (int c = 0; c < 3; ++c)
                          result[m][3 * row + c] = albedo[3 * row + c] * product(r, 3 * m + c);
                    }
                  }));
  return result;
}

}  // namespace acpca
