#pragma once
// A light set: the lighting domain of a captured (imported) transport. Its
// columns are N lights instead of the cube lattice's texels; light k has a
// direction (from the subject toward the light), the solid angle of its cell
// on the sphere and the irradiance E_k it delivered (docs/formats.md,
// "Captured transport").
#include <Eigen/Core>
#include <string>
#include <vector>

#include "transport/cube_lattice.h"

namespace acpca {

/// How a light set's cells were made.
enum class CellSource {
  /// Spherical Voronoi cells of the directions, each capped at capDegrees
  /// from its light (a dome without lights below the subject leaves the
  /// lower sphere uncovered instead of handing it to its lowest ring).
  CappedVoronoi,
  /// Given in the lights file, one solid angle per light.
  Given,
};

/// Most lights a light set may hold (files are refused above it before any
/// allocation; light stages hold hundreds to a few thousand).
inline constexpr int kMaxLights = 1 << 16;

struct LightSet {
  std::vector<Vec3> directions;             ///< unit
  std::vector<double> solidAngles;          ///< steradians, one per light
  std::vector<Eigen::Vector3d> irradiance;  ///< E_k per channel (the rows are divided by it)
  CellSource cells = CellSource::CappedVoronoi;
  double capDegrees = 0;  ///< CappedVoronoi only

  int size() const { return static_cast<int>(directions.size()); }
  bool empty() const { return directions.empty(); }
  /// 4 pi less the cells' solid angles: the directions no light stands for.
  double uncoveredSolidAngle() const;
  /// "331 lights, spherical Voronoi cells capped at 24 degrees" (for info).
  std::string describe() const;
  /// Throws UserError naming `context` when sizes or values are wrong.
  void validate(const std::string& context) const;
};

/// Two lights closer than this (radians) are one direction given twice.
inline constexpr double kSameDirection = 1e-6;

/// The first pair of unit directions closer than kSameDirection (indices,
/// the lower first; by the later of the pair), or {-1, -1}.
std::pair<int, int> findSameDirection(const std::vector<Vec3>& directions);

/// The default cap of the cells: the largest angle from any light to its
/// nearest neighbour. A full-sphere rig's cells all lie within it (a
/// Voronoi cell's farthest point is nearer than the next light), while a
/// dome's lowest ring reaches at most one spacing below itself.
double defaultCellCapDegrees(const std::vector<Vec3>& directions);

/// The lattice resolution cells are found on: texels about a quarter of a
/// typical cell's radius across (114.6 / sqrt(lights) degrees), so that a
/// texel split between cells is rare and small, in steps of 16 from 32 to
/// 256 (64 for 331 lights). Integrating a map costs with the texels.
int cellLatticeResolution(int lights);
/// cellLatticeResolution's bounds and step: R rounded up to a multiple of
/// kCellLatticeStep within kMinCellLattice .. kMaxCellLattice.
inline constexpr int kCellLatticeStep = 16, kMinCellLattice = 32, kMaxCellLattice = 256;
/// A light set's parts: enough for this many samples along a face's side.
inline constexpr int kCellSamplesPerFaceSide = 512;

/// Where each part of the sphere belongs: every texel of a fine cube lattice,
/// split into sub x sub parts of exact solid angle, goes to the nearest light
/// (largest cosine; ties to the lower index) when that light is within the
/// cap, else to no cell. Integrating lighting onto the cells is then the
/// lattice's exact per-texel integral shared out by these fractions, so the
/// cells and the uncovered rest sum to 4 pi to rounding.
class LightCells {
 public:
  /// One texel's share of one cell: the fraction of the texel's solid angle.
  struct Share {
    int cell = 0;
    double fraction = 0;
  };

  /// capDegrees <= 0 or >= 180: uncapped. latticeResolution 0: cellLattice's
  /// for the number of lights; sub 0: enough parts for kCellSamplesPerFaceSide
  /// samples a face side.
  LightCells(const std::vector<Vec3>& directions, double capDegrees, int latticeResolution = 0,
             int sub = 0);

  const CubeLattice& lattice() const { return lattice_; }
  int cells() const { return cells_; }
  /// The shares of texel j (those of no cell are left out).
  const Share* begin(int texel) const { return shares_.data() + start_[texel]; }
  const Share* end(int texel) const { return shares_.data() + start_[texel + 1]; }
  /// Solid angle of each cell.
  std::vector<double> solidAngles() const;
  /// Sums per-texel values of the fine lattice onto the cells: out[k * stride + c]
  /// += sum over texels j of share(j, k) * texelValues[j * stride + c].
  void gather(const std::vector<double>& texelValues, int stride, std::vector<double>& out) const;

 private:
  CubeLattice lattice_;
  int cells_;
  std::vector<int> start_;  ///< per texel, into shares_ (size texels + 1)
  std::vector<Share> shares_;
};

}  // namespace acpca
