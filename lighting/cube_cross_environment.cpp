// Cube-map environments given as a horizontal cross (4:3), in the layout that
// `envmap --cross` writes (cube_cross.h). Each cross pixel is constant
// radiance over its exact solid angle on its cube face, split into sub-cells
// small against a lattice texel, each added to the texel holding its rotated
// centre: energy is conserved to rounding at any rotation.
#include <tbb/parallel_for.h>

#include <cmath>

#include "core/error.h"
#include "lighting/builtin_maps.h"
#include "lighting/cube_cross.h"
#include "lighting/environment.h"

namespace acpca {

const std::array<CrossFace, 6> kCrossFaces = {{
    {0, 1, {-1, 0, 0}, {0, 0, -1}, {0, -1, 0}},
    {1, 1, {0, 0, -1}, {1, 0, 0}, {0, -1, 0}},
    {2, 1, {1, 0, 0}, {0, 0, 1}, {0, -1, 0}},
    {3, 1, {0, 0, 1}, {-1, 0, 0}, {0, -1, 0}},
    {1, 0, {0, 1, 0}, {1, 0, 0}, {0, 0, -1}},
    {1, 2, {0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
}};

bool crossDirection(int x, int y, int faceSize, Vec3& direction) {
  const int column = x / faceSize, row = y / faceSize;
  // Face-local coordinates in [-1, 1], a to the right, b downwards.
  const double a = 2 * ((x % faceSize) + 0.5) / faceSize - 1;
  const double b = 2 * ((y % faceSize) + 0.5) / faceSize - 1;
  for (const CrossFace& face : kCrossFaces)
    if (face.column == column && face.row == row) {
      direction = face.centre + a * face.right + b * face.down;
      return true;
    }
  return false;
}

namespace {

class CubeCrossEnvironment : public Environment {
 public:
  CubeCrossEnvironment(std::string name, int faceSize, std::vector<float> rgb)
      : name_(std::move(name)), faceSize_(faceSize), rgb_(std::move(rgb)) {
    ACPCA_CHECK(rgb_.size() == 36ull * faceSize * faceSize, "cross buffer ", rgb_.size());
  }
  std::string name() const override { return name_; }

  Rgb radiance(const Vec3& dir) const override {  // nearest pixel
    const CrossFace* best = &kCrossFaces[0];
    for (const CrossFace& f : kCrossFaces)
      if (dir.dot(f.centre) > dir.dot(best->centre)) best = &f;
    const Vec3 onFace = dir / dir.dot(best->centre);
    const auto pixel = [&](double t) {
      return std::clamp(static_cast<int>((t + 1) / 2 * faceSize_), 0, faceSize_ - 1);
    };
    const int x = best->column * faceSize_ + pixel(onFace.dot(best->right));
    const int y = best->row * faceSize_ + pixel(onFace.dot(best->down));
    const float* p = &rgb_[3 * (static_cast<size_t>(y) * 4 * faceSize_ + x)];
    return {p[0], p[1], p[2]};
  }

  void integrate(const CubeLattice& lattice, const Eigen::Matrix3d& rotation,
                 LatticeLighting& lighting) const override {
    ACPCA_CHECK(lighting.size() == 3u * lattice.size(), "lighting size ", lighting.size());
    // Sub-cells at most 1/8 of a texel across.
    const int sub =
        std::max(1, (kMapSubCellsPerTexel * lattice.resolution() + faceSize_ - 1) / faceSize_);
    const int cells = faceSize_ * sub;
    const double cell = 2.0 / cells;
    // Per face its own partial sums, added in order: thread-count independent.
    std::vector<std::vector<double>> partial(6);
    tbb::parallel_for(0, 6, [&](int faceIndex) {
      const CrossFace& face = kCrossFaces[faceIndex];
      auto& acc = partial[faceIndex];
      acc.assign(lighting.size(), 0.0);
      for (int j = 0; j < cells; ++j)
        for (int i = 0; i < cells; ++i) {
          const int x = face.column * faceSize_ + i / sub, y = face.row * faceSize_ + j / sub;
          const float* p = &rgb_[3 * (static_cast<size_t>(y) * 4 * faceSize_ + x)];
          if (p[0] == 0 && p[1] == 0 && p[2] == 0) continue;
          const double a0 = -1 + i * cell, b0 = -1 + j * cell;
          const double omega = CubeLattice::rectangleSolidAngle(a0, b0, a0 + cell, b0 + cell);
          const Vec3 w =
              face.centre + (a0 + 0.5 * cell) * face.right + (b0 + 0.5 * cell) * face.down;
          const int texel = lattice.texelOf(rotation * w.normalized());
          for (int c = 0; c < 3; ++c) acc[3 * texel + c] += omega * p[c];
        }
    });
    for (const auto& acc : partial)
      for (size_t k = 0; k < lighting.size(); ++k) lighting[k] += acc[k];
  }

 private:
  std::string name_;
  int faceSize_;
  std::vector<float> rgb_;
};

}  // namespace

std::unique_ptr<Environment> makeCubeCrossEnvironment(std::string name, int faceSize,
                                                      std::vector<float> rgb) {
  return std::make_unique<CubeCrossEnvironment>(std::move(name), faceSize, std::move(rgb));
}

}  // namespace acpca
