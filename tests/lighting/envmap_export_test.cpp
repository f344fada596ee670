// What the lattice sees, exported as pictures (lat-long and cube cross) and
// read back as environments: continuity, exact energy, round trips.
#include "lighting/envmap_export.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "imageio/image_output.h"
#include "lighting/environment.h"
#include "lighting/rotation.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

TEST(EnvmapExport, CrossIsContinuousAndMatchesTheLatLong) {
  const int face = 16;
  // Neighbouring pixels of the cross, also across face edges, look in nearby directions.
  Vec3 a, b;
  int pairs = 0;
  for (int y = 0; y < 3 * face; ++y)
    for (int x = 0; x + 1 < 4 * face; ++x)
      if (crossDirection(x, y, face, a) && crossDirection(x + 1, y, face, b)) {
        EXPECT_LT(std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)), 0.2);
        ++pairs;
      }
  for (int x = 0; x < 4 * face; ++x)
    for (int y = 0; y + 1 < 3 * face; ++y)
      if (crossDirection(x, y, face, a) && crossDirection(x, y + 1, face, b)) {
        EXPECT_LT(std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)), 0.2);
      }
  EXPECT_GT(pairs, 6 * face * face / 2);
  // The middle of the cross looks down -Z, as the centre of the lat-long does.
  ASSERT_TRUE(crossDirection(face + face / 2, face + face / 2, face, a));
  EXPECT_GT(a.normalized().dot(Vec3(0, 0, -1)), 0.99);
  // Same radiance in both pictures of a sun towards +X.
  const CubeLattice lattice(8);
  const LatticeLighting L =
      computeLighting(*makeSunEnvironment(90, 90, 20, Rgb::Constant(3)), lattice, {});
  const Image latlong = latticeToLatLong(L, lattice, 256, 128);
  const Image cross = latticeToCross(L, lattice, face);
  EXPECT_GT(latlong.at(192, 64)[0], 0);  // u = 0.75, the horizon
  // The lat-long spreads a texel over the pixels it holds, the cross over
  // its exact solid angle: the same radiance within the pixels' quantization.
  EXPECT_NEAR(latlong.at(192, 64)[0] / cross.at(2 * face + face / 2, face + face / 2)[0], 1, 0.1);
}

TEST(EnvmapExport, TheLatLongHoldsExactlyTheLatticeEnergy) {
  // A small sun (a few texels) is where rounding texels to pixels would show.
  const CubeLattice lattice(32);
  const LatticeLighting L =
      computeLighting(*makeSunEnvironment(60, 90, 4, Rgb(1000, 500, 250)), lattice, {});
  const Rgb total = totalEnergy(L);
  for (const auto& [w, h] : {std::pair{2048, 1024}, std::pair{512, 256}}) {
    const Image image = latticeToLatLong(L, lattice, w, h);
    Rgb sum = Rgb::Zero();
    for (int y = 0; y < h; ++y) {
      const double omega = (std::cos(M_PI * y / h) - std::cos(M_PI * (y + 1) / h)) * 2 * M_PI / w;
      for (int x = 0; x < w; ++x)
        for (int c = 0; c < 3; ++c) sum[c] += image.at(x, y)[c] * omega;
    }
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(sum[c] / total[c], 1, 1e-5) << w << "x" << h;
  }
}

TEST(Environment, CubeCrossFilesRoundTripTheLatticeAndKeepEnergyRotated) {
  // A cross written by latticeToCross (faces 2 pixels per texel) and read back
  // gives every texel its lighting again; rotated, the energy stays.
  const CubeLattice lattice(8);
  LatticeLighting L = computeLighting(*loadEnvironment("sky"), lattice, {});
  const LatticeLighting sun =
      computeLighting(*makeSunEnvironment(60, 30, 10, Rgb::Constant(50)), lattice, {});
  for (size_t k = 0; k < L.size(); ++k) L[k] += sun[k];
  const Image cross = latticeToCross(L, lattice, 16);
  test::TempDir dir;
  const std::string path = dir.file("cross.exr");
  writeImage(cross, path, ImageFormat::Exr, 0, true);
  const auto env = loadEnvironment(path);
  EXPECT_EQ(env->name(), "cross");
  const LatticeLighting back = computeLighting(*env, lattice, {});
  for (size_t k = 0; k < L.size(); ++k) EXPECT_NEAR(back[k], L[k], 1e-5 * L[k] + 1e-9) << k;
  const LatticeLighting turned = computeLighting(*env, lattice, {37, 20, 10});
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(totalEnergy(turned)[c], totalEnergy(L)[c], 1e-5 * totalEnergy(L)[c]);
  // Background lookups see the sun where the lattice put it.
  const Vec3 towardsSun = directionFromAngles(60 * M_PI / 180, 30 * M_PI / 180);
  EXPECT_GT(env->radiance(towardsSun)[0], 10 * env->radiance(-towardsSun)[0]);
}

}  // namespace
}  // namespace acpca
