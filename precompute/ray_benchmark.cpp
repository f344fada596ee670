#include "precompute/ray_benchmark.h"

#include "core/stopwatch.h"
#include "core/text.h"

#include <tbb/blocked_range.h>
#include <tbb/info.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_arena.h>

#include <limits>
#include <numeric>

#include "core/error.h"
#include "precompute/embree_scene.h"
#include "precompute/image_row_schedule.h"
#include "precompute/transport_pass.h"

namespace acpca {

namespace {

/// The points (hit samples) and directions the loops trace.
struct Workload {
  std::vector<PixelSample> points;  // in 4x4 pixel blocks, 16 consecutive per block
  std::vector<Eigen::Vector3f> directions;
  std::vector<std::array<int, 16>> blocks;  // 4x4 texel blocks
  float epsilon = 0;
};

Workload makeWorkload(const EmbreeScene& embree, const GBuffer& g, const CubeLattice& lattice,
                      int imageRows) {
  Workload w;
  w.epsilon = embree.rayEpsilon();
  const int y0 = std::max(0, (g.size.height - imageRows) / 2) / 4 * 4;
  const int y1 = std::min(g.size.height, y0 + imageRows);
  for (int by = y0; by < y1; by += 4)
    for (int bx = 0; bx < g.size.width; bx += 4)
      for (int y = by; y < std::min(by + 4, y1); ++y)
        for (int x = bx; x < std::min(bx + 4, g.size.width); ++x)
          if (g.at(x, y, 0).material >= 0) w.points.push_back(g.at(x, y, 0));
  for (int j = 0; j < lattice.size(); ++j)
    w.directions.push_back(lattice.direction(j).cast<float>());
  w.blocks = texelBlocks(lattice);
  return w;
}

void setRay(RTCRay16& ray, int i, const Eigen::Vector3f& o, const Eigen::Vector3f& d, float tnear) {
  ray.org_x[i] = o.x(), ray.org_y[i] = o.y(), ray.org_z[i] = o.z();
  ray.dir_x[i] = d.x(), ray.dir_y[i] = d.y(), ray.dir_z[i] = d.z();
  ray.tnear[i] = tnear, ray.tfar[i] = std::numeric_limits<float>::infinity();
  ray.time[i] = 0, ray.mask[i] = ~0u, ray.id[i] = i, ray.flags[i] = 0;
}

/// rtcOccluded1: every point against every direction above its horizon.
long long loopSingle(RTCScene scene, const Workload& w, size_t begin, size_t end) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  long long rays = 0;
  for (size_t p = begin; p < end; ++p)
    for (const auto& d : w.directions) {
      if (w.points[p].normal.dot(d) <= 0) continue;
      RTCRay ray{};
      ray.org_x = w.points[p].origin.x(), ray.org_y = w.points[p].origin.y();
      ray.org_z = w.points[p].origin.z();
      ray.dir_x = d.x(), ray.dir_y = d.y(), ray.dir_z = d.z();
      ray.tnear = w.epsilon, ray.tfar = std::numeric_limits<float>::infinity(), ray.mask = ~0u;
      rtcOccluded1(scene, &ctx, &ray);
      ++rays;
    }
  return rays;
}

/// rtcOccluded16, one direction over 16 neighbouring points (the precompute's packet).
long long loopPointPackets(RTCScene scene, const Workload& w, size_t begin, size_t end) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(64) RTCRay16 ray;
  alignas(64) int valid[16];
  long long rays = 0;
  for (size_t p0 = begin; p0 < end; p0 += 16) {
    const size_t n = std::min<size_t>(16, end - p0);
    for (const auto& d : w.directions) {
      int active = 0;
      for (size_t i = 0; i < 16; ++i) {
        const auto& pt = w.points[p0 + std::min(i, n - 1)];
        valid[i] = (i < n && pt.normal.dot(d) > 0) ? -1 : 0;
        active += valid[i] != 0;
        setRay(ray, int(i), pt.origin, d, w.epsilon);
      }
      if (!active) continue;
      rtcOccluded16(valid, scene, &ctx, &ray);
      rays += active;
    }
  }
  return rays;
}

/// rtcOccluded16, 16 directions from one point (incoherent packets).
long long loopDirectionPackets(RTCScene scene, const Workload& w, size_t begin, size_t end) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  alignas(64) RTCRay16 ray;
  alignas(64) int valid[16];
  long long rays = 0;
  const size_t l = w.directions.size();
  for (size_t p = begin; p < end; ++p)
    for (size_t j0 = 0; j0 < l; j0 += 16) {
      int active = 0;
      for (size_t i = 0; i < 16; ++i) {
        const auto& d = w.directions[std::min(j0 + i, l - 1)];
        valid[i] = (j0 + i < l && w.points[p].normal.dot(d) > 0) ? -1 : 0;
        active += valid[i] != 0;
        setRay(ray, int(i), w.points[p].origin, d, w.epsilon);
      }
      if (!active) continue;
      rtcOccluded16(valid, scene, &ctx, &ray);
      rays += active;
    }
  return rays;
}

/// rtcOccluded16, a 4x4 block of neighbouring texels from one point.
long long loopTexelBlocks(RTCScene scene, const Workload& w, size_t begin, size_t end) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  alignas(64) RTCRay16 ray;
  alignas(64) int valid[16];
  long long rays = 0;
  for (size_t p = begin; p < end; ++p)
    for (const auto& block : w.blocks) {
      int active = 0;
      for (int i = 0; i < 16; ++i) {
        const int j = block[i] >= 0 ? block[i] : block[0];
        valid[i] = (block[i] >= 0 && w.points[p].normal.dot(w.directions[j]) > 0) ? -1 : 0;
        active += valid[i] != 0;
        setRay(ray, i, w.points[p].origin, w.directions[j], w.epsilon);
      }
      if (!active) continue;
      rtcOccluded16(valid, scene, &ctx, &ray);
      rays += active;
    }
  return rays;
}

template <typename Loop>
RayRate timeLoop(const std::string& name, RTCScene scene, const Workload& w, int repeats,
                 Loop loop) {
  RayRate best{name, 0, std::numeric_limits<double>::infinity()};
  const size_t blocks = (w.points.size() + 15) / 16;
  for (int r = 0; r < repeats; ++r) {
    const Stopwatch watch;
    const long long rays = tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, blocks, 4), 0LL,
        [&](const tbb::blocked_range<size_t>& range, long long sum) {
          return sum +
                 loop(scene, w, range.begin() * 16, std::min(w.points.size(), range.end() * 16));
        },
        std::plus<>());
    const double seconds = watch.seconds();
    if (seconds < best.seconds) best = {name, rays, seconds};
  }
  return best;
}

/// The real transport pass over the middle `imageRows` rows of the image,
/// direct light alone, without writing a file: its occlusion rays and seconds.
PrecomputeStats measurePrecomputeRate(const Scene& scene, const PrecomputeOptions& options,
                                      int imageRows) {
  validatePrecomputeOptions(options);
  const int threads = arenaThreads(options.threads);
  tbb::task_arena arena(threads);
  PrecomputeOptions direct = options;  // the rate of the shadow rays: direct light alone
  direct.bounces = 0;
  return arena.execute([&] {
    const TransportPass pass(scene, direct);
    const CubeLattice& lattice = pass.lattice;
    // The middle rows of the image, where the scene's detail usually is (the
    // same rows as the raw loops trace).
    const int height = scene.camera.size.height;
    const int want = std::clamp(imageRows, 1, height);
    std::vector<int> middle(want);
    std::iota(middle.begin(), middle.end(), (height - want) / 2);
    long long rows = 0;
    PrecomputeStats stats =
        renderImageRows(pass.renderer, middle, threads, [&](const std::vector<float>& r) {
          rows += static_cast<long long>(r.size()) / lattice.size();
        });
    stats.occupiedPixels = rows;
    stats.triangles = scene.triangleCount();
    stats.degenerateTriangles = pass.embree.degenerateTriangles();
    stats.seconds = stats.transportSeconds;
    return stats;
  });
}

}  // namespace

const RayRate& RayBenchmarkReport::bestRawLoop() const {
  ACPCA_CHECK(!rawLoops.empty(), "no raw loops measured");
  const RayRate* best = &rawLoops.front();
  for (const auto& r : rawLoops)
    if (r.raysPerSecond() > best->raysPerSecond()) best = &r;
  return *best;
}

RayBenchmarkReport runRayBenchmark(const Scene& scene, int cubemapResolution, int threads,
                                   int imageRows, int repeats) {
  RayBenchmarkReport report;
  report.threads = threads > 0 ? threads : tbb::info::default_concurrency();
  report.triangles = scene.triangleCount();
  report.imageRows = imageRows;
  PrecomputeOptions options;
  options.cubemapResolution = cubemapResolution;
  options.threads = report.threads;
  options.samplesPerPixel = 1;  // the raw loops trace from pixel centres too
  report.precompute = {"precompute (4x4 texel blocks, BRDF and rows, all)", 0,
                       std::numeric_limits<double>::infinity()};
  for (int r = 0; r < repeats; ++r) {
    const PrecomputeStats s = measurePrecomputeRate(scene, options, imageRows);
    if (s.transportSeconds < report.precompute.seconds)
      report.precompute = {report.precompute.name, s.occlusionRays, s.transportSeconds};
  }
  tbb::task_arena arena(report.threads);
  arena.execute([&] {
    const CubeLattice lattice(cubemapResolution);
    const EmbreeScene embree(scene);
    const GBuffer gbuffer = renderGBuffer(embree, scene.camera, 1);
    const Workload w = makeWorkload(embree, gbuffer, lattice, imageRows);
    report.rawLoops.push_back(
        timeLoop("raw rtcOccluded1", embree.handle(), w, repeats, loopSingle));
    report.rawLoops.push_back(timeLoop("raw rtcOccluded16, one direction over 4x4 points",
                                       embree.handle(), w, repeats, loopPointPackets));
    report.rawLoops.push_back(timeLoop("raw rtcOccluded16, 16 directions from one point",
                                       embree.handle(), w, repeats, loopDirectionPackets));
    report.rawLoops.push_back(timeLoop("raw rtcOccluded16, 4x4 texel block from one point",
                                       embree.handle(), w, repeats, loopTexelBlocks));
  });
  return report;
}

double RayBenchmarkReport::ratioToBest() const {
  return precompute.raysPerSecond() / bestRawLoop().raysPerSecond();
}

std::string RayBenchmarkReport::table() const {
  std::string out = formatted("%-58s %14s %12s %10s\n", "loop", "rays", "M rays/s", "per core");
  const auto row = [&](const RayRate& rate) {
    out += formatted("%-58s %14lld %12.2f %10.2f\n", rate.name.c_str(), rate.rays,
                     rate.raysPerSecond() / 1e6, rate.raysPerSecond() / 1e6 / threads);
  };
  row(precompute);
  for (const auto& raw : rawLoops) row(raw);
  out += formatted("precompute / best raw loop (%s): %.3f\n", bestRawLoop().name.c_str(),
                   ratioToBest());
  return out;
}

nlohmann::json RayBenchmarkReport::json() const {
  Table loops({"name", "rays", "rays_per_second"});
  for (const auto& raw : rawLoops) loops.add({raw.name, raw.rays, raw.raysPerSecond()});
  return {{"triangles", triangles},
          {"threads", threads},
          {"precompute_rays_per_second", precompute.raysPerSecond()},
          {"raw_loops", loops.json()},
          {"best_raw_loop", bestRawLoop().name},
          {"ratio_to_best", ratioToBest()}};
}

}  // namespace acpca
