#include "relight/sphere_lamp.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.h"
#include "core/random_bits.h"
#include "relight/shadow_ray_batch.h"

namespace acpca {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kTile = 3;                // probes interleave over 3x3 pixels
constexpr int kProbes = kTile * kTile;  // so a neighbourhood's cover the disc
constexpr std::int8_t kNoProbe = -1, kProbeBlocked = 0, kProbeReached = 1;

/// cos t and sin t for |t| <= pi/4, by their series to t^10 and t^11: within
/// 2e-9, and no libm call (those were a tenth of a sun's frame).
Eigen::Vector2d cosSinWithinQuarter(double t) {
  const double t2 = t * t;
  const double c =
      1 + t2 * (-1.0 / 2 + t2 * (1.0 / 24 + t2 * (-1.0 / 720 + t2 * (1.0 / 40320 - t2 / 3628800))));
  const double s =
      t * (1 + t2 * (-1.0 / 6 +
                     t2 * (1.0 / 120 + t2 * (-1.0 / 5040 + t2 * (1.0 / 362880 - t2 / 39916800)))));
  return {c, s};
}

/// The concentric map of the unit square onto the unit disc [Shirley97]:
/// area-preserving, and square cells stay compact on the disc. Its angle is
/// pi/4 (y/x) where |x| > |y|, else pi/2 - pi/4 (x/y), whose cosine and sine
/// are the sine and cosine of pi/4 (x/y).
Eigen::Vector2d concentricDisc(double a, double b) {
  const double x = 2 * a - 1, y = 2 * b - 1;
  if (x == 0 && y == 0) return {0, 0};
  if (std::abs(x) > std::abs(y)) return x * cosSinWithinQuarter(kPi / 4 * (y / x));
  const Eigen::Vector2d cs = cosSinWithinQuarter(kPi / 4 * (x / y));
  return {y * cs.y(), y * cs.x()};
}

/// The probes' disc points: the centre and eight on the rim (just inside,
/// off the tangent), so that an edge across the disc leaves out at most the
/// sliver between two rim points (1.2% of the disc).
const std::array<Eigen::Vector2d, kProbes>& probePoints() {
  static const auto points = [] {
    std::array<Eigen::Vector2d, kProbes> p;
    p[0] = {0, 0};
    for (int k = 1; k < kProbes; ++k)
      p[k] = 0.98 * Eigen::Vector2d(std::cos(k * kPi / 4), std::sin(k * kPi / 4));
    return p;
  }();
  return points;
}

/// The side n of `rays` = n x n strata; checked a square.
int strataSide(int rays) {
  const int side = static_cast<int>(std::lround(std::sqrt(double(rays))));
  ACPCA_CHECK(side >= 1 && side * side == rays, "sphere lamp rays ", rays, " is not a square");
  return side;
}

/// A sample's stratum i of n x n disc points: a point in cell i of an n x n
/// grid of the square, jittered by the sample's own seed, mapped onto the
/// disc. Jittered anew for each sample, each sample's sum is an unbiased
/// estimate (one fixed pattern, merely turned, is not: its radii are off
/// uniform by up to a cell, which widened a 16-ray penumbra by 7%).
Eigen::Vector2d stratumPoint(int i, int side, std::uint64_t seed) {
  const std::uint64_t h = splitMix(seed * 0x9e3779b97f4a7c15ull + static_cast<std::uint64_t>(i));
  return concentricDisc((i % side + unitFromBits(h)) / side,
                        (i / side + unitFromBits(splitMix(h))) / side);
}

/// A sphere seen from a point: the cap of directions to it.
struct SphereCap {
  Vec3 axis, u, v;  ///< towards the centre; two unit vectors across
  double distance = 0, radius = 0, sinAlpha = 0;
  double oneMinusCos = 0;  ///< 1 - cos(alpha), kept exact for small caps

  double solidAngle() const { return 2 * kPi * oneMinusCos; }
  /// Whether the whole cap lies above the plane of unit normal n.
  bool above(const Vec3& n) const { return n.dot(axis) >= sinAlpha; }
  /// Whether none of it lies above that plane: the cap's highest direction
  /// there is cos(theta + alpha) for theta the axis's angle from n.
  bool below(const Vec3& n) const { return n.dot(axis) <= -sinAlpha; }
  /// The direction to disc point p (|p| <= 1), uniform in solid angle over
  /// the cap: 1 - cos(theta) = |p|^2 (1 - cos(alpha)).
  Vec3 direction(const Eigen::Vector2d& p) const {
    const double rho2 = p.squaredNorm();
    if (rho2 == 0) return axis;
    const double k = rho2 * oneMinusCos;
    const double across = std::sqrt(std::max(0.0, k * (2 - k)) / rho2);
    return (1 - k) * axis + across * (p.x() * u + p.y() * v);
  }
  /// Where a ray along w (a direction of the cap) meets the near surface;
  /// infinity for a distant disc.
  double reach(const Vec3& w) const {
    if (std::isinf(distance)) return distance;
    const double along = w.dot(axis) * distance;
    return along - std::sqrt(std::max(0.0, along * along - distance * distance + radius * radius));
  }
};

/// False when the point lies inside or on the sphere.
bool capOf(const CapLamp& lamp, const Vec3& point, SphereCap& cap) {
  if (lamp.atInfinity) {
    cap.axis = lamp.centre;
    cap.distance = std::numeric_limits<double>::infinity();
    cap.radius = lamp.radius;
    cap.sinAlpha = std::sin(lamp.radius);
    const double half = std::sin(0.5 * lamp.radius);
    cap.oneMinusCos = 2 * half * half;
  } else {
    const Vec3 toCentre = lamp.centre - point;
    cap.radius = lamp.radius;
    cap.distance = toCentre.norm();
    if (!(cap.distance > cap.radius)) return false;
    cap.axis = toCentre / cap.distance;
    cap.sinAlpha = cap.radius / cap.distance;
    const double sin2 = cap.sinAlpha * cap.sinAlpha;
    cap.oneMinusCos = sin2 / (1 + std::sqrt(1 - sin2));
  }
  const Vec3 helper = std::abs(cap.axis.y()) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
  cap.u = cap.axis.cross(helper).normalized();
  cap.v = cap.axis.cross(cap.u);
  return true;
}

/// The caps a lamp shows: a distant disc's is the same from every point, so
/// it and its probe directions are worked out once; a sphere's per point.
class CapsOf {
 public:
  explicit CapsOf(const CapLamp& lamp) : lamp_(lamp) {
    if (!lamp.atInfinity) return;
    capOf(lamp, Vec3::Zero(), distant_);
    for (int k = 0; k < kProbes; ++k) probes_[k] = distant_.direction(probePoints()[k]);
  }
  /// The cap seen from `point` (in `scratch` for a sphere); null when the
  /// point lies inside or on the sphere.
  const SphereCap* at(const Vec3& point, SphereCap& scratch) const {
    if (lamp_.atInfinity) return &distant_;
    return capOf(lamp_, point, scratch) ? &scratch : nullptr;
  }
  /// Probe point k's direction on `cap` (one of at()'s).
  Vec3 probe(const SphereCap& cap, int k) const {
    return lamp_.atInfinity ? probes_[k] : cap.direction(probePoints()[k]);
  }

 private:
  const CapLamp& lamp_;
  SphereCap distant_;
  std::array<Vec3, kProbes> probes_;
};

Vec3 vec3At(const std::vector<float>& values, long long i) {
  return {values[3 * i], values[3 * i + 1], values[3 * i + 2]};
}

/// A ray's far end: just short of the lamp, so what lies beyond it casts no
/// shadow (a distant disc's rays run on to infinity).
float stopBefore(double reach) {
  return static_cast<float>(reach * (1 - 1e-6));
}

/// One sample's light from the cap, and what its rays found.
struct CapLight {
  double unoccluded = 0;  ///< weight x integral of f/albedo x cos over the cap
  double strataSum = 0;   ///< over the strata above both horizons: f/albedo x cos
  double seen = 0;        ///< the same over the strata whose rays reached the lamp
  int cornersQueued = 0, cornersReached = 0;  ///< the first look's rays
};

/// Which of a sample's strata sumStrata traces: all, the four corner cells
/// of its n x n grid (the first look: four rays spread over the disc), or
/// the rest.
enum class Strata { All, Corners, Rest };

bool isCorner(int i, int side) {
  const int column = i % side, row = i / side;
  return (column == 0 || column == side - 1) && (row == 0 || row == side - 1);
}

/// The strata of one sample: the sum over those above both horizons of
/// f/albedo x cos (0 unless `wantSum`: then only the `which` are drawn)
/// and, where `trace`, the rays of the `which` among them queued with that
/// as their light; `queued` counts them.
template <typename Batch>
double sumStrata(const TransportHeader& h, const SphereCap& cap, long long s, int rays,
                 Batch* trace, Strata which, bool wantSum, int* queued = nullptr) {
  const LampGeometry& g = h.lamps;
  const Vec3 origin = vec3At(g.origin, s), n = vec3At(g.normal, s),
             ng = vec3At(g.geometricNormal, s);
  const Vec3 toViewer = (h.camera.eye - origin).normalized();
  const Material& material = g.materials[g.material[s]];
  const Vec3 tangent = g.tangentAt(s);
  // Jittered and turned by the sample's seed: neighbouring samples' strata
  // differ, and a lamp that moves keeps each sample's.
  const auto seed = static_cast<std::uint64_t>(s);
  const double turn = 2 * kPi * unitFromBits(splitMix(seed));
  const double c = std::cos(turn), sn = std::sin(turn);
  const int side = strataSide(rays);
  double sum = 0;
  for (int i = 0; i < rays; ++i) {
    const bool chosen =
        trace && (which == Strata::All || isCorner(i, side) == (which == Strata::Corners));
    if (!chosen && !wantSum) continue;
    const Eigen::Vector2d p = stratumPoint(i, side, seed);
    const Vec3 w = cap.direction({c * p.x() - sn * p.y(), sn * p.x() + c * p.y()});
    const double cosine = n.dot(w);
    if (!(cosine > 0 && ng.dot(w) > 0)) continue;  // both horizons, as the precompute's rays
    const double value = brdfShape(material, n, tangent, toViewer, w) * cosine;
    sum += value;
    if (!chosen) continue;
    trace->add(origin.cast<float>(), w.cast<float>(), stopBefore(cap.reach(w)), s, value);
    if (queued) ++*queued;
  }
  return sum;
}

}  // namespace

CapLamp CapLamp::sphere(const LocalLight& lamp, const SphereLight& shape) {
  CapLamp cap;
  cap.centre = lamp.position;
  cap.radius = shape.radius;
  cap.radiance = lamp.emission;
  return cap;
}

CapLamp CapLamp::distant(const MapSource& disc) {
  CapLamp cap;
  cap.centre = disc.direction.normalized();
  cap.radius = disc.radius;
  cap.atInfinity = true;
  cap.radiance = disc.radiance;
  return cap;
}

std::vector<LampSight> sphereLampSight(const TransportHeader& h, const SceneOccluder& occluder,
                                       const CapLamp& lamp, std::atomic<long long>& rays) {
  const LampGeometry& g = h.lamps;
  const int width = h.camera.size.width, height = h.camera.size.height;
  const CapsOf caps(lamp);
  std::vector<std::int8_t> probe(static_cast<size_t>(g.samples()), kNoProbe);
  // Per pixel, what its own probes saw: bit 1 one reached the lamp, bit 2
  // one was blocked (each row writes its own pixel's).
  constexpr std::uint8_t kSawReached = 1, kSawBlocked = 2;
  std::vector<std::uint8_t> saw(static_cast<size_t>(width) * height, 0);
  tbb::parallel_for(tbb::blocked_range<long long>(0, h.rows(), 256), [&](const auto& range) {
    ShadowRayBatch batch(occluder, g.rayEpsilon,
                         [&](std::int64_t s, double) { probe[s] = kProbeReached; });
    for (long long r = range.begin(); r < range.end(); ++r) {
      const int x = h.pixels[r] % width, y = h.pixels[r] / width;
      for (long long s = g.sampleStart[r]; s < g.sampleStart[r + 1]; ++s) {
        SphereCap scratch;
        const Vec3 origin = vec3At(g.origin, s);
        const SphereCap* cap = caps.at(origin, scratch);
        if (!cap) continue;
        // The pixel's place in its tile picks the first point, its samples
        // the next: every 3x3 window of pixels holds all nine points.
        const int k =
            static_cast<int>((x % kTile + kTile * (y % kTile) + s - g.sampleStart[r]) % kProbes);
        const Vec3 w = caps.probe(*cap, k);
        if (!(vec3At(g.normal, s).dot(w) > 0 && vec3At(g.geometricNormal, s).dot(w) > 0)) continue;
        probe[s] = kProbeBlocked;  // until the ray says otherwise
        batch.add(origin.cast<float>(), w.cast<float>(), stopBefore(cap->reach(w)), s, 0);
      }
    }
    batch.flush();
    rays += batch.rays();
    for (long long r = range.begin(); r < range.end(); ++r) {
      std::uint8_t bits = 0;
      for (long long s = g.sampleStart[r]; s < g.sampleStart[r + 1]; ++s)
        bits |= probe[s] == kProbeReached   ? kSawReached
                : probe[s] == kProbeBlocked ? kSawBlocked
                                            : 0;
      saw[h.pixels[r]] = bits;
    }
  });
  std::vector<LampSight> sight(static_cast<size_t>(h.rows()));
  tbb::parallel_for(tbb::blocked_range<long long>(0, h.rows(), 1024), [&](const auto& range) {
    for (long long r = range.begin(); r < range.end(); ++r) {
      const int x = h.pixels[r] % width, y = h.pixels[r] / width;
      std::uint8_t bits = 0;
      for (int ny = std::max(0, y - 1); ny <= std::min(height - 1, y + 1); ++ny)
        for (int nx = std::max(0, x - 1); nx <= std::min(width - 1, x + 1); ++nx)
          bits |= saw[static_cast<size_t>(ny) * width + nx];
      const bool reached = bits & kSawReached, blocked = bits & kSawBlocked;
      // No probe above the horizons (a cap across them): the strata decide.
      sight[r] = reached == blocked ? LampSight::Partly
                 : reached          ? LampSight::Whole
                                    : LampSight::Hidden;
    }
  });
  return sight;
}

long long addSphereLamp(const TransportHeader& h, const SceneOccluder& occluder,
                        const CapLamp& lamp, const std::vector<LampSight>& sight, int rays,
                        long long first, long long end, std::vector<Rgb>& acc) {
  const LampGeometry& g = h.lamps;
  const long long firstSample = g.sampleStart[first];
  std::vector<CapLight> light(static_cast<size_t>(g.sampleStart[end] - firstSample));
  // A distant disc's samples look at four strata first; a sphere lamp's,
  // whose penumbrae span many pixels, trace all of theirs at once (a first
  // look that stops where four agree would clip a wide penumbra's tails:
  // 6% narrower at 16 rays).
  const Strata firstLook = lamp.atInfinity ? Strata::Corners : Strata::All;
  bool looking = true;
  ShadowRayBatch batch(occluder, g.rayEpsilon, [&](std::int64_t s, double value) {
    CapLight& l = light[s - firstSample];
    l.seen += value;
    l.cornersReached += looking;
  });
  const CapsOf caps(lamp);
  // The samples of [first, end) that a ray can reach: fn(row, sample, cap, light).
  const auto eachSample = [&](auto&& fn) {
    for (long long r = first; r < end; ++r) {
      if (sight[r] == LampSight::Hidden) continue;
      for (long long s = g.sampleStart[r]; s < g.sampleStart[r + 1]; ++s) {
        SphereCap scratch;
        const SphereCap* cap = caps.at(vec3At(g.origin, s), scratch);
        // Facing away (half the leaves of a plant): no stratum lies above
        // both horizons, so no light and no strata to draw.
        if (cap && !cap->below(vec3At(g.normal, s)) && !cap->below(vec3At(g.geometricNormal, s)))
          fn(r, s, *cap, light[s - firstSample]);
      }
    }
  };
  eachSample([&](long long r, long long s, const SphereCap& cap, CapLight& l) {
    const Vec3 n = vec3At(g.normal, s);
    // A diffuse sample seeing the whole cap above its horizons: the
    // integral of cos / pi over it is sin^2(alpha) cos(beta), exactly.
    const bool closedForm = g.materials[g.material[s]].type == Material::Type::Diffuse &&
                            cap.above(n) && cap.above(vec3At(g.geometricNormal, s));
    const bool traced = sight[r] == LampSight::Partly;
    // The whole sum only where the light needs it now (not in closed form);
    // a penumbra's first look needs its four strata alone.
    if (!closedForm || traced)
      l.strataSum = sumStrata(h, cap, s, rays, traced ? &batch : nullptr, firstLook, !closedForm,
                              &l.cornersQueued);
    l.unoccluded = g.weight[s] * (closedForm ? cap.sinAlpha * cap.sinAlpha * n.dot(cap.axis)
                                             : l.strataSum * cap.solidAngle() / rays);
  });
  batch.flush();
  // The first look's four rays agreeing, the sample is taken as lit whole or
  // not at all (most of a 3-pixel band round a shadow edge is: 86% of the
  // plant's); else the rest of its strata are traced.
  looking = false;
  if (firstLook == Strata::Corners)
    eachSample([&](long long r, long long s, const SphereCap& cap, CapLight& l) {
      if (sight[r] != LampSight::Partly) return;
      const bool whole = l.cornersQueued > 0 && l.cornersReached == l.cornersQueued;
      const bool hidden = l.cornersQueued > 0 && l.cornersReached == 0;
      if (whole || hidden)  // a share of 1 or 0, whatever the sum
        l.strataSum = std::max(l.strataSum, 1.0), l.seen = whole ? l.strataSum : 0;
      else
        l.strataSum = sumStrata(h, cap, s, rays, &batch, Strata::Rest, true);
    });
  batch.flush();
  for (long long r = first; r < end; ++r) {
    if (sight[r] == LampSight::Hidden) continue;
    double sum = 0;
    for (long long s = g.sampleStart[r]; s < g.sampleStart[r + 1]; ++s) {
      const CapLight& l = light[s - firstSample];
      // Seen partly: the unoccluded light times the share of the strata's
      // f/albedo x cos that reached the lamp, so a penumbra meets the whole
      // cap's light seamlessly.
      if (sight[r] == LampSight::Whole)
        sum += l.unoccluded;
      else if (l.strataSum > 0)
        sum += l.unoccluded * (l.seen / l.strataSum);
    }
    acc[r - first] += sum * lamp.radiance;
  }
  return batch.rays();
}

}  // namespace acpca
