#pragma once
// A lat-long map integrated onto the cube lattice (docs/lighting.md,
// "Integrating a map"). Each map pixel is split into sub-cells small against
// a texel; every sub-cell adds radiance x its exact solid angle to the texel
// holding its rotated centre. Two ways to the same sums:
//  - cell by cell, any rotation: each sub-cell's direction turned and
//    classified (2M sub-cells for a 2048x1024 map);
//  - under a yaw alone (what --rotate YAW and sweeps make), row by row: a
//    yaw slides every row of sub-cells along its circle of latitude, and
//    each circle crosses the lattice's texels in arcs found once per row
//    (where it meets the planes that bound texels and faces). Each arc's
//    sub-cells are a run of the row, summed from the row's prefix sums: a
//    few hundred runs a row instead of a direction per sub-cell.
// Both put every sub-cell in the same texel but one whose centre lies
// within rounding of a texel's edge, and add in different orders.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "lighting/environment.h"

namespace acpca {

/// A map's sub-cells per pixel side on `lattice`: at most 1/8 of a texel's
/// angular size.
int latLongSubCells(const LatLongPixels& map, const CubeLattice& lattice);

/// Cell by cell, under any rotation: adds onto `lighting`.
void integrateLatLongCells(const LatLongPixels& map, const CubeLattice& lattice,
                           const Eigen::Matrix3d& rotation, LatticeLighting& lighting);

/// Whether `rotation` turns about +Y alone (R(1,1) = 1, exactly).
bool isYawOnly(const Eigen::Matrix3d& rotation);

/// Each row of a map's pixels as prefix sums (double) at every 16th pixel,
/// made once per map: an eighth of the map's own size (a full table was
/// twice it), the pixels between added as the full table would have them.
class LatLongRowSums {
 public:
  explicit LatLongRowSums(const LatLongPixels& map);
  /// RGB sums over sub-cells [0, i) of row `row` (`sub` sub-cells a pixel
  /// side), the row repeating around the circle: any i.
  void upTo(int row, long long i, int sub, double out[3]) const;
  /// Asks the CPU to fetch what upTo(row, i, ...) reads (0 <= i < width x sub).
  void prefetch(int row, long long i, int sub) const {
    const long long block = i / sub / kBlock;
    __builtin_prefetch(&sums_[(static_cast<size_t>(row) * entries_ + block) * 3]);
    __builtin_prefetch(rgb_ + (static_cast<size_t>(row) * width_ + block * kBlock) * 3);
  }

 private:
  static constexpr int kBlock = 16;
  int width_, entries_;  ///< entries a row: the sums before pixels 0, 16, ..., and the total
  const float* rgb_;
  std::vector<double> sums_;
};

/// Under a yaw alone (isYawOnly), row by row: adds onto `lighting`.
void integrateLatLongYawed(const LatLongPixels& map, const LatLongRowSums& sums,
                           const CubeLattice& lattice, const Eigen::Matrix3d& rotation,
                           LatticeLighting& lighting);
/// The same under several yaws at once, each row read once for all of them:
/// adds onto *lightings[k] what integrateLatLongYawed adds for rotations[k],
/// the same values.
void integrateLatLongYaws(const LatLongPixels& map, const LatLongRowSums& sums,
                          const CubeLattice& lattice, const std::vector<Eigen::Matrix3d>& rotations,
                          const std::vector<LatticeLighting*>& lightings);

}  // namespace acpca
