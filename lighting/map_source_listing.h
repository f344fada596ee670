#pragma once
// A map's sources (lighting/map_sources.h) in a frame: turned with its
// rotation, and listed as reports, manifests and frame headers give them
// (docs/formats.md, "Batch manifest").
#include <array>
#include <nlohmann/json.hpp>
#include <vector>

#include "lighting/map_sources.h"
#include "lighting/rotation.h"

namespace acpca {

/// The sources turned as the map is under `rotation`.
std::vector<MapSource> turnedSources(const std::vector<MapSource>& sources,
                                     const EnvRotation& rotation);

/// Each source's direction, THETA and PHI as `sun:` takes them, angular
/// radius in degrees, RGB radiance and share of its map's energy.
nlohmann::json sourcesJson(const std::vector<MapSource>& sources);

/// A frame's lighting label (docs/formats.md, "Batch manifest"): the nine
/// RGB coefficients of its lattice's lighting plus its sources' (projectDisc).
nlohmann::json sh9Json(const std::array<Rgb, 9>& lattice, const std::vector<MapSource>& sources);

}  // namespace acpca
