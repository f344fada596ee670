#pragma once
// The horizontal cube cross (4:3) that `envmap --cross` writes and `--env`
// reads, laid out as seen from inside:
//          +Y
//     -X   -Z   +X   +Z
//          -Y
// so that the middle row runs with the lat-long's u (u = 0.25 is -X) and
// every shared edge is continuous.
#include <array>

#include "transport/cube_lattice.h"

namespace acpca {

/// One face of the cross: its grid cell and its frame (centre, and the
/// directions of increasing x and y within it).
struct CrossFace {
  int column, row;
  Vec3 centre, right, down;
};
extern const std::array<CrossFace, 6> kCrossFaces;

/// Direction of cross pixel centre (x, y); false where the cross has no face.
bool crossDirection(int x, int y, int faceSize, Vec3& direction);

}  // namespace acpca
