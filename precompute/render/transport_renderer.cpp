#include "precompute/render/transport_renderer.h"

#include <tbb/parallel_pipeline.h>
#include <tbb/info.h>
#include <tbb/task_arena.h>

#include <array>
#include <bit>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include "precompute/render/embree_scene.h"
#include "precompute/transport/error.h"

namespace acpca {

namespace {

using Clock = std::chrono::steady_clock;
double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Pixels per side of a packet: one direction over 4x4 neighbouring points is
/// what Embree traces fastest (coherent rtcOccluded16).
constexpr int kBlock = 4;
constexpr int kLanes = kBlock * kBlock;

/// The shadow-ray directions of every texel: its centre when one ray per texel,
/// else `raysPerTexel` stratified points weighted by their solid-angle density
/// so that they average over the texel's area.
struct TexelDirections {
  int raysPerTexel = 1;
  std::vector<float> x, y, z, weight;  // texel j, ray k at j * raysPerTexel + k
};

TexelDirections makeTexelDirections(const CubeLattice& lattice, int raysPerTexel) {
  TexelDirections t;
  t.raysPerTexel = raysPerTexel;
  const size_t n = static_cast<size_t>(lattice.size()) * raysPerTexel;
  t.x.resize(n), t.y.resize(n), t.z.resize(n), t.weight.resize(n);
  const double step = 2.0 / lattice.resolution();
  for (int j = 0; j < lattice.size(); ++j) {
    const TexelCoord c = lattice.texelCoord(j);
    double total = 0;
    for (int k = 0; k < raysPerTexel; ++k) {
      Vec3 d;
      double density = 1;
      if (raysPerTexel == 1) {
        d = lattice.direction(j);
      } else {
        // R2 points in the texel, shifted per texel (Cranley-Patterson) so that
        // neighbouring texels do not share a pattern.
        const double shiftS = std::fmod(j * 0.6180339887498949, 1.0);
        const double shiftT = std::fmod(j * 0.4142135623730950, 1.0);
        const double u = std::fmod(shiftS + k * 0.7548776662466927, 1.0);
        const double v = std::fmod(shiftT + k * 0.5698402909980532, 1.0);
        const double sc = -1 + (c.col + u) * step, tc = -1 + (c.row + v) * step;
        const Vec3 p = CubeLattice::faceDirection(c.face, sc, tc);
        density = 1 / std::pow(p.squaredNorm(), 1.5);  // d(omega)/d(area) on the face
        d = p.normalized();
      }
      const size_t q = static_cast<size_t>(j) * raysPerTexel + k;
      t.x[q] = float(d.x()), t.y[q] = float(d.y()), t.z[q] = float(d.z());
      t.weight[q] = float(density);
      total += density;
    }
    for (int k = 0; k < raysPerTexel; ++k) t.weight[static_cast<size_t>(j) * raysPerTexel + k] /= float(total);
  }
  return t;
}

/// Computes transport rows for bands of kBlock image rows.
class BandRenderer {
 public:
  BandRenderer(const EmbreeScene& scene, const GBuffer& gbuffer, const TexelDirections& dirs,
               int latticeSize)
      : scene_(scene), gbuffer_(gbuffer), dirs_(dirs), l_(latticeSize) {}

  /// Occupied pixels of image rows [y0, y0 + kBlock), in row-major order.
  long long countRows(int y0) const {
    long long n = 0;
    for (int y = y0; y < std::min(y0 + kBlock, gbuffer_.size.height); ++y)
      for (int x = 0; x < gbuffer_.size.width; ++x) n += hits(x, y) > 0;
    return n;
  }

  /// Fills out (countRows(y0) x l, zeroed here) and returns the occlusion rays traced.
  long long render(int y0, std::vector<float>& out) const {
    const int width = gbuffer_.size.width;
    const int y1 = std::min(y0 + kBlock, gbuffer_.size.height);
    std::vector<int> rowOf(static_cast<size_t>(kBlock) * width, -1);
    int rows = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = 0; x < width; ++x)
        if (hits(x, y) > 0) rowOf[(y - y0) * width + x] = rows++;
    out.assign(static_cast<size_t>(rows) * l_, 0.0f);
    long long rays = 0;
    for (int x0 = 0; x0 < width; x0 += kBlock)
      for (int s = 0; s < gbuffer_.samplesPerPixel; ++s) {
        Packet packet;
        for (int y = y0; y < y1; ++y)
          for (int x = x0; x < std::min(x0 + kBlock, width); ++x) {
            const PixelSample& ps = gbuffer_.at(x, y, s);
            if (ps.material >= 0)
              packet.add(ps, scene_.materials()[ps.material], rowOf[(y - y0) * width + x],
                         1.0f / hits(x, y));
          }
        if (packet.lanes > 0) rays += trace(packet, out);
      }
    return rays;
  }

 private:
  /// Up to 16 pixel samples that share each shadow direction.
  struct Packet {
    int lanes = 0;
    std::array<Eigen::Vector3f, kLanes> origin, normal, mirrored;
    std::array<int, kLanes> row{};
    std::array<float, kLanes> weight{}, specular{}, exponent{};
    std::array<bool, kLanes> glossy{};

    void add(const PixelSample& ps, const Material& m, int r, float w) {
      origin[lanes] = ps.origin;
      normal[lanes] = ps.normal;
      mirrored[lanes] = 2 * ps.normal.dot(ps.toViewer) * ps.normal - ps.toViewer;
      glossy[lanes] = m.type == Material::Type::Phong && m.specular > 0;
      specular[lanes] = glossy[lanes] ? float(m.specular) : 0.0f;
      exponent[lanes] = float(m.exponent);
      row[lanes] = r;
      weight[lanes] = w;
      ++lanes;
    }
  };

  int hits(int x, int y) const {
    int n = 0;
    for (int s = 0; s < gbuffer_.samplesPerPixel; ++s) n += gbuffer_.at(x, y, s).material >= 0;
    return n;
  }

  long long trace(const Packet& p, std::vector<float>& out) const {
    constexpr float invPi = std::numbers::inv_pi_v<float>;
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    alignas(64) RTCRay16 ray;
    alignas(64) int valid[kLanes];
    const float epsilon = scene_.rayEpsilon();
    for (int i = 0; i < kLanes; ++i) {
      const int lane = std::min(i, p.lanes - 1);  // unused lanes mirror a real one
      ray.org_x[i] = p.origin[lane].x(), ray.org_y[i] = p.origin[lane].y();
      ray.org_z[i] = p.origin[lane].z();
      ray.tnear[i] = epsilon, ray.time[i] = 0, ray.mask[i] = ~0u, ray.id[i] = i, ray.flags[i] = 0;
    }
    long long rays = 0;
    float cosine[kLanes];
    const int k = dirs_.raysPerTexel;
    for (int j = 0; j < l_; ++j)
      for (int r = 0; r < k; ++r) {
        const size_t q = static_cast<size_t>(j) * k + r;
        const float dx = dirs_.x[q], dy = dirs_.y[q], dz = dirs_.z[q];
        int active = 0;
        for (int i = 0; i < kLanes; ++i) {
          cosine[i] = i < p.lanes ? p.normal[i].x() * dx + p.normal[i].y() * dy + p.normal[i].z() * dz
                                  : 0.0f;
          valid[i] = cosine[i] > 0 ? -1 : 0;  // below the horizon: zero, no ray
          active += cosine[i] > 0;
        }
        if (active == 0) continue;
        for (int i = 0; i < kLanes; ++i) {
          ray.dir_x[i] = dx, ray.dir_y[i] = dy, ray.dir_z[i] = dz;
          ray.tfar[i] = std::numeric_limits<float>::infinity();
        }
        rtcOccluded16(valid, scene_.handle(), &context, &ray);
        rays += active;
        for (int i = 0; i < p.lanes; ++i) {
          if (!valid[i] || ray.tfar[i] < 0) continue;  // occluded rays come back with tfar = -inf
          float shape = invPi;
          if (p.glossy[i]) {  // Phong of design.md section 4, divided by the albedo
            const float c = p.mirrored[i].x() * dx + p.mirrored[i].y() * dy + p.mirrored[i].z() * dz;
            const float lobe = c > 0 ? std::pow(c, p.exponent[i]) : 0.0f;
            shape = (1 - p.specular[i]) * invPi +
                    p.specular[i] * (p.exponent[i] + 2) * 0.5f * invPi * lobe;
          }
          out[static_cast<size_t>(p.row[i]) * l_ + j] += p.weight[i] * dirs_.weight[q] * cosine[i] * shape;
        }
      }
    return rays;
  }

  const EmbreeScene& scene_;
  const GBuffer& gbuffer_;
  const TexelDirections& dirs_;
  int l_;
};

void validateOptions(const PrecomputeOptions& o) {
  if (o.cubemapResolution < 1 || o.cubemapResolution > 256)
    throw UserError(concat("--cubemap ", o.cubemapResolution, " is out of range 1..256"));
  if (o.samplesPerPixel < 1 || o.samplesPerPixel > 256)
    throw UserError(concat("--spp ", o.samplesPerPixel, " is out of range 1..256"));
  if (o.texelRays < 1 || o.texelRays > 1024)
    throw UserError(concat("--texel-rays ", o.texelRays, " is out of range 1..1024"));
  if (o.threads < 0) throw UserError(concat("--threads ", o.threads, " must be >= 0"));
}

int arenaThreads(int threads) {
  return threads > 0 ? threads : tbb::info::default_concurrency();
}

/// Runs the band pipeline over image rows [firstBand, lastBand) * kBlock: bands are
/// computed in parallel and handed to `sink` in order (so output is identical for
/// any thread count).
template <typename Sink>
PrecomputeStats runBands(const BandRenderer& renderer, int firstBand, int lastBand, int threads,
                         Sink&& sink) {
  struct Slot {
    int y0 = 0;
    long long rays = 0;
    std::vector<float> rows;
  };
  const int tokens = 2 * threads;
  std::vector<Slot> slots(tokens);
  std::atomic<unsigned long long> threadMask{0};
  std::atomic<long long> rays{0};
  int next = firstBand;
  const auto start = Clock::now();
  tbb::parallel_pipeline(
      tokens,
      tbb::make_filter<void, Slot*>(tbb::filter_mode::serial_in_order,
                                    [&](tbb::flow_control& fc) -> Slot* {
                                      if (next >= lastBand) {
                                        fc.stop();
                                        return nullptr;
                                      }
                                      Slot* slot = &slots[(next - firstBand) % tokens];
                                      slot->y0 = kBlock * next++;
                                      return slot;
                                    }) &
          tbb::make_filter<Slot*, Slot*>(tbb::filter_mode::parallel,
                                         [&](Slot* slot) {
                                           const int t = tbb::this_task_arena::current_thread_index();
                                           threadMask |= 1ull << (t & 63);
                                           slot->rays = renderer.render(slot->y0, slot->rows);
                                           rays += slot->rays;
                                           return slot;
                                         }) &
          tbb::make_filter<Slot*, void>(tbb::filter_mode::serial_in_order,
                                        [&](Slot* slot) { sink(slot->rows); }));
  PrecomputeStats stats;
  stats.transportSeconds = secondsSince(start);
  stats.occlusionRays = rays;
  stats.threadsUsed = std::popcount(threadMask.load());
  return stats;
}

}  // namespace

PrecomputeStats precomputeTransport(const Scene& scene, const std::string& outPath,
                                    const PrecomputeOptions& options) {
  validateOptions(options);
  const auto start = Clock::now();
  const int threads = arenaThreads(options.threads);
  tbb::task_arena arena(threads);
  return arena.execute([&] {
    const CubeLattice lattice(options.cubemapResolution);
    const EmbreeScene embree(scene);
    const GBuffer gbuffer = renderGBuffer(embree, scene.camera, options.samplesPerPixel);

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
          albedo += embree.materials()[ps.material].albedo;
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
    const TexelDirections dirs = makeTexelDirections(lattice, options.texelRays);
    const BandRenderer renderer(embree, gbuffer, dirs, lattice.size());
    long long written = 0;
    const int bands = (size.height + kBlock - 1) / kBlock;
    PrecomputeStats stats = runBands(renderer, 0, bands, threads, [&](const std::vector<float>& rows) {
      const long long count = static_cast<long long>(rows.size()) / lattice.size();
      writer.writeRows(written, count, rows.data());
      written += count;
      if (options.progress) options.progress(written, header.rows());
    });
    writer.finish();
    stats.triangles = scene.triangleCount();
    stats.occupiedPixels = header.rows();
    stats.bytesWritten = writer.bytesWritten();
    stats.seconds = secondsSince(start);
    return stats;
  });
}

PrecomputeStats measurePrecomputeRate(const Scene& scene, const PrecomputeOptions& options,
                                      int imageRows) {
  validateOptions(options);
  const int threads = arenaThreads(options.threads);
  tbb::task_arena arena(threads);
  return arena.execute([&] {
    const CubeLattice lattice(options.cubemapResolution);
    const EmbreeScene embree(scene);
    const GBuffer gbuffer = renderGBuffer(embree, scene.camera, options.samplesPerPixel);
    const TexelDirections dirs = makeTexelDirections(lattice, options.texelRays);
    const BandRenderer renderer(embree, gbuffer, dirs, lattice.size());
    // The middle rows of the image, where the scene's detail usually is.
    const int bands = (scene.camera.size.height + kBlock - 1) / kBlock;
    const int want = std::clamp((imageRows + kBlock - 1) / kBlock, 1, bands);
    const int first = (bands - want) / 2;
    long long rows = 0;
    PrecomputeStats stats = runBands(renderer, first, first + want, threads,
                                     [&](const std::vector<float>& r) {
                                       rows += static_cast<long long>(r.size()) / lattice.size();
                                     });
    stats.occupiedPixels = rows;
    stats.triangles = scene.triangleCount();
    stats.seconds = stats.transportSeconds;
    return stats;
  });
}

}  // namespace acpca
