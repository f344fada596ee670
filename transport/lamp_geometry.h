#pragma once
// What lights a pixel exactly under a point or spot lamp (docs/lighting.md,
// "Lamps"): each occupied row's traced camera samples (where their shadow
// rays start, how they face, their weight in the row and their material),
// and the scene's surfaces that can shadow them. Transport files from
// version 5 and model files from version 7 hold it; older files, captured
// light sets and scenes of no geometry do not (`empty()`). Tangents and
// anisotropic materials came with transport version 6 and model version 8.
#include <hdf5.h>

#include <cstdint>
#include <string>
#include <vector>

#include "transport/material.h"

namespace acpca {

struct LampGeometry {
  /// rows + 1 offsets: row r's samples are [sampleStart[r], sampleStart[r + 1]).
  std::vector<std::int64_t> sampleStart;
  /// 3 per sample: the hit pushed off along the geometric normal, where the
  /// precompute's shadow rays started from it.
  std::vector<float> origin;
  std::vector<float> normal;           ///< 3 per sample: unit shading normal, facing the camera
  std::vector<float> geometricNormal;  ///< 3 per sample: unit, facing the camera
  /// 3 per sample: unit, across the shading normal, the material's rotation
  /// applied; empty in files from before tangents (all isotropic there).
  std::vector<float> tangent;
  /// Per sample: its share of the row (docs/scenes.md, "Anti-aliasing"; a
  /// row's shares sum to 1).
  std::vector<float> weight;
  std::vector<std::int32_t> material;  ///< per sample: into materials
  std::vector<Material> materials;     ///< the scene's, by geometry (albedo unused)
  /// The surfaces, as the precompute traced them: triangles of vertices
  /// (zero-area ones left out) and spheres (centre, radius).
  std::vector<float> vertices;          ///< 3 per vertex
  std::vector<std::int32_t> triangles;  ///< 3 vertex indices per triangle
  std::vector<float> spheres;           ///< 4 per sphere
  /// Where along a shadow ray the search starts (the precompute's, scene relative).
  float rayEpsilon = 0;

  bool empty() const { return sampleStart.empty(); }
  /// Sample s's tangent (any across its normal where the file has none).
  Vec3 tangentAt(long long s) const;
  long long samples() const { return static_cast<long long>(weight.size()); }
  /// Throws UserError naming `context` when sizes, indices or values disagree.
  void validate(long long rows, const std::string& context) const;
};

/// Writes the lamp datasets (nothing for empty geometry).
void writeLampGeometry(hid_t file, const LampGeometry& lamps, const std::string& context);
/// The scene's materials as the file records them (lamp_materials), read
/// without the rest (the file must hold lamp geometry).
std::vector<Material> readLampMaterials(hid_t file, const std::string& context);
/// Whether the file holds them.
bool hasLampGeometry(hid_t file);
/// Reads them, every shape checked against `rows` before allocating, then
/// validated; empty when the file holds none.
LampGeometry readLampGeometry(hid_t file, long long rows, const std::string& context);

}  // namespace acpca
