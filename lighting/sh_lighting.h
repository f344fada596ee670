#pragma once
// Lighting labels for datasets: the first nine spherical-harmonic
// coefficients of the radiance a lattice lighting holds (docs/formats.md,
// "Batch manifest"). The radiance is piecewise constant, texel by texel, so
// each coefficient is exact up to the quadrature of Y over each texel.
#include <array>
#include <vector>

#include "lighting/domain_lighting.h"
#include "lighting/environment.h"
#include "lighting/map_sources.h"
#include "transport/cube_lattice.h"

namespace acpca {

/// The bands' normalisations: sqrt(1 / 4 pi), sqrt(3 / 4 pi), sqrt(15 / 4 pi),
/// sqrt(5 / 16 pi), sqrt(15 / 16 pi); realSh9 is c0, c1 y, c1 z, c1 x, c2 x y,
/// c2 y z, c3 (3 z^2 - 1), c2 x z, c4 (x^2 - y^2).
inline constexpr std::array<double, 5> kSh9Normalisations{0.28209479177387814, 0.4886025119029199,
                                                          1.0925484305920792, 0.31539156525252005,
                                                          0.5462742152960396};

/// Real orthonormal spherical harmonics of bands 0 to 2 at the unit direction
/// d, in the order (0,0), (1,-1), (1,0), (1,1), (2,-2), (2,-1), (2,0), (2,1),
/// (2,2), the usual polynomials in x, y, z taken in our world axes (+Y up):
/// Y(1,-1) ~ y, Y(1,0) ~ z, Y(1,1) ~ x, Y(2,0) ~ 3 z^2 - 1.
std::array<double, 9> realSh9(const Vec3& d);

/// A distant disc's nine coefficients in closed form (Funk-Hecke): L Y(d)
/// times the cap's integral of the band's Legendre polynomial, 2 pi (1 - cos
/// a), pi sin^2 a and pi cos a sin^2 a for bands 0, 1 and 2: what a map's
/// source adds to its lattice's coefficients.
std::array<Rgb, 9> projectDisc(const MapSource& disc);

/// Per texel of `lattice`, the mean of each realSh9 band over it (16 x 16
/// cells of exact solid angle). threads false: on the calling thread alone
/// (where TBB may not start threads: a forked Python DataLoader worker).
std::vector<std::array<double, 9>> texelSh9Means(const CubeLattice& lattice, bool threads = true);

/// Projects lattice lightings onto realSh9: per band the integral of the
/// lattice's radiance (each texel's lighting over its solid angle) times Y.
class ShProjector {
 public:
  explicit ShProjector(const CubeLattice& lattice);
  /// A file's domain: its lattice, or a captured light set's cells (the
  /// lighting of each taken as uniform over the cell, as for a texel).
  explicit ShProjector(const DomainLighting& domain);
  /// Nine RGB coefficients: constant radiance 1 gives 2 sqrt(pi) for (0,0).
  std::array<Rgb, 9> project(const LatticeLighting& lighting) const;

 private:
  /// Per texel, the mean of each Y over the texel (16 x 16 cells of exact
  /// solid angle).
  std::vector<std::array<double, 9>> meanY_;
};

}  // namespace acpca
