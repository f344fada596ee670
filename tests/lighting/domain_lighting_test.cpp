// Lighting a light set: environments integrated over the lights' cells keep
// their energy, a sun lands in the cell around it, and rotations re-integrate.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "lighting/domain_lighting.h"

namespace acpca {
namespace {

constexpr double kPi = std::numbers::pi;

TransportHeader lightSetHeader(std::vector<Vec3> directions, double cap,
                               std::vector<double> given = {}) {
  TransportHeader h;
  h.cubemapResolution = 0;
  for (Vec3& d : directions) d.normalize();
  h.lights.directions = directions;
  h.lights.irradiance.assign(directions.size(), Eigen::Vector3d::Ones());
  if (given.empty()) {
    h.lights.capDegrees = cap;
    h.lights.solidAngles = LightCells(directions, cap).solidAngles();
  } else {
    h.lights.cells = CellSource::Given;
    h.lights.solidAngles = given;
  }
  return h;
}

std::vector<Vec3> octahedron() {
  return {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
}

TEST(DomainLighting, AConstantMapGivesEachCellItsSolidAngle) {
  const TransportHeader h = lightSetHeader(octahedron(), 90);
  const DomainLighting domain(h);
  ASSERT_TRUE(domain.isLightSet());
  EXPECT_EQ(domain.size(), 6);
  double uncovered = 1;
  const LatticeLighting l =
      domain(*makeConstantEnvironment(Rgb(1, 2, 3)), {}, RotationMode::Exact, &uncovered);
  for (int k = 0; k < 6; ++k)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(l[3 * k + c], (c + 1) * 4 * kPi / 6, 1e-9);
  EXPECT_NEAR(uncovered, 0, 1e-12);
}

TEST(DomainLighting, ASunLandsWhollyInTheCellAroundItAtAnyRotation) {
  const DomainLighting domain(lightSetHeader(octahedron(), 90));
  // A 2-degree sun at theta 30, phi 30: nearest +Y.
  const auto sun = makeSunEnvironment(30, 30, 2, Rgb::Ones());
  const double energy = totalEnergy(computeLighting(*sun, CubeLattice(32), {}))[0];
  const LatticeLighting l = domain(*sun, {});
  EXPECT_NEAR(l[3 * 2], energy, 1e-9 * energy);  // light +Y
  // Yaw 90 carries it nowhere new (it stays nearest +Y); pitch -90 tips
  // +Y onto +Z: the rotation is integrated again, not looked up.
  EXPECT_NEAR(domain(*sun, {90, 0, 0})[3 * 2], energy, 1e-9 * energy);
  const LatticeLighting tipped = domain(*sun, {0, 90, 0});
  const Vec3 to = rotationMatrix({0, 90, 0}) * directionFromAngles(kPi / 6, kPi / 6);
  ASSERT_GT(to.z(), 0.8);  // nearest +Z now
  EXPECT_NEAR(tipped[3 * 4], energy, 1e-9 * energy);
  EXPECT_THROW(domain(*sun, {0, 90, 0}, RotationMode::FastLattice), UserError);
}

TEST(DomainLighting, CappedCellsLeaveTheUncoveredLightOut) {
  // One light at +Y capped at 30 degrees: a constant map's lighting is the
  // cap's solid angle, and the rest of the sphere is reported as lost.
  const DomainLighting domain(lightSetHeader({{0, 1, 0}}, 30));
  double uncovered = 0;
  const LatticeLighting l =
      domain(*makeConstantEnvironment(Rgb::Ones()), {}, RotationMode::Exact, &uncovered);
  const double cap = 2 * kPi * (1 - std::cos(kPi / 6));
  EXPECT_NEAR(l[0], cap, 2e-4);
  EXPECT_NEAR(uncovered, 1 - cap / (4 * kPi), 2e-5);
}

TEST(DomainLighting, GivenCellsScaleTheVoronoiCellsMeanRadiance) {
  // Cells the file gives: the mean radiance of each Voronoi cell times them.
  const DomainLighting domain(lightSetHeader(octahedron(), 0, {1, 1, 2, 1, 1, 1}));
  const LatticeLighting l = domain(*makeConstantEnvironment(Rgb::Ones()), {});
  EXPECT_NEAR(l[3 * 2], 2, 1e-9);
  EXPECT_NEAR(l[0], 1, 1e-9);
  // Drawn as a map: each cell's radiance, 1 everywhere.
  for (double r : latticeRadiance(domain.mapLighting(l), domain.mapLattice()))
    EXPECT_NEAR(r, 1, 1e-9);
}

TEST(DomainLighting, ManyRotationsAtOnceAreEachRotationAlone) {
  // A light set's cells and a cube lattice's texels, under several rotations
  // at once: the lighting and the uncovered share of each as made alone.
  const auto sky = makeSkyEnvironment();
  const std::vector<EnvRotation> rotations{{}, {30, 0, 0}, {-75, 10, 5}};
  TransportHeader lattice;
  lattice.cubemapResolution = 8;
  for (const TransportHeader& h : {lightSetHeader(octahedron(), 40), lattice}) {
    const DomainLighting domain(h);
    std::vector<double> shares;
    const std::vector<LatticeLighting> many =
        domain.lightings(*sky, rotations, RotationMode::Exact, &shares);
    ASSERT_EQ(many.size(), rotations.size());
    ASSERT_EQ(shares.size(), rotations.size());
    for (size_t k = 0; k < rotations.size(); ++k) {
      double share = -1;
      EXPECT_EQ(many[k], domain(*sky, rotations[k], RotationMode::Exact, &share)) << k;
      EXPECT_EQ(shares[k], share) << k;
    }
  }
}

TEST(DomainLighting, ACubeLatticeFileLightsAsBefore) {
  TransportHeader h;
  h.cubemapResolution = 8;
  const DomainLighting domain(h);
  EXPECT_FALSE(domain.isLightSet());
  const auto sky = makeSkyEnvironment();
  EXPECT_EQ(domain(*sky, {30, 0, 0}), computeLighting(*sky, CubeLattice(8), {30, 0, 0}));
}

}  // namespace
}  // namespace acpca
