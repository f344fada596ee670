#pragma once
// The part of the file header that transport and model files share: image
// size, lattice resolution, scene name, camera, and per occupied pixel its
// index, albedo and coverage (and, in transport files, its normal). One writer
// and one reader, so the two file kinds accept exactly the same geometry.
#include <hdf5.h>

#include <string>

#include "transport/transport_file.h"

namespace acpca {

/// Writes the shared attributes and per-pixel datasets; `withNormals` adds the
/// "normal" dataset (transport files); "position" is written when the header
/// holds positions (both kinds, from transport version 2 and model version 4).
void writeImageHeader(hid_t file, const TransportHeader& header, bool withNormals,
                      const std::string& context);

/// Reads what writeImageHeader wrote, checking every size against the image
/// before allocating; without normals they are set to zero, and positions are
/// left empty when the file has none (older files). Leaves the
/// transport-only fields (samples, texel rays, precision) at their defaults.
/// Throws UserError naming `context` (the file) and the field.
TransportHeader readImageHeader(hid_t file, bool withNormals, const std::string& context);

}  // namespace acpca
