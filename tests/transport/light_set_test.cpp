// Light sets: cells of the sphere that sum to 4 pi, capped cells of a dome,
// and the light set's round trip through the transport file.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "tests/sphere_points.h"
#include "tests/temp_dir.h"
#include "transport/light_set.h"
#include "transport/transport_file.h"

namespace acpca {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<Vec3> octahedron() {
  return {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
}

double sum(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return s;
}

TEST(LightCells, TheOctahedronsCellsAreTheCubeFaces) {
  // Light +X's Voronoi cell is where x is the largest coordinate: face +X,
  // whose solid angle is 4 pi / 6 by symmetry.
  const LightCells cells(octahedron(), 180, 16, 2);
  for (double w : cells.solidAngles()) EXPECT_NEAR(w, 4 * kPi / 6, 1e-12);
  EXPECT_DOUBLE_EQ(defaultCellCapDegrees(octahedron()), 90);
}

TEST(LightCells, UncappedCellsSumToTheSphere) {
  const std::vector<Vec3> lights = test::goldenSpiral(331);
  const LightCells cells(lights, 180);
  const std::vector<double> w = cells.solidAngles();
  EXPECT_NEAR(sum(w), 4 * kPi, 4 * kPi * 1e-6);
  // Evenly spread lights have nearly equal cells.
  for (double x : w) EXPECT_NEAR(x, 4 * kPi / 331, 0.15 * 4 * kPi / 331);
  // The default cap holds every point of every cell.
  const LightCells capped(lights, defaultCellCapDegrees(lights));
  EXPECT_NEAR(sum(capped.solidAngles()), 4 * kPi, 4 * kPi * 1e-6);
}

TEST(LightCells, ACappedLoneLightHoldsItsSphericalCap) {
  // One light at +Y capped at 30 degrees: a cap of 2 pi (1 - cos 30).
  const LightCells cells({{0, 1, 0}}, 30);
  EXPECT_NEAR(cells.solidAngles()[0], 2 * kPi * (1 - std::cos(kPi / 6)), 2e-4);
}

TEST(LightCells, ADomesLowestRingDoesNotTakeTheLowerHemisphere) {
  // Rings every 15 degrees from the zenith down to the horizon: a dome.
  std::vector<Vec3> dome{{0, 1, 0}};
  for (int ring = 1; ring <= 6; ++ring) {
    const double theta = ring * 15 * kPi / 180;
    const int count = 6 * ring;
    for (int i = 0; i < count; ++i) {
      const double phi = 2 * kPi * i / count;
      dome.emplace_back(std::sin(theta) * std::sin(phi), std::cos(theta),
                        -std::sin(theta) * std::cos(phi));
    }
  }
  const double cap = defaultCellCapDegrees(dome);
  EXPECT_LT(cap, 20);
  LightSet set;
  set.directions = dome;
  set.solidAngles = LightCells(dome, cap).solidAngles();
  // Nothing reaches further below the horizon than the cap.
  const double coveredAtMost = 2 * kPi * (1 + std::sin(cap * kPi / 180));
  EXPECT_LE(sum(set.solidAngles), coveredAtMost * (1 + 1e-3));
  EXPECT_GT(set.uncoveredSolidAngle(), 2 * kPi * (1 - std::sin(cap * kPi / 180)) * 0.999);
}

TEST(LightSetFile, ALightSetSurvivesTheTransportFile) {
  test::TempDir dir;
  TransportHeader h;
  h.camera.size = {3, 2};
  h.cubemapResolution = 0;
  h.precision = Precision::F32;
  h.lights.directions = octahedron();
  h.lights.solidAngles.assign(6, 4 * kPi / 6);
  h.lights.irradiance.assign(6, Eigen::Vector3d(1, 2, 3));
  h.lights.capDegrees = 90;
  h.pixels = {1, 4};
  h.albedo.assign(6, 1.0f);
  h.coverage = {1.0f, 0.5f};
  const std::string path = dir.file("lights.h5");
  std::vector<float> rows(2 * 6);
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = 0.25f * i;
  TransportWriter w(path, h);
  w.writeRows(0, 2, rows.data());
  w.finish();

  const TransportReader r(path);
  const TransportHeader& back = r.header();
  ASSERT_TRUE(back.isLightSet());
  EXPECT_EQ(back.latticeSize(), 6);
  EXPECT_EQ(back.rowLength(), 6);
  EXPECT_EQ(back.lights.directions, h.lights.directions);
  EXPECT_EQ(back.lights.solidAngles, h.lights.solidAngles);
  EXPECT_EQ(back.lights.irradiance, h.lights.irradiance);
  EXPECT_EQ(back.lights.cells, CellSource::CappedVoronoi);
  EXPECT_EQ(back.lights.capDegrees, 90);
  EXPECT_FALSE(back.hasNormals());
  std::vector<float> read(rows.size());
  r.readRows(0, 2, read.data());
  EXPECT_EQ(read, rows);
}

TEST(LightSetFile, BadLightSetsAreRefused) {
  LightSet set;
  set.directions = {{0, 2, 0}};
  set.solidAngles = {1};
  set.irradiance = {Eigen::Vector3d::Ones()};
  set.capDegrees = 30;
  EXPECT_THROW(set.validate("f"), UserError);  // not a unit vector
  set.directions = {{0, 1, 0}};
  set.solidAngles = {13};
  EXPECT_THROW(set.validate("f"), UserError);  // more than the sphere
  set.solidAngles = {1};
  set.irradiance = {Eigen::Vector3d(1, 0, 1)};
  EXPECT_THROW(set.validate("f"), UserError);  // a channel without light
  set.irradiance = {Eigen::Vector3d::Ones()};
  EXPECT_NO_THROW(set.validate("f"));
}

}  // namespace
}  // namespace acpca
