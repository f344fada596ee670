#include "lighting/envmap_export.h"

#include <cmath>
#include <functional>
#include <numbers>

namespace acpca {

namespace {

Image radianceImage(const LatticeLighting& lighting, const CubeLattice& lattice, int width,
                    int height, const std::function<bool(int, int, Vec3&)>& direction) {
  const std::vector<double> radiance = latticeRadiance(lighting, lattice);
  Image image{width, height, 3, std::vector<float>(static_cast<size_t>(width) * height * 3, 0.f)};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      Vec3 d;
      if (!direction(x, y, d)) continue;
      const int j = lattice.texelOf(d);
      for (int c = 0; c < 3; ++c) image.at(x, y)[c] = float(radiance[3 * j + c]);
    }
  return image;
}

}  // namespace

Image latticeToLatLong(const LatticeLighting& lighting, const CubeLattice& lattice, int width,
                       int height) {
  constexpr double kPi = std::numbers::pi;
  // Which texel each pixel centre falls in, and the solid angle those pixels
  // cover per texel: a texel's lighting over that solid angle keeps its energy
  // exactly, whatever the image size.
  std::vector<int> texel(static_cast<size_t>(width) * height);
  std::vector<double> covered(lattice.size(), 0.0);
  for (int y = 0; y < height; ++y) {
    const double omega =
        (std::cos(kPi * y / height) - std::cos(kPi * (y + 1) / height)) * 2 * kPi / width;
    for (int x = 0; x < width; ++x) {
      const double phi = 2 * kPi * ((x + 0.5) / width - 0.5);
      const double theta = kPi * (y + 0.5) / height;
      const int j = lattice.texelOf(directionFromAngles(theta, phi));
      texel[static_cast<size_t>(y) * width + x] = j;
      covered[j] += omega;
    }
  }
  Image image{width, height, 3, std::vector<float>(static_cast<size_t>(width) * height * 3, 0.f)};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const int j = texel[static_cast<size_t>(y) * width + x];
      for (int c = 0; c < 3; ++c) image.at(x, y)[c] = float(lighting[3 * j + c] / covered[j]);
    }
  return image;
}

Image latticeRadianceToLatLong(const LatticeLighting& lighting, const CubeLattice& lattice,
                               int width, int height) {
  constexpr double kPi = std::numbers::pi;
  const std::vector<double> radiance = latticeRadiance(lighting, lattice);
  Image image{width, height, 3, std::vector<float>(static_cast<size_t>(width) * height * 3)};
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double phi = 2 * kPi * ((x + 0.5) / width - 0.5), theta = kPi * (y + 0.5) / height;
      const int j = lattice.texelOf(directionFromAngles(theta, phi));
      for (int c = 0; c < 3; ++c) image.at(x, y)[c] = static_cast<float>(radiance[3 * j + c]);
    }
  return image;
}

Image latticeToCross(const LatticeLighting& lighting, const CubeLattice& lattice, int faceSize) {
  return radianceImage(lighting, lattice, 4 * faceSize, 3 * faceSize,
                       [&](int x, int y, Vec3& d) { return crossDirection(x, y, faceSize, d); });
}

}  // namespace acpca
