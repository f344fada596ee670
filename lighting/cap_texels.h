#pragma once
// The texels a cap of directions (a sphere's or a distant disc's) covers, and
// its share of each.
#include <vector>

#include "lighting/light_kinds.h"
#include "transport/cube_lattice.h"

namespace acpca {

/// The shares of the cap of angular radius asin(sinAlpha) around the unit
/// `axis` in the texels it covers, summing to 1, appended to `taps`: a cap
/// inside one texel is all of it; one up to two texels across is split over
/// a grid of cells about alpha / 12 wide that divides every texel; a larger
/// one texel by texel (whole texels their exact solid angle, rim texels that
/// of the 8x8 sub-cells whose centres are inside). A cap under a microradian
/// is a point: its texel.
void appendCapShares(const CubeLattice& lattice, const Vec3& axis, double sinAlpha,
                     std::vector<LightTap>& taps);

}  // namespace acpca
