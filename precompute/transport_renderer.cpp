#include "precompute/transport_renderer.h"

#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <numeric>
#include <optional>
#include <unordered_map>

#include "core/error.h"
#include "core/half.h"
#include "core/input_guard.h"
#include "core/ordered_pipeline.h"
#include "core/rank_gather.h"
#include "core/ranks.h"
#include "core/stopwatch.h"
#include "precompute/embree_scene.h"
#include "precompute/indirect_light.h"
#include "precompute/sample_patterns.h"
#include "precompute/shadow_rays.h"

namespace acpca {

namespace {

/// Image rows per band: the unit of parallel work and of ordered writing.
constexpr int kBandRows = 1;

/// Computes transport rows for bands of kBandRows image rows: the direct part
/// by the lattice's shadow rays from each traced camera sample, and with
/// bounces the indirect part (indirect_light.h) in the same row.
class BandRenderer {
 public:
  BandRenderer(const GBuffer& gbuffer, const ShadowRays& shadows, const CubeLattice& lattice,
               Antialiasing mode, const IndirectLight* indirect)
      : gbuffer_(gbuffer),
        mode_(mode),
        shadows_(shadows),
        indirect_(indirect),
        l_(lattice.size()),
        channels_(indirect ? indirect->settings().channels : 1) {}

  int rowLength() const { return channels_ * l_; }

  struct Counts {
    long long shadowRays = 0, pathRays = 0, supersampled = 0;
  };

  /// Fills out (one row per occupied pixel of image rows [y0, y0 + kBandRows), in
  /// row-major order) and counts the rays traced.
  Counts render(int y0, std::vector<float>& out) const {
    const int width = gbuffer_.size.width;
    const int y1 = std::min(y0 + kBandRows, gbuffer_.size.height);
    int rows = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < width; ++x) rows += hits(x, y) > 0;
    const size_t length = rowLength();
    out.assign(static_cast<size_t>(rows) * length, 0.0f);
    Counts counts;
    int row = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < width; ++x)
        if (hits(x, y) > 0) renderPixel(x, y, out.data() + row++ * length, counts);
    return counts;
  }

  /// Adds pixel (x, y)'s row to target (zeroed, rowLength values) and counts
  /// its rays.
  void renderPixel(int x, int y, float* target, Counts& counts) const {
    thread_local std::vector<float> weights;
    sampleWeights(gbuffer_, x, y, mode_, weights);
    counts.supersampled +=
        std::count_if(weights.begin() + 1, weights.end(), [](float w) { return w > 0; }) > 0;
    for (int s = 0; s < gbuffer_.samplesPerPixel; ++s) {
      const PixelSample& ps = gbuffer_.at(x, y, s);
      if (weights[s] > 0) counts.shadowRays += traceDirect(ps, weights[s], target);
    }
    // Light arriving straight from the lattice has its colour in every channel.
    for (int c = 1; c < channels_; ++c) std::copy_n(target, l_, target + c * l_);
    if (indirect_)
      for (int s = 0; s < gbuffer_.samplesPerPixel; ++s)
        if (weights[s] > 0) {
          const auto rays =
              indirect_->add(gbuffer_.at(x, y, s), sampleSeed(x, y, s), weights[s], target);
          counts.pathRays += rays.paths;
          counts.shadowRays += rays.shadow;
        }
  }

  /// The cache pre-pass over one band: the cells its paths reach, in order.
  void collectCells(int y0, std::unordered_map<std::uint64_t, PathVertex>& cells,
                    std::vector<std::uint64_t>& order) const {
    cells.clear(), order.clear();
    const int y1 = std::min(y0 + kBandRows, gbuffer_.size.height);
    std::vector<float> weights;
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < gbuffer_.size.width; ++x) {
        if (hits(x, y) == 0) continue;
        sampleWeights(gbuffer_, x, y, mode_, weights);
        for (int s = 0; s < gbuffer_.samplesPerPixel; ++s)
          if (weights[s] > 0)
            indirect_->collectCells(gbuffer_.at(x, y, s), sampleSeed(x, y, s), cells, order);
      }
  }

 private:
  int hits(int x, int y) const {
    int n = 0;
    for (int s = 0; s < gbuffer_.samplesPerPixel; ++s) n += gbuffer_.at(x, y, s).material >= 0;
    return n;
  }

  /// Seeds a camera sample's paths by where it is, so that they never depend
  /// on which thread renders them.
  std::uint64_t sampleSeed(int x, int y, int s) const {
    return (static_cast<std::uint64_t>(y) * gbuffer_.size.width + x) * gbuffer_.samplesPerPixel + s;
  }

  /// Adds weight x V x cos x (f / albedo) of one pixel sample to its row.
  long long traceDirect(const PixelSample& ps, float weight, float* row) const {
    const Material& m = shadows_.scene().materials()[ps.material];
    const LobeShape shape(m, ps.normal, ps.toViewer);
    const TexelDirections& dirs = shadows_.directions();
    return shadows_.trace(
        ps.origin, ps.normal, ps.geometricNormal, 0.0f, [&](int j, size_t q, float cosine) {
          row[j] +=
              weight * dirs.weight[q] * cosine * shape(dirs.x[q], dirs.y[q], dirs.z[q], cosine);
        });
  }

  const GBuffer& gbuffer_;
  const Antialiasing mode_;
  const ShadowRays& shadows_;
  const IndirectLight* indirect_;
  const int l_;
  const int channels_;
};

void validateOptions(const PrecomputeOptions& o) {
  if (o.cubemapResolution < 1 || o.cubemapResolution > 256)
    throw ParameterError("cube-map resolution", o.cubemapResolution, "is out of range 1..256");
  if (o.samplesPerPixel < 1 || o.samplesPerPixel > 256)
    throw ParameterError("samples per pixel", o.samplesPerPixel, "is out of range 1..256");
  if (o.texelRays < 1 || o.texelRays > 1024)
    throw ParameterError("rays per texel", o.texelRays, "is out of range 1..1024");
  if (o.threads < 0) throw ParameterError("threads", o.threads, "must be >= 0");
  if (o.bounces < 0 || o.bounces > kMaxBounces)
    throw ParameterError("bounces", o.bounces, concat("is out of range 0..", kMaxBounces));
  if (o.indirectSamples < 1 || o.indirectSamples > kMaxIndirectSamples)
    throw ParameterError("indirect samples", o.indirectSamples,
                         concat("is out of range 1..", kMaxIndirectSamples));
  if (!(o.indirectCacheCell >= 0 && o.indirectCacheCell <= 0.1))
    throw ParameterError("indirect cache cell", o.indirectCacheCell,
                         "is out of range 0..0.1 (a fraction of the scene's extent; 0: no cache)");
}

int arenaThreads(int threads) {
  return threads > 0 ? threads : tbb::info::default_concurrency();
}

/// Runs the band pipeline over image rows [firstBand, lastBand) * kBandRows: bands are
/// computed in parallel and handed to `sink` in order (so output is identical for
/// any thread count).
template <typename Sink, typename OnStart>
PrecomputeStats runBands(const BandRenderer& renderer, const std::vector<int>& bands, int threads,
                         Sink&& sink, OnStart&& onStart) {
  struct Slot {
    int y0 = 0;
    BandRenderer::Counts counts;
    std::vector<float> rows;
  };
  std::atomic<unsigned long long> threadMask{0};
  std::atomic<long long> shadowRays{0}, pathRays{0}, supersampled{0};
  size_t next = 0;
  const Stopwatch watch;
  runOrderedPipeline<Slot>(
      2 * threads,
      [&](Slot& slot) {
        if (next >= bands.size()) return false;
        onStart(bands[next]);
        slot.y0 = kBandRows * bands[next++];
        return true;
      },
      [&](Slot& slot) {
        threadMask |= 1ull << (tbb::this_task_arena::current_thread_index() & 63);
        slot.counts = renderer.render(slot.y0, slot.rows);
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

template <typename Sink>
PrecomputeStats runBands(const BandRenderer& renderer, int firstBand, int lastBand, int threads,
                         Sink&& sink) {
  std::vector<int> bands(std::max(0, lastBand - firstBand));
  std::iota(bands.begin(), bands.end(), firstBand);
  return runBands(renderer, bands, threads, sink, [](int) {});
}

/// Bands per tile, the unit an MPI job's log names (16 image rows).
constexpr int kTileBands = 16 / kBandRows;

/// Writes every band of the image in order, the bands of an MPI job's other
/// ranks received from them (rank 0), or renders this rank's bands and sends
/// them to rank 0 (the others). A single process renders and writes them all.
/// Bands are dealt round robin (band b to rank b mod K): rank 0 writes in band
/// order and a sender waits until its band's turn, so every rank can run
/// ahead of the writer by its pipeline's few bands only, and round robin keeps
/// them all inside that window (whole tiles per rank ran one rank at a time).
/// The rows of a band never depend on who renders it, so the file does not
/// depend on the rank count. Returns this rank's counts.
PrecomputeStats renderAllBands(const BandRenderer& renderer, int height, int threads,
                               const std::function<void(const std::vector<float>&)>& write,
                               const PrecomputeOptions& options) {
  const int bandCount = (height + kBandRows - 1) / kBandRows;
  const int count = ranks::count();
  std::vector<int> mine;
  for (long long band : ranks::itemsOfThisRank(bandCount)) mine.push_back(static_cast<int>(band));
  const auto onStart = [&](int band) {
    // Each rank logs the first of its bands in every tile: the last line of a
    // rank that dies names where it was.
    if (count > 1 && band % kTileBands < count && options.log)
      options.log(concat(ranks::prefix(), "starts tile ", band / kTileBands, " (image rows ",
                         band * kBandRows, "-",
                         std::min(height, (band + kTileBands) * kBandRows) - 1, ")"));
    if (options.beforeBand) options.beforeBand(band);
  };
  ranks::Gather<float> gather(bandCount, ranks::GatherOrder::ItemOrder,
                              [&](long long, std::vector<float>& rows) { write(rows); });
  size_t mineDone = 0;
  PrecomputeStats stats = runBands(
      renderer, mine, threads,
      [&](std::vector<float>& rows) { gather.put(mine[mineDone++], rows); }, onStart);
  gather.finish();
  return stats;
}

/// The cache's pre-pass: every band's path vertices, in parallel, merged into
/// the cache in band order (so its cells and their points never depend on the
/// thread count), then every cell's visibility traced.
void buildIndirectCache(const BandRenderer& renderer, IndirectLight& indirect, int height,
                        int threads, PrecomputeStats& stats, const PrecomputeOptions& options) {
  struct Slot {
    int y0 = 0;
    std::unordered_map<std::uint64_t, PathVertex> cells;
    std::vector<std::uint64_t> order;
  };
  const Stopwatch watch;
  const int bands = (height + kBandRows - 1) / kBandRows;
  int next = 0;
  runOrderedPipeline<Slot>(
      2 * threads,
      [&](Slot& slot) {
        if (next >= bands) return false;
        slot.y0 = kBandRows * next++;
        return true;
      },
      [&](Slot& slot) { renderer.collectCells(slot.y0, slot.cells, slot.order); },
      [&](Slot& slot) {
        indirect.mergeCells(slot.cells, slot.order);
        if (options.cacheProgress)
          options.cacheProgress(std::min(slot.y0 + kBandRows, height), height);
      });
  stats.cacheRays = indirect.fillCache(options.cacheFillProgress);
  stats.cachePoints = indirect.cachedPoints();
  stats.cacheSeconds = watch.seconds();
}

/// Everything a transport pass over a scene needs, built once inside the arena.
struct TransportPass {
  TransportPass(const Scene& scene, const PrecomputeOptions& options)
      : lattice(options.cubemapResolution),
        embree(scene),
        gbuffer(renderGBuffer(embree, scene.camera, options.samplesPerPixel)),
        dirs(makeTexelDirections(lattice, options.texelRays)),
        shadows(embree, dirs, lattice),
        indirect(options.bounces > 0
                     ? std::make_unique<IndirectLight>(embree, shadows, lattice.size(), scene,
                                                       indirectSettings(scene, options))
                     : nullptr),
        renderer(gbuffer, shadows, lattice, options.antialiasing, indirect.get()) {}

  static IndirectSettings indirectSettings(const Scene& scene, const PrecomputeOptions& o) {
    IndirectSettings s;
    s.bounces = o.bounces;
    s.samples = o.indirectSamples;
    s.cacheCell = o.indirectCacheCell;
    s.channels = sceneIsGrey(scene) ? 1 : 3;
    return s;
  }

  int channels() const { return indirect ? indirect->settings().channels : 1; }

  const CubeLattice lattice;
  const EmbreeScene embree;
  const GBuffer gbuffer;
  const TexelDirections dirs;
  const ShadowRays shadows;
  const std::unique_ptr<IndirectLight> indirect;
  const BandRenderer renderer;
};

/// The header of the scene's transport: the image geometry, and per occupied
/// pixel (row-major order) its albedo (mean over hit samples), coverage and
/// normal.
TransportHeader transportHeader(const Scene& scene, const PrecomputeOptions& options,
                                const GBuffer& gbuffer, int channels) {
  TransportHeader header;
  header.camera = scene.camera;
  header.cubemapResolution = options.cubemapResolution;
  header.samplesPerPixel = options.samplesPerPixel;
  header.texelRays = options.texelRays;
  header.precision = options.precision;
  header.scene = scene.name;
  header.channels = channels;
  if (options.bounces > 0) {
    header.bounces = options.bounces;
    header.indirectSamples = options.indirectSamples;
    header.indirectCacheCell = options.indirectCacheCell;
  }
  const ImageSize size = scene.camera.size;
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      Eigen::Vector3f albedo = Eigen::Vector3f::Zero();
      int hits = 0, first = -1;
      for (int s = 0; s < options.samplesPerPixel; ++s) {
        const PixelSample& ps = gbuffer.at(x, y, s);
        if (ps.material < 0) continue;
        albedo += ps.albedo;
        if (hits++ == 0) first = s;
      }
      if (hits == 0) continue;
      header.pixels.push_back(y * size.width + x);
      albedo /= float(hits);
      header.albedo.insert(header.albedo.end(), albedo.data(), albedo.data() + 3);
      header.coverage.push_back(float(hits) / options.samplesPerPixel);
      const auto& n = gbuffer.at(x, y, first).normal;
      header.normals.insert(header.normals.end(), n.data(), n.data() + 3);
    }
  return header;
}

}  // namespace

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
  validateOptions(options);
  refuseOutputOverInputs(outPath, scene.files);
  requireResources(precomputeNeed(scene, outPath, options), options.force);
  const Stopwatch watch;
  const int threads = arenaThreads(options.threads);
  tbb::task_arena arena(threads);
  return arena.execute([&] {
    TransportPass pass(scene, options);
    const EmbreeScene& embree = pass.embree;
    const GBuffer& gbuffer = pass.gbuffer;

    const TransportHeader header = transportHeader(scene, options, gbuffer, pass.channels());
    const ImageSize size = scene.camera.size;

    // Only rank 0 of an MPI job writes; every rank builds the same header.
    std::optional<TransportWriter> writer;
    if (ranks::rank() == 0) writer.emplace(outPath, header);
    const BandRenderer& renderer = pass.renderer;
    PrecomputeStats cache;  // each rank builds the same cache (same paths, same order)
    if (pass.indirect && options.indirectCacheCell > 0)
      buildIndirectCache(renderer, *pass.indirect, size.height, threads, cache, options);
    long long written = 0;
    PrecomputeStats stats = renderAllBands(
        renderer, size.height, threads,
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
      : pass(scene, options),
        header(transportHeader(scene, options, pass.gbuffer, pass.channels())) {
    if (pass.indirect && options.indirectCacheCell > 0)
      buildIndirectCache(pass.renderer, *pass.indirect, scene.camera.size.height,
                         tbb::this_task_arena::max_concurrency(), stats, options);
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
  validateOptions(options);
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
    BandRenderer::Counts counts;
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

double phongHalfWidth(double exponent) {
  return std::acos(std::pow(0.5, 1 / exponent));
}

double lobeHalfWidth(const Material& m) {
  if (m.specular <= 0) return 0;
  if (m.type == Material::Type::Phong) return m.exponent > 0 ? phongHalfWidth(m.exponent) : 0;
  if (m.type == Material::Type::Ggx) {
    // D falls to half its peak where cos^2 theta_h = (1 - sqrt2 a^2) / (1 - a^2);
    // mirrored about the normal, the lobe of light directions is twice as wide.
    const double a2 = m.roughness * m.roughness;
    if (std::sqrt(2.0) * a2 >= 1) return 0;  // wider than any lattice misses
    return 2 * std::acos(std::sqrt((1 - std::sqrt(2.0) * a2) / (1 - a2)));
  }
  return 0;
}

namespace {
int texelRaysForHalfWidth(double halfWidth, int cubemapResolution) {
  if (halfWidth <= 0) return 1;
  // Two samples across the lobe's half width: on a Phong sphere under constant
  // light (s = 1000, 5000) its integral is then within 4% on average, 20% at worst.
  const double rays = std::pow(2 * (2.0 / cubemapResolution) / halfWidth, 2);
  return static_cast<int>(std::clamp(std::ceil(rays), 1.0, 1024.0));
}
}  // namespace

int texelRaysForLobe(double exponent, int cubemapResolution) {
  return exponent <= 0 ? 1 : texelRaysForHalfWidth(phongHalfWidth(exponent), cubemapResolution);
}

std::vector<std::string> samplingWarnings(const Scene& scene, const PrecomputeOptions& options) {
  std::vector<std::string> warnings;
  const double spacing = 2.0 / options.cubemapResolution / std::sqrt(double(options.texelRays));
  const auto check = [&](const Material& m, const std::string& object) {
    const double halfWidth = lobeHalfWidth(m);
    if (halfWidth <= 0 || spacing <= halfWidth) return;  // two samples across the half maximum
    const std::string lobe = m.type == Material::Type::Phong
                                 ? concat("Phong exponent ", m.exponent)
                                 : concat("GGX roughness ", m.roughness);
    warnings.push_back(concat(object, ": ", lobe, " has a lobe ", 2 * halfWidth * 180 / M_PI,
                              " degrees wide at half maximum, under two direction samples across (",
                              spacing * 180 / M_PI, " degrees apart on 6x",
                              options.cubemapResolution, "x", options.cubemapResolution, " with ",
                              options.texelRays, " ray(s) per texel): its highlights alias; ",
                              texelRaysForHalfWidth(halfWidth, options.cubemapResolution),
                              " rays per texel or a larger cube map resolve it"));
  };
  for (const auto& mesh : scene.meshes) check(mesh.material, concat("mesh '", mesh.name, "'"));
  for (size_t i = 0; i < scene.spheres.size(); ++i)
    check(scene.spheres[i].material, concat("sphere ", i));
  return warnings;
}

PrecomputeStats measurePrecomputeRate(const Scene& scene, const PrecomputeOptions& options,
                                      int imageRows) {
  validateOptions(options);
  const int threads = arenaThreads(options.threads);
  tbb::task_arena arena(threads);
  PrecomputeOptions direct = options;  // the rate of the shadow rays: direct light alone
  direct.bounces = 0;
  return arena.execute([&] {
    const TransportPass pass(scene, direct);
    const CubeLattice& lattice = pass.lattice;
    const BandRenderer& renderer = pass.renderer;
    // The middle rows of the image, where the scene's detail usually is (the same
    // rows as the raw loops of ray_benchmark.cpp trace).
    const int bands = (scene.camera.size.height + kBandRows - 1) / kBandRows;
    const int want = std::clamp((imageRows + kBandRows - 1) / kBandRows, 1, bands);
    const int first = (bands - want) / 2;
    long long rows = 0;
    PrecomputeStats stats =
        runBands(renderer, first, first + want, threads, [&](const std::vector<float>& r) {
          rows += static_cast<long long>(r.size()) / lattice.size();
        });
    stats.occupiedPixels = rows;
    stats.triangles = scene.triangleCount();
    stats.degenerateTriangles = pass.embree.degenerateTriangles();
    stats.seconds = stats.transportSeconds;
    return stats;
  });
}

}  // namespace acpca
