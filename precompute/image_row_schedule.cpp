#include "precompute/image_row_schedule.h"

#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <unordered_map>

#include "core/error.h"
#include "core/ordered_pipeline.h"
#include "core/rank_gather.h"
#include "core/ranks.h"
#include "core/stopwatch.h"

namespace acpca {

namespace {

/// Image rows per line of an MPI job's log.
constexpr int kLoggedRows = 16;

}  // namespace

PrecomputeStats renderImageRows(const ImageRowRenderer& renderer, const std::vector<int>& rows,
                                int threads, const std::function<void(std::vector<float>&)>& sink,
                                const std::function<void(int)>& onStart) {
  struct Slot {
    int y = 0;
    ImageRowRenderer::Counts counts;
    std::vector<float> rows;
  };
  std::atomic<unsigned long long> threadMask{0};
  std::atomic<long long> shadowRays{0}, pathRays{0}, supersampled{0};
  size_t next = 0;
  const Stopwatch watch;
  runOrderedPipeline<Slot>(
      2 * threads,
      [&](Slot& slot) {
        if (next >= rows.size()) return false;
        if (onStart) onStart(rows[next]);
        slot.y = rows[next++];
        return true;
      },
      [&](Slot& slot) {
        threadMask |= 1ull << (tbb::this_task_arena::current_thread_index() & 63);
        slot.counts = renderer.render(slot.y, slot.rows);
        shadowRays += slot.counts.shadowRays;
        pathRays += slot.counts.pathRays;
        supersampled += slot.counts.supersampled;
      },
      [&](Slot& slot) { sink(slot.rows); });
  PrecomputeStats stats;
  stats.transportSeconds = watch.seconds();
  stats.occlusionRays = shadowRays;
  stats.pathRays = pathRays;
  stats.supersampledPixels = supersampled;
  stats.threadsUsed = std::popcount(threadMask.load());
  return stats;
}

/// Image rows are dealt round robin (row y to rank y mod K): rank 0 writes in
/// image order and a sender waits until its row's turn, so every rank can run
/// ahead of the writer by its pipeline's few rows only, and round robin keeps
/// them all inside that window (whole blocks of rows per rank ran one rank at
/// a time). The transport rows of an image row never depend on who renders
/// it, so the file does not depend on the rank count.
PrecomputeStats renderAndGatherImageRows(
    const ImageRowRenderer& renderer, int threads,
    const std::function<void(const std::vector<float>&)>& write, const PrecomputeOptions& options) {
  const int height = renderer.height();
  const int count = ranks::count();
  std::vector<int> mine;
  for (long long y : ranks::itemsOfThisRank(height)) mine.push_back(static_cast<int>(y));
  const auto onStart = [&](int y) {
    // Each rank logs the first of its rows in every 16: the last line of a
    // rank that dies names where it was.
    if (count > 1 && y % kLoggedRows < count && options.log) {
      const int first = y / kLoggedRows * kLoggedRows;
      options.log(concat(ranks::prefix(), "starts image rows ", first, "-",
                         std::min(height, first + kLoggedRows) - 1));
    }
    if (options.beforeImageRow) options.beforeImageRow(y);
  };
  ranks::Gather<float> gather(height, ranks::GatherOrder::ItemOrder,
                              [&](long long, std::vector<float>& rows) { write(rows); });
  size_t mineDone = 0;
  PrecomputeStats stats = renderImageRows(
      renderer, mine, threads,
      [&](std::vector<float>& rows) { gather.put(mine[mineDone++], rows); }, onStart);
  gather.finish();
  return stats;
}

void buildIndirectCache(const ImageRowRenderer& renderer, IndirectLight& indirect, int threads,
                        PrecomputeStats& stats, const PrecomputeOptions& options) {
  struct Slot {
    int y = 0;
    std::unordered_map<std::uint64_t, PathVertex> cells;
    std::vector<std::uint64_t> order;
  };
  const Stopwatch watch;
  const int height = renderer.height();
  int next = 0;
  runOrderedPipeline<Slot>(
      2 * threads,
      [&](Slot& slot) {
        if (next >= height) return false;
        slot.y = next++;
        return true;
      },
      [&](Slot& slot) { renderer.collectCells(slot.y, slot.cells, slot.order); },
      [&](Slot& slot) {
        indirect.mergeCells(slot.cells, slot.order);
        if (options.cacheProgress) options.cacheProgress(slot.y + 1, height);
      });
  stats.cacheRays = indirect.fillCache(options.cacheFillProgress);
  stats.cachePoints = indirect.cachedPoints();
  stats.cacheSeconds = watch.seconds();
}

}  // namespace acpca
