#pragma once
// What the lattice sees of a lighting, as pictures: a lat-long image and a
// horizontal cube cross, piecewise constant per texel.
#include "imageio/image_output.h"
#include "lighting/cube_cross.h"
#include "lighting/lighting.h"

namespace acpca {

/// Lat-long image (docs/design.md section 3 mapping) of the lattice radiance,
/// piecewise constant per texel: each texel's lighting spread over the pixels
/// whose centres fall in it, so the image integrates to exactly the lattice's
/// energy (what a renderer lit by it must see; a texel no pixel centre falls
/// in, possible below about 4R x 2R pixels, is lost).
Image latticeToLatLong(const LatticeLighting& lighting, const CubeLattice& lattice, int width,
                       int height);

/// Lat-long image of the lattice radiance: each pixel the radiance of the
/// texel its centre falls in (a constant map stays constant; the image's
/// energy is the lattice's up to that sampling). What a batch's lighting
/// label holds.
Image latticeRadianceToLatLong(const LatticeLighting& lighting, const CubeLattice& lattice,
                               int width, int height);

/// The lattice radiance as a horizontal cross (cube_cross.h), faces of
/// faceSize pixels.
Image latticeToCross(const LatticeLighting& lighting, const CubeLattice& lattice, int faceSize);

}  // namespace acpca
