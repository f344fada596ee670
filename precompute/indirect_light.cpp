#include "precompute/indirect_light.h"

#include <tbb/parallel_for.h>

#include <atomic>
#include <bit>
#include <cmath>
#include <numbers>
#include <numeric>

#include "core/error.h"
#include "core/random_bits.h"

namespace acpca {

namespace {

constexpr float kPi = std::numbers::pi_v<float>;

/// Path i's point of the R2 sequence in the unit square, shifted by a random
/// offset per camera sample and bounce (Cranley-Patterson), so that the paths
/// of one sample are stratified and no two samples share a pattern.
Eigen::Vector2d stratifiedPoint(int i, std::uint64_t seed, int bounce) {
  const std::uint64_t h = splitMix(seed * 0x2545f4914f6cdd1dull + std::uint64_t(bounce) + 1);
  const double shiftU = unitFromBits(h), shiftV = unitFromBits(splitMix(h));
  return {std::fmod(shiftU + (i + 0.5) * 0.7548776662466927, 1.0),
          std::fmod(shiftV + (i + 0.5) * 0.5698402909980532, 1.0)};
}

/// A direction with density cos/pi about n (Malley's method: a uniform point
/// on the disc lifted onto the hemisphere).
Eigen::Vector3f cosineDirection(const Eigen::Vector3f& n, const Eigen::Vector2d& u) {
  // An orthonormal frame without branches on n (Duff et al. 2017).
  const float sign = std::copysign(1.0f, n.z());
  const float a = -1.0f / (sign + n.z()), b = n.x() * n.y() * a;
  const Eigen::Vector3f t(1 + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
  const Eigen::Vector3f s(b, sign + n.y() * n.y() * a, -n.y());
  const double r = std::sqrt(u.x()), phi = 2 * std::numbers::pi * u.y();
  const float x = float(r * std::cos(phi)), y = float(r * std::sin(phi));
  const float z = float(std::sqrt(std::max(0.0, 1 - u.x())));
  return (x * t + y * s + z * n).normalized();
}

/// Which of 24 direction cells a unit vector falls in (a cube map of 2 x 2
/// texels per face), so that the two faces of a thin surface never share.
int normalBucket(const Eigen::Vector3f& n) {
  int axis = 0;
  if (std::abs(n.y()) > std::abs(n[axis])) axis = 1;
  if (std::abs(n.z()) > std::abs(n[axis])) axis = 2;
  const int face = 2 * axis + (n[axis] < 0);
  const float u = n[(axis + 1) % 3], v = n[(axis + 2) % 3];
  return 4 * face + 2 * (u >= 0) + (v >= 0);
}

bool isGrey(const Eigen::Vector3f& c) {
  return c.x() == c.y() && c.y() == c.z();
}

/// Shadow rays of cached points reach this far below their own horizon, so that
/// a neighbour whose normal leans (a curved surface within one cell) still
/// finds its directions traced.
constexpr float kCacheHorizonCos = -0.5f;

}  // namespace

bool sceneIsGrey(const Scene& scene) {
  const auto greyTexture = [](const Texture* t) {
    if (!t) return true;
    for (int y = 0; y < t->height(); ++y)
      for (int x = 0; x < t->width(); ++x)
        if (!isGrey(t->texel(x, y))) return false;
    return true;
  };
  for (const auto& mesh : scene.meshes)
    if (!isGrey(mesh.material.albedo) || !greyTexture(mesh.albedoTexture.get())) return false;
  for (const auto& sphere : scene.spheres)
    if (!isGrey(sphere.material.albedo)) return false;
  return true;
}

IndirectLight::IndirectLight(const EmbreeScene& scene, const ShadowRays& shadows, int latticeSize,
                             const Scene& source, const IndirectSettings& settings)
    : scene_(scene), shadows_(shadows), l_(latticeSize), settings_(settings) {
  const Eigen::AlignedBox3d box = source.bounds();
  lo_ = box.isEmpty() ? Eigen::Vector3f::Zero() : Eigen::Vector3f(box.min().cast<float>());
  // 2^19 cells per axis at most: the key packs three 19-bit cell indices.
  cell_ = float(std::max(settings.cacheCell * source.extent(), source.extent() / (1 << 19)));
  words_ = (l_ * shadows.directions().raysPerTexel + 63) / 64;
}

std::uint64_t IndirectLight::cellKey(const PathVertex& v) const {
  std::uint64_t key = std::uint64_t(normalBucket(v.geometricNormal));
  for (int a = 0; a < 3; ++a) {
    const float c = std::floor((v.origin[a] - lo_[a]) / cell_);
    key = key << 19 | std::uint64_t(std::clamp(c, 0.0f, float((1 << 19) - 1)));
  }
  return key;
}

/// Walks the paths of one camera sample: path i leaves the sample's surface in
/// a cosine-distributed direction about its shading normal, and each surface it
/// reaches, up to the bounce count, is visited with the path's throughput so
/// far, beta (the product, over the vertices before it, of f cos / pdf, divided
/// by the pixel's own albedo). Returns the closest-hit rays traced.
template <typename Visit>
long long IndirectLight::walk(const PixelSample& ps, std::uint64_t seed, Visit&& visit) const {
  const auto& materials = scene_.materials();
  // Each bounce's directions are one stratified set, dealt to the paths in a
  // random order per bounce: with the same order at every bounce, a path's
  // second direction would be its first shifted by a constant, and the noise
  // of the second bounce would not fall as paths are added.
  const int samples = settings_.samples;
  std::vector<int> order(static_cast<size_t>(samples) * settings_.bounces);
  for (int bounce = 1; bounce <= settings_.bounces; ++bounce) {
    int* perm = order.data() + static_cast<size_t>(bounce - 1) * samples;
    std::iota(perm, perm + samples, 0);
    std::uint64_t state = splitMix(seed ^ (0x6a09e667f3bcc909ull * std::uint64_t(bounce)));
    for (int i = samples - 1; bounce > 1 && i > 0; --i) {
      state = splitMix(state);
      std::swap(perm[i], perm[static_cast<int>(state % std::uint64_t(i + 1))]);
    }
  }
  long long rays = 0;
  for (int i = 0; i < samples; ++i) {
    PathVertex at{ps.origin,   ps.normal, ps.geometricNormal, ps.tangent,
                  ps.toViewer, ps.albedo, ps.material};
    Eigen::Array3f beta = Eigen::Array3f::Ones();
    bool first = true;
    for (int bounce = 1; bounce <= settings_.bounces; ++bounce) {
      const int stratum = order[static_cast<size_t>(bounce - 1) * samples + i];
      const Eigen::Vector3f d = cosineDirection(at.normal, stratifiedPoint(stratum, seed, bounce));
      // From below the true surface the surface itself is in the way.
      if (d.dot(at.geometricNormal) <= 0) break;
      const Material& m = materials[at.material];
      const LobeShape shape(m, at.normal, at.tangent, at.toViewer);
      // f cos / (cos / pi) = pi f: the albedo, times pi shape where not diffuse;
      // the pixel's own albedo is left out (rows are divided by it).
      const float lobe =
          shape.constant() ? 1.0f : kPi * shape(d.x(), d.y(), d.z(), d.dot(at.normal));
      beta *= lobe;
      if (!first) beta *= at.albedo.array();
      first = false;
      ++rays;
      const EmbreeScene::Hit hit = scene_.intersect(at.origin.cast<double>(), d.cast<double>());
      if (hit.material < 0) break;  // it left the scene: direct light, counted already
      at.origin = (hit.position + double(scene_.rayEpsilon()) * hit.normal).cast<float>();
      at.normal = hit.shadingNormal.cast<float>();
      at.geometricNormal = hit.normal.cast<float>();
      at.tangent = hit.tangent.cast<float>();
      at.toViewer = -d;
      at.albedo = hit.albedo;
      at.material = hit.material;
      visit(at, beta);
    }
  }
  return rays;
}

void IndirectLight::collectCells(const PixelSample& ps, std::uint64_t seed,
                                 std::unordered_map<std::uint64_t, PathVertex>& firstInBand,
                                 std::vector<std::uint64_t>& order) const {
  walk(ps, seed, [&](const PathVertex& v, const Eigen::Array3f&) {
    const std::uint64_t key = cellKey(v);
    if (firstInBand.emplace(key, v).second) order.push_back(key);
  });
}

void IndirectLight::mergeCells(const std::unordered_map<std::uint64_t, PathVertex>& band,
                               const std::vector<std::uint64_t>& order) {
  for (std::uint64_t key : order)
    if (cellIndex_.emplace(key, static_cast<std::int64_t>(cellVertex_.size())).second)
      cellVertex_.push_back(band.at(key));
}

long long IndirectLight::fillCache(const std::function<void(long long, long long)>& progress) {
  visibility_.assign(cellVertex_.size() * words_, 0);
  std::atomic<long long> rays{0};
  const std::size_t points = cellVertex_.size(), batch = 4096;
  // Batches in turn, each in parallel, so that progress is reported from here.
  for (std::size_t first = 0; first < points; first += batch) {
    tbb::parallel_for(first, std::min(points, first + batch), [&](std::size_t c) {
      const PathVertex& v = cellVertex_[c];
      std::uint64_t* bits = visibility_.data() + c * words_;
      rays += shadows_.trace(v.origin, v.geometricNormal, v.geometricNormal, kCacheHorizonCos,
                             [&](int, std::size_t q, float) { bits[q >> 6] |= 1ull << (q & 63); });
    });
    if (progress) progress(static_cast<long long>(std::min(points, first + batch)), points);
  }
  return rays;
}

IndirectLight::Rays IndirectLight::add(const PixelSample& ps, std::uint64_t seed, float weight,
                                       float* row) const {
  Rays rays;
  const float share = weight / float(settings_.samples);
  rays.paths = walk(ps, seed, [&](const PathVertex& v, const Eigen::Array3f& beta) {
    const Eigen::Array3f b = share * beta * v.albedo.array();
    if (settings_.cacheCell > 0) {
      const auto found = cellIndex_.find(cellKey(v));
      if (found != cellIndex_.end()) {
        gatherCached(visibility_.data() + found->second * words_, v, b, row);
        return;
      }
    }
    rays.shadow += gatherExact(v, b, row);
  });
  return rays;
}

long long IndirectLight::gatherExact(const PathVertex& v, const Eigen::Array3f& beta,
                                     float* row) const {
  const LobeShape shape(scene_.materials()[v.material], v.normal, v.tangent, v.toViewer);
  const TexelDirections& dirs = shadows_.directions();
  const int channels = settings_.channels;
  return shadows_.trace(
      v.origin, v.normal, v.geometricNormal, 0.0f, [&](int j, std::size_t q, float cosine) {
        const float value =
            dirs.weight[q] * cosine * shape(dirs.x[q], dirs.y[q], dirs.z[q], cosine);
        for (int c = 0; c < channels; ++c) row[c * l_ + j] += beta[c] * value;
      });
}

/// The exact gather with the cell's visibility in place of the vertex's own:
/// its cosines, horizons and lobe are the vertex's.
void IndirectLight::gatherCached(const std::uint64_t* bits, const PathVertex& v,
                                 const Eigen::Array3f& beta, float* row) const {
  const LobeShape shape(scene_.materials()[v.material], v.normal, v.tangent, v.toViewer);
  const TexelDirections& dirs = shadows_.directions();
  const int k = dirs.raysPerTexel, channels = settings_.channels;
  const Eigen::Vector3f n = v.normal, ng = v.geometricNormal;
  const float invPi = std::numbers::inv_pi_v<float>;
  const int rays = l_ * k;
  alignas(64) float value[64];
  for (int w = 0; w < words_; ++w) {
    const std::uint64_t word = bits[w];
    if (word == 0) continue;
    const int q0 = 64 * w, count = std::min(64, rays - q0);
    // Branch-free over the word's 64 rays, so that the compiler vectorizes it.
    for (int i = 0; i < count; ++i) {
      const int q = q0 + i;
      const float dx = dirs.x[q], dy = dirs.y[q], dz = dirs.z[q];
      const float cosine = n.x() * dx + n.y() * dy + n.z() * dz;
      const float cosG = ng.x() * dx + ng.y() * dy + ng.z() * dz;
      const bool lit = ((word >> i) & 1) != 0 && cosine > 0 && cosG > 0;
      value[i] = lit ? dirs.weight[q] * cosine : 0.0f;
    }
    if (!shape.constant())
      for (int i = 0; i < count; ++i)
        if (value[i] > 0) {
          const int q = q0 + i;
          value[i] *= shape(dirs.x[q], dirs.y[q], dirs.z[q],
                            n.x() * dirs.x[q] + n.y() * dirs.y[q] + n.z() * dirs.z[q]);
        }
    const float scale = shape.constant() ? invPi : 1.0f;
    for (int c = 0; c < channels; ++c) {
      const float b = beta[c] * scale;
      float* out = row + c * l_;
      if (k == 1) {
        for (int i = 0; i < count; ++i) out[q0 + i] += b * value[i];
      } else {
        for (int i = 0; i < count; ++i) out[(q0 + i) / k] += b * value[i];
      }
    }
  }
}

}  // namespace acpca
