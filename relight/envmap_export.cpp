#include "relight/envmap_export.h"

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

bool crossDirection(int x, int y, int faceSize, Vec3& direction) {
  const int fx = x / faceSize, fy = y / faceSize;
  // Face-local coordinates in [-1, 1], a to the right, b downwards.
  const double a = 2 * ((x % faceSize) + 0.5) / faceSize - 1;
  const double b = 2 * ((y % faceSize) + 0.5) / faceSize - 1;
  Vec3 centre, right, down;
  if (fy == 1) {
    const Vec3 centres[4] = {{-1, 0, 0}, {0, 0, -1}, {1, 0, 0}, {0, 0, 1}};
    const Vec3 rights[4] = {{0, 0, -1}, {1, 0, 0}, {0, 0, 1}, {-1, 0, 0}};
    if (fx < 0 || fx > 3) return false;
    centre = centres[fx], right = rights[fx], down = {0, -1, 0};
  } else if (fx == 1 && fy == 0) {  // +Y above -Z: its lower edge meets -Z's upper edge
    centre = {0, 1, 0}, right = {1, 0, 0}, down = {0, 0, -1};
  } else if (fx == 1 && fy == 2) {  // -Y below -Z
    centre = {0, -1, 0}, right = {1, 0, 0}, down = {0, 0, 1};
  } else {
    return false;
  }
  direction = centre + a * right + b * down;
  return true;
}

Image latticeToCross(const LatticeLighting& lighting, const CubeLattice& lattice, int faceSize) {
  return radianceImage(lighting, lattice, 4 * faceSize, 3 * faceSize,
                       [&](int x, int y, Vec3& d) { return crossDirection(x, y, faceSize, d); });
}

}  // namespace acpca
