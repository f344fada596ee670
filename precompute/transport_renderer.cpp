#include "precompute/transport_renderer.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <filesystem>
#include <optional>

#include "core/error.h"
#include "core/half.h"
#include "core/input_guard.h"
#include "core/ranks.h"
#include "core/stopwatch.h"
#include "precompute/image_row_schedule.h"
#include "precompute/transport_pass.h"

namespace acpca {

ResourceNeed precomputeNeed(const Scene& scene, const std::string& outPath,
                            const PrecomputeOptions& o) {
  const long long pixels =
      static_cast<long long>(scene.camera.size.width) * scene.camera.size.height;
  const long long directions = 6LL * o.cubemapResolution * o.cubemapResolution;
  const int rowsPerPixel = o.bounces > 0 ? 3 : 1;  // coloured bounced light: R, G and B rows
  ResourceNeed need;
  need.what =
      concat("a ", scene.camera.size.width, "x", scene.camera.size.height, " transport of 6x",
             o.cubemapResolution, "x", o.cubemapResolution, " directions");
  need.diskBytes = pixels * rowsPerPixel * directions * (o.precision == Precision::F16 ? 2 : 4);
  need.largestFile = need.diskBytes;
  const std::filesystem::path out(outPath);
  need.diskDirectory = out.has_parent_path() ? out.parent_path().string() : ".";
  need.diskAdvice =
      "the streamed build (adaptive-cpca build) renders and compresses tile by tile with no "
      "transport on disk; or render a smaller image, fewer bounces or f16 values";
  need.memoryAdvice = "render a smaller image or fewer samples per pixel";
  // The G-buffer's samples, each row's pixel, albedo and coverage, and the
  // scene with its BVH (about 100 bytes a triangle).
  need.memoryBytes =
      pixels * (o.samplesPerPixel * static_cast<long long>(sizeof(PixelSample)) + 32) +
      scene.triangleCount() * 100;
  return need;
}

PrecomputeStats precomputeTransport(const Scene& scene, const std::string& outPath,
                                    const PrecomputeOptions& options) {
  validatePrecomputeOptions(options);
  refuseOutputOverInputs(outPath, scene.files);
  requireResources(precomputeNeed(scene, outPath, options), options.force);
  const Stopwatch watch;
  const int threads = arenaThreads(options.threads);
  tbb::task_arena arena(threads);
  return arena.execute([&] {
    TransportPass pass(scene, options);
    const EmbreeScene& embree = pass.embree;

    const TransportHeader header = transportHeader(scene, options, pass);

    // Only rank 0 of an MPI job writes; every rank builds the same header.
    std::optional<TransportWriter> writer;
    if (ranks::rank() == 0) writer.emplace(outPath, header);
    const ImageRowRenderer& renderer = pass.renderer;
    PrecomputeStats cache;  // each rank builds the same cache (same paths, same order)
    if (pass.indirect && options.indirectCacheCell > 0)
      buildIndirectCache(renderer, *pass.indirect, threads, cache, options);
    long long written = 0;
    PrecomputeStats stats = renderAndGatherImageRows(
        renderer, threads,
        [&](const std::vector<float>& rows) {
          const long long count = static_cast<long long>(rows.size()) / renderer.rowLength();
          writer->writeRows(written, count, rows.data());
          written += count;
          if (options.progress) options.progress(written, header.rows());
        },
        options);
    stats.occlusionRays = ranks::sum(stats.occlusionRays);
    stats.pathRays = ranks::sum(stats.pathRays);
    stats.supersampledPixels = ranks::sum(stats.supersampledPixels);
    stats.threadsUsed = static_cast<int>(ranks::sum(stats.threadsUsed));
    if (writer) {
      writer->finish();
      stats.bytesWritten = writer->bytesWritten();
    }
    stats.cachePoints = cache.cachePoints;
    stats.cacheRays = cache.cacheRays;
    stats.cacheSeconds = cache.cacheSeconds;
    stats.channels = header.channels;
    stats.triangles = scene.triangleCount();
    stats.degenerateTriangles = embree.degenerateTriangles();
    stats.occupiedPixels = header.rows();
    stats.seconds = watch.seconds();
    return stats;
  });
}

struct RowSource::Impl {
  Impl(const Scene& scene, const PrecomputeOptions& options)
      : pass(scene, options), header(transportHeader(scene, options, pass)) {
    if (pass.indirect && options.indirectCacheCell > 0)
      buildIndirectCache(pass.renderer, *pass.indirect, tbb::this_task_arena::max_concurrency(),
                         stats, options);
    stats.triangles = scene.triangleCount();
    stats.degenerateTriangles = pass.embree.degenerateTriangles();
    stats.occupiedPixels = header.rows();
    stats.channels = header.channels;
  }
  TransportPass pass;
  const TransportHeader header;
  PrecomputeStats stats;
};

RowSource::RowSource(const Scene& scene, const PrecomputeOptions& options) {
  validatePrecomputeOptions(options);
  impl_ = std::make_unique<Impl>(scene, options);
}

RowSource::~RowSource() = default;

const TransportHeader& RowSource::header() const {
  return impl_->header;
}

const PrecomputeStats& RowSource::setupStats() const {
  return impl_->stats;
}

std::pair<long long, long long> RowSource::render(const std::vector<long long>& rows,
                                                  float* out) const {
  const TransportHeader& h = impl_->header;
  const size_t length = h.rowLength();
  const int width = h.camera.size.width;
  std::atomic<long long> shadowRays{0}, pathRays{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, rows.size(), 4), [&](const auto& range) {
    ImageRowRenderer::Counts counts;
    std::vector<std::uint16_t> half(length);
    for (size_t i = range.begin(); i != range.end(); ++i) {
      const std::int32_t pixel = h.pixels.at(static_cast<size_t>(rows[i]));
      float* row = out + i * length;
      std::fill_n(row, length, 0.0f);
      impl_->pass.renderer.renderPixel(pixel % width, pixel / width, row, counts);
      if (h.precision == Precision::F16) {  // as the transport file stores it
        floatToHalf(row, half.data(), length);
        halfToFloat(half.data(), row, length);
      }
    }
    shadowRays += counts.shadowRays;
    pathRays += counts.pathRays;
  });
  return {shadowRays.load(), pathRays.load()};
}

}  // namespace acpca
