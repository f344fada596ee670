#pragma once
// The part of the file header that transport and model files share: image
// size, lattice resolution, scene name, camera, and per occupied pixel its
// index, albedo and coverage (and, in transport files, its normal). One writer
// and one reader, so the two file kinds accept exactly the same geometry.
#include <hdf5.h>

#include <string>

#include "transport/transport_file.h"

namespace acpca {

/// Writes the shared attributes and per-pixel datasets; "normal", "position"
/// and "object" (with the attribute "object_names") are written when the
/// header holds them (transport version 3 and model version 5 hold all three).
void writeImageHeader(hid_t file, const TransportHeader& header, const std::string& context);

/// Reads what writeImageHeader wrote, checking every size against the image
/// before allocating. Normals, positions and objects are left empty when the
/// file has none (older files); `requireNormals` (transports) refuses a file
/// without normals. Leaves the transport-only fields (samples, texel rays,
/// precision) at their defaults. Throws UserError naming `context` (the file)
/// and the field.
TransportHeader readImageHeader(hid_t file, bool requireNormals, const std::string& context);

}  // namespace acpca
