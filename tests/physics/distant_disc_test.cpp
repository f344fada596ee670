// Distant discs (a map's sun and lamps) lit exactly (relight/sphere_lamp.h,
// CapLamp::distant): the closed form L sin^2(alpha) cos(beta) over an open
// floor, a straight edge's penumbra as wide as the disc's angle and the
// edge's distance give, a sun's shadow edge where its direction puts it to a
// quarter of a pixel, and the same values for any thread count.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "precompute/scene.h"
#include "precompute/transport_renderer.h"
#include "relight/lamp_light.h"
#include "relight/sphere_lamp.h"
#include "tests/physics/penumbra_profile.h"
#include "tests/render_support.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDegree = kPi / 180;
constexpr float kAlbedo = 0.8f;
const Material kGrey{Material::Type::Diffuse, {kAlbedo, kAlbedo, kAlbedo}};

std::string precomputed(const test::TempDir& dir, const Scene& s, int spp) {
  const std::string path = dir.file("t.h5");
  PrecomputeOptions o;
  o.cubemapResolution = 8;
  o.samplesPerPixel = spp;
  o.precision = Precision::F32;
  precomputeTransport(s, path, o);
  return path;
}

/// A disc `theta` degrees from +Y towards -X, of angular radius `radius`
/// degrees and radiance L.
MapSource disc(double theta, double radius, double radiance) {
  MapSource d;
  d.direction = Vec3(-std::sin(theta * kDegree), std::cos(theta * kDegree), 0);
  d.radius = radius * kDegree;
  d.radiance = Rgb::Constant(radiance);
  return d;
}

TEST(DistantDiscs, AnOpenFloorReceivesLPiSinSquaredAlphaCosBeta) {
  // A diffuse floor of albedo a under a disc of angular radius alpha at
  // beta from its normal shows a L sin^2(alpha) cos(beta) (irradiance
  // L pi sin^2 alpha cos beta, times a / pi) at every pixel, wherever the
  // pixel is: no 1/d^2. Every probe reaches the disc, so one ray a sample.
  const test::TempDir dir;
  const std::string path = precomputed(dir, test::floorScene(32, kGrey), 1);
  const TransportReader t(path);
  for (const auto& [beta, alpha] : {std::pair{30.0, 0.265}, std::pair{60.0, 3.0}}) {
    const MapSource d = disc(beta, alpha, 4e4);
    const ExactLamps lamps(t.header());
    const std::vector<float> rows = lamps.relight({}, kDefaultSphereLampRays, {d});
    const double expected =
        kAlbedo * 4e4 * std::pow(std::sin(alpha * kDegree), 2) * std::cos(beta * kDegree);
    for (long long r = 0; r < t.rows(); ++r)
      ASSERT_NEAR(rows[3 * r] / expected, 1, 1e-5) << beta << " " << alpha << " row " << r;
    EXPECT_EQ(lamps.shadowRays(), t.header().lamps.samples());
  }
  // Below kPointDiscRadius a disc is a point at infinity of its power
  // L 2 pi (1 - cos alpha): a L 2 (1 - cos alpha) cos(beta), one ray a sample
  // and no probe.
  const double alpha = 0.5 * kPointDiscRadius;
  const MapSource tiny = disc(45, alpha / kDegree, 1e9);
  const ExactLamps lamps(t.header());
  const std::vector<float> rows = lamps.relight({}, kDefaultSphereLampRays, {tiny});
  const double expected = kAlbedo * 1e9 * 2 * (1 - std::cos(alpha)) * std::cos(45 * kDegree);
  for (long long r = 0; r < t.rows(); ++r)
    ASSERT_NEAR(rows[3 * r] / expected, 1, 1e-5) << "row " << r;
  EXPECT_EQ(lamps.shadowRays(), t.header().lamps.samples());
}

/// A floor under a thin slab whose edge runs along z at (kEdgeX, kEdgeY):
/// the lit share of the disc per image column, over the middle rows.
constexpr double kEdgeX = -0.5, kEdgeY = 1.0;
test::ShareProfile edgeProfile(const TransportHeader& h, const std::vector<float>& rows,
                               const MapSource& d) {
  const double whole = kAlbedo * d.radiance.x() * std::pow(std::sin(d.radius), 2) * d.direction.y();
  return test::floorColumnProfile(h, rows, 0.1, [&](const Vec3&) { return whole; });
}

Scene slabScene(int size) {
  Scene s = test::floorScene(size, kGrey);
  s.meshes.push_back(makeBox({-6, kEdgeY, -6}, {kEdgeX, kEdgeY + 0.001, 6}, kGrey, "slab"));
  return s;
}

TEST(DistantDiscs, AStraightEdgesPenumbraIsAsWideAsTheDiscAndTheDistanceGive) {
  // A floor point at x sees the disc cut by the plane through it and the
  // edge (the line along z through (kEdgeX, kEdgeY)): the disc's centre
  // lies at angle delta from that plane, and the share seen is the part of
  // the disc beyond a chord at delta / alpha radii from its centre. The
  // width between 10% and 90% of the whole disc's light against the same
  // from the closed form.
  const test::TempDir dir;
  const std::string path = precomputed(dir, slabScene(128), 4);
  const TransportReader t(path);
  const MapSource d = disc(30, 2, 100);
  const ExactLamps lamps(t.header());
  const auto profile = edgeProfile(t.header(), lamps.relight({}, kDefaultSphereLampRays, {d}), d);
  ASSERT_GT(profile.size(), 100u);
  EXPECT_LT(profile.front().second, 1e-6);      // the umbra
  EXPECT_NEAR(profile.back().second, 1, 1e-5);  // the whole disc, in closed form
  const auto share = [&](double x) {
    const Eigen::Vector2d toEdge(kEdgeX - x, kEdgeY);
    const Eigen::Vector2d normal = Eigen::Vector2d(toEdge.y(), -toEdge.x()).normalized();
    const double t = std::asin(normal.dot(Eigen::Vector2d(d.direction.x(), d.direction.y()))) /
                     d.radius;  // > 0: the centre on the lit side
    return test::visibleShare(t);
  };
  const auto closedCrossing = [&](double s) { return test::risingCrossing(share, s, -0.5, 1.0); };
  const double measured = test::profileCrossing(profile, 0.9) - test::profileCrossing(profile, 0.1);
  const double expected = closedCrossing(0.9) - closedCrossing(0.1);
  EXPECT_NEAR(measured / expected, 1, 0.05) << measured << " against " << expected;
  RecordProperty("penumbra_width_10_90", std::to_string(measured));
  RecordProperty("closed_form_width_10_90", std::to_string(expected));
}

TEST(DistantDiscs, ASunsShadowEdgeFallsWhereItsDirectionPutsItToAQuarterPixel) {
  // A 0.53-degree sun 40 degrees from the zenith: the slab's edge at height
  // kEdgeY casts its shadow edge at x = kEdgeX + kEdgeY tan(40 degrees);
  // the half-lit crossing of the columns' profile lies there to 0.25 px.
  const test::TempDir dir;
  const std::string path = precomputed(dir, slabScene(96), 16);
  const TransportReader t(path);
  const MapSource d = disc(40, 0.265, 4e4);
  const ExactLamps lamps(t.header());
  const std::vector<float> rows = lamps.relight({}, kDefaultSphereLampRays, {d});
  const auto profile = edgeProfile(t.header(), rows, d);
  const double pixel = (profile.back().first - profile.front().first) / (profile.size() - 1);
  const double expected = kEdgeX + kEdgeY * std::tan(40 * kDegree);
  const double measured = test::profileCrossing(profile, 0.5);
  EXPECT_LT(std::abs(measured - expected) / pixel, 0.25)
      << measured << " against " << expected << ", a pixel " << pixel;
  RecordProperty("shadow_edge_offset_px", std::to_string((measured - expected) / pixel));
  tbb::task_arena one(1);
  EXPECT_EQ(one.execute([&] { return ExactLamps(t.header()).relight({}, 64, {d}); }), rows);
}

}  // namespace
}  // namespace acpca
