#pragma once
// The part of the file header that transport and model files share: image
// size, lattice resolution, scene name, camera, and per occupied pixel its
// index, albedo and coverage (and, in transport files, its normal). One writer
// and one reader, so the two file kinds accept exactly the same geometry.
#include <hdf5.h>

#include <string>

#include "transport/file_summary.h"
#include "transport/transport_file.h"

namespace acpca {

/// Writes the shared attributes and per-pixel datasets; "normal", "position"
/// and "object" (with the attribute "object_names") are written when the
/// header holds them (transport version 3 and model version 5 hold all three).
/// A light set's file has cube map 0, no camera, and the light datasets
/// instead (transport version 4, model version 6).
void writeImageHeader(hid_t file, const TransportHeader& header, const std::string& context);

/// Reads what writeImageHeader wrote, checking every size against the image
/// before allocating. Normals, positions and objects are left empty when the
/// file has none (older files); `requireNormals` (transports) refuses a
/// file of a scene without normals. Leaves the transport-only fields (samples, texel rays,
/// precision) at their defaults. Throws UserError naming `context` (the file)
/// and the field.
TransportHeader readImageHeader(hid_t file, bool requireNormals, const std::string& context);

/// readImageHeader's attributes (object names too) with every dataset's
/// shape checked the same way, but no per-pixel dataset read: the header's
/// arrays stay empty and `datasets` says what the file holds.
TransportHeader readImageHeaderAttributes(hid_t file, bool requireNormals,
                                          const std::string& context, PixelDatasets& datasets);

/// Whether the transport or model file at `path` is over a captured light
/// set (its cube map is 0); false for anything else, unreadable files too
/// (whoever opens it next says what is wrong). Front ends choose defaults by it.
bool fileHoldsLightSet(const std::string& path);

}  // namespace acpca
