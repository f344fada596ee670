#include "precompute/render/transport_renderer.h"

#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.h"
#include "core/ordered_pipeline.h"
#include "core/stopwatch.h"
#include "precompute/render/embree_scene.h"
#include "precompute/render/sample_patterns.h"

namespace acpca {

namespace {

/// Image rows per band: the unit of parallel work and of ordered writing.
constexpr int kBandRows = 1;

/// Computes transport rows for bands of kBandRows image rows. Shadow rays go
/// out as rtcOccluded16 packets of a 4x4 block of neighbouring texels from one
/// point: the fastest of the layouts `bench rays` measures on our scenes.
class BandRenderer {
 public:
  BandRenderer(const EmbreeScene& scene, const GBuffer& gbuffer, const TexelDirections& dirs,
               const CubeLattice& lattice, Antialiasing mode)
      : scene_(scene),
        gbuffer_(gbuffer),
        mode_(mode),
        dirs_(dirs),
        blocks_(texelBlocks(lattice)),
        l_(lattice.size()) {
    // A cone around each block's directions, to skip blocks wholly below a
    // point's horizon with one dot product.
    for (const auto& block : blocks_) {
      Eigen::Vector3f centre = Eigen::Vector3f::Zero();
      forEachDirection(block, [&](const Eigen::Vector3f& d) { centre += d; });
      centre.normalize();
      float minCos = 1;
      forEachDirection(block,
                       [&](const Eigen::Vector3f& d) { minCos = std::min(minCos, centre.dot(d)); });
      const float sinSpread = std::sqrt(std::max(0.0f, 1 - minCos * minCos)) + 1e-4f;
      cones_.push_back({centre, minCos < 0 ? 2.0f : sinSpread});
    }
  }

  /// Fills out (one row per occupied pixel of image rows [y0, y0 + kBandRows), in
  /// row-major order) and returns the occlusion rays traced.
  long long render(int y0, std::vector<float>& out, long long& supersampled) const {
    const int width = gbuffer_.size.width;
    const int y1 = std::min(y0 + kBandRows, gbuffer_.size.height);
    int rows = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < width; ++x) rows += hits(x, y) > 0;
    out.assign(static_cast<size_t>(rows) * l_, 0.0f);
    long long rays = 0;
    int row = 0;
    std::vector<float> weights;
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < width; ++x) {
        if (hits(x, y) == 0) continue;
        sampleWeights(gbuffer_, x, y, mode_, weights);
        supersampled +=
            std::count_if(weights.begin() + 1, weights.end(), [](float w) { return w > 0; }) > 0;
        for (int s = 0; s < gbuffer_.samplesPerPixel; ++s) {
          const PixelSample& ps = gbuffer_.at(x, y, s);
          if (weights[s] > 0)
            rays += trace(ps, scene_.materials()[ps.material], weights[s],
                          out.data() + static_cast<size_t>(row) * l_);
        }
        ++row;
      }
    return rays;
  }

 private:
  int hits(int x, int y) const {
    int n = 0;
    for (int s = 0; s < gbuffer_.samplesPerPixel; ++s) n += gbuffer_.at(x, y, s).material >= 0;
    return n;
  }

  /// Adds weight x V x cos x (f / albedo) of one pixel sample to its row.
  long long trace(const PixelSample& ps, const Material& m, float weight, float* row) const {
    constexpr float invPi = std::numbers::inv_pi_v<float>;
    const Eigen::Vector3f n = ps.normal, ng = ps.geometricNormal;
    const bool flat = n == ng;  // one horizon to test
    const Eigen::Vector3f mirrored = 2 * n.dot(ps.toViewer) * n - ps.toViewer;
    const bool glossy = m.type == Material::Type::Phong && m.specular > 0;
    const bool ggx = m.type == Material::Type::Ggx && m.specular > 0;
    const float ks = float(m.specular), s = float(m.exponent), alpha = float(m.roughness);
    const Eigen::Vector3f v = ps.toViewer;
    const float cosO = n.dot(v);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) RTCRay16 ray;
    alignas(64) int valid[16];
    for (int i = 0; i < 16; ++i) {
      ray.org_x[i] = ps.origin.x(), ray.org_y[i] = ps.origin.y(), ray.org_z[i] = ps.origin.z();
      ray.tnear[i] = scene_.rayEpsilon(), ray.time[i] = 0, ray.mask[i] = ~0u;
      ray.id[i] = i, ray.flags[i] = 0;
    }
    long long rays = 0;
    float cosine[16];
    size_t slot[16];
    const int k = dirs_.raysPerTexel;
    for (size_t b = 0; b < blocks_.size(); ++b) {
      // All of the block is below the horizon when n is more than 90 degrees
      // plus the block's spread away from its axis.
      if (n.dot(cones_[b].axis) < -cones_[b].sinSpread) continue;
      const auto& block = blocks_[b];
      for (int r = 0; r < k; ++r) {
        int active = 0;
        for (int i = 0; i < 16; ++i) {
          const int j = block[i] >= 0 ? block[i] : block[0];
          const size_t q = static_cast<size_t>(j) * k + r;
          slot[i] = q;
          cosine[i] = n.x() * dirs_.x[q] + n.y() * dirs_.y[q] + n.z() * dirs_.z[q];
          // Light must arrive above the shading horizon (the cosine) and above
          // the true surface: from below the geometric horizon the surface
          // itself is in the way (docs/scenes.md, "Shading normals").
          const bool above =
              cosine[i] > 0 &&
              (flat || ng.x() * dirs_.x[q] + ng.y() * dirs_.y[q] + ng.z() * dirs_.z[q] > 0);
          valid[i] = block[i] >= 0 && above ? -1 : 0;
          active += valid[i] != 0;
        }
        if (active == 0) continue;
        for (int i = 0; i < 16; ++i) {
          ray.dir_x[i] = dirs_.x[slot[i]], ray.dir_y[i] = dirs_.y[slot[i]];
          ray.dir_z[i] = dirs_.z[slot[i]];
          ray.tfar[i] = std::numeric_limits<float>::infinity();
        }
        rtcOccluded16(valid, scene_.handle(), &context, &ray);
        rays += active;
        for (int i = 0; i < 16; ++i) {
          if (!valid[i] || ray.tfar[i] < 0) continue;  // occluded rays come back with tfar = -inf
          const size_t q = slot[i];
          float shape = invPi;
          if (glossy) {  // Phong of design.md section 4, divided by the albedo
            const float c =
                mirrored.x() * dirs_.x[q] + mirrored.y() * dirs_.y[q] + mirrored.z() * dirs_.z[q];
            shape =
                (1 - ks) * invPi + ks * (s + 2) * 0.5f * invPi * (c > 0 ? std::pow(c, s) : 0.0f);
          } else if (ggx) {  // microfacet GGX without Fresnel, divided by the albedo
            const Eigen::Vector3f h =
                (Eigen::Vector3f(dirs_.x[q], dirs_.y[q], dirs_.z[q]) + v).normalized();
            shape = (1 - ks) * invPi + ks * ggxSpecular(cosine[i], cosO, n.dot(h), alpha);
          }
          row[block[i]] += weight * dirs_.weight[q] * cosine[i] * shape;
        }
      }
    }
    return rays;
  }

  template <typename F>
  void forEachDirection(const std::array<int, 16>& block, F&& f) const {
    for (int j : block)
      if (j >= 0)
        for (int r = 0; r < dirs_.raysPerTexel; ++r) {
          const size_t q = static_cast<size_t>(j) * dirs_.raysPerTexel + r;
          f(Eigen::Vector3f(dirs_.x[q], dirs_.y[q], dirs_.z[q]));
        }
  }

  struct Cone {
    Eigen::Vector3f axis;
    float sinSpread;  ///< every direction d of the block has d.axis >= cos(spread)
  };

  const EmbreeScene& scene_;
  const GBuffer& gbuffer_;
  const Antialiasing mode_;
  const TexelDirections& dirs_;
  std::vector<std::array<int, 16>> blocks_;
  std::vector<Cone> cones_;
  int l_;
};

void validateOptions(const PrecomputeOptions& o) {
  if (o.cubemapResolution < 1 || o.cubemapResolution > 256)
    throw ParameterError("cube-map resolution", o.cubemapResolution, "is out of range 1..256");
  if (o.samplesPerPixel < 1 || o.samplesPerPixel > 256)
    throw ParameterError("samples per pixel", o.samplesPerPixel, "is out of range 1..256");
  if (o.texelRays < 1 || o.texelRays > 1024)
    throw ParameterError("rays per texel", o.texelRays, "is out of range 1..1024");
  if (o.threads < 0) throw ParameterError("threads", o.threads, "must be >= 0");
}

int arenaThreads(int threads) {
  return threads > 0 ? threads : tbb::info::default_concurrency();
}

/// Runs the band pipeline over image rows [firstBand, lastBand) * kBandRows: bands are
/// computed in parallel and handed to `sink` in order (so output is identical for
/// any thread count).
template <typename Sink>
PrecomputeStats runBands(const BandRenderer& renderer, int firstBand, int lastBand, int threads,
                         Sink&& sink) {
  struct Slot {
    int y0 = 0;
    long long rays = 0, supersampled = 0;
    std::vector<float> rows;
  };
  std::atomic<unsigned long long> threadMask{0};
  std::atomic<long long> rays{0}, supersampled{0};
  int next = firstBand;
  const Stopwatch watch;
  runOrderedPipeline<Slot>(
      2 * threads,
      [&](Slot& slot) {
        if (next >= lastBand) return false;
        slot.y0 = kBandRows * next++;
        return true;
      },
      [&](Slot& slot) {
        threadMask |= 1ull << (tbb::this_task_arena::current_thread_index() & 63);
        slot.supersampled = 0;
        slot.rays = renderer.render(slot.y0, slot.rows, slot.supersampled);
        rays += slot.rays;
        supersampled += slot.supersampled;
      },
      [&](Slot& slot) { sink(slot.rows); });
  PrecomputeStats stats;
  stats.transportSeconds = watch.seconds();
  stats.occlusionRays = rays;
  stats.supersampledPixels = supersampled;
  stats.threadsUsed = std::popcount(threadMask.load());
  return stats;
}

/// Everything a transport pass over a scene needs, built once inside the arena.
struct TransportPass {
  TransportPass(const Scene& scene, const PrecomputeOptions& options)
      : lattice(options.cubemapResolution),
        embree(scene),
        gbuffer(renderGBuffer(embree, scene.camera, options.samplesPerPixel)),
        dirs(makeTexelDirections(lattice, options.texelRays)),
        renderer(embree, gbuffer, dirs, lattice, options.antialiasing) {}
  const CubeLattice lattice;
  const EmbreeScene embree;
  const GBuffer gbuffer;
  const TexelDirections dirs;
  const BandRenderer renderer;
};

}  // namespace

PrecomputeStats precomputeTransport(const Scene& scene, const std::string& outPath,
                                    const PrecomputeOptions& options) {
  validateOptions(options);
  const Stopwatch watch;
  const int threads = arenaThreads(options.threads);
  tbb::task_arena arena(threads);
  return arena.execute([&] {
    const TransportPass pass(scene, options);
    const CubeLattice& lattice = pass.lattice;
    const EmbreeScene& embree = pass.embree;
    const GBuffer& gbuffer = pass.gbuffer;

    // Per-pixel data of the occupied pixels, in row-major order.
    TransportHeader header;
    header.camera = scene.camera;
    header.cubemapResolution = options.cubemapResolution;
    header.samplesPerPixel = options.samplesPerPixel;
    header.texelRays = options.texelRays;
    header.precision = options.precision;
    header.scene = scene.name;
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

    TransportWriter writer(outPath, header);
    const BandRenderer& renderer = pass.renderer;
    long long written = 0;
    const int bands = (size.height + kBandRows - 1) / kBandRows;
    PrecomputeStats stats =
        runBands(renderer, 0, bands, threads, [&](const std::vector<float>& rows) {
          const long long count = static_cast<long long>(rows.size()) / lattice.size();
          writer.writeRows(written, count, rows.data());
          written += count;
          if (options.progress) options.progress(written, header.rows());
        });
    writer.finish();
    stats.triangles = scene.triangleCount();
    stats.degenerateTriangles = embree.degenerateTriangles();
    stats.occupiedPixels = header.rows();
    stats.bytesWritten = writer.bytesWritten();
    stats.seconds = watch.seconds();
    return stats;
  });
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
    warnings.push_back(concat(
        object, ": ", lobe, " has a lobe ", 2 * halfWidth * 180 / M_PI,
        " degrees wide at half maximum, under two direction samples across (", spacing * 180 / M_PI,
        " degrees apart on 6x", options.cubemapResolution, "x", options.cubemapResolution, " with ",
        options.texelRays, " ray(s) per texel): its highlights alias; --texel-rays ",
        texelRaysForHalfWidth(halfWidth, options.cubemapResolution),
        " or a larger --cubemap resolves it"));
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
  return arena.execute([&] {
    const TransportPass pass(scene, options);
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
