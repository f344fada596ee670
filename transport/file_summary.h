#pragma once
// A transport file read for what `info` reports: its attributes and the
// shapes of its datasets, none of its arrays (docs/formats.md). Milliseconds
// at any size, where the whole header of a 1024x1024 transport is 50 MB.
#include <string>

#include "transport/transport_file.h"

namespace acpca {

/// What a file's per-pixel datasets hold, known from their shapes alone
/// (`info` reports it without reading them).
struct PixelDatasets {
  long long rows = 0;
  bool normals = false, positions = false, objects = false;
  bool lamps = false;     ///< the lamp samples and surfaces (transport/lamp_geometry.h)
  bool tangents = false;  ///< the lamp samples' tangents (transport 6, model 8)
  /// The scene's materials by geometry (lamp_materials; albedo unused):
  /// what `info` prints. Empty without lamp geometry.
  std::vector<Material> materials;
  /// Those of a header whose arrays were read.
  static PixelDatasets of(const TransportHeader& header);
};

/// A transport file's attributes and shapes, its per-pixel datasets and rows
/// left unread: what `info` reports, read in milliseconds at any size.
struct TransportSummary {
  TransportHeader header;  ///< attributes only: its per-pixel arrays are empty
  PixelDatasets pixels;
  long long fileBytes = -1;
};

/// Checks the file as TransportReader does, but for the values of its arrays.
TransportSummary readTransportSummary(const std::string& path);

}  // namespace acpca
