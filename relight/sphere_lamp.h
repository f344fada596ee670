#pragma once
// Sphere lamps and distant discs (a map's sun) lit exactly (docs/lighting.md,
// "Lamps" and "A map's sources"): each traced camera sample sees the lamp as
// a cap of directions, and its light is the BRDF
// times the cosine over the part of the cap its shadow rays reach. Rays go
// where the penumbra is: one probe per sample first, interleaved over 3x3
// pixels so that a neighbourhood's nine probes cover the disc; a pixel
// whose neighbourhood saw all of its probes reach the lamp (or none) is
// lit whole (or not at all) without more rays, and the rest trace a
// stratified set over the cap.
#include <atomic>
#include <cstdint>
#include <vector>

#include "lighting/local_light.h"
#include "lighting/map_sources.h"
#include "occlusion/scene_occluder.h"
#include "transport/transport_file.h"

namespace acpca {

/// What shadow rays aim at: a sphere lamp, whose cap narrows with distance,
/// or a distant disc, the same cap from every point (a sphere at infinity:
/// no 1/d^2, and nothing beyond the scene casts a shadow).
struct CapLamp {
  static CapLamp sphere(const LocalLight& lamp, const SphereLight& shape);
  static CapLamp distant(const MapSource& disc);
  Vec3 centre = Vec3::Zero();  ///< the sphere's centre, or the unit direction to the disc
  double radius = 0;           ///< the sphere's, or the disc's angular radius (radians)
  bool atInfinity = false;
  Rgb radiance = Rgb::Zero();  ///< uniform over the cap
};

/// What a row's 3x3 pixel neighbourhood saw of a lamp by its probes.
enum class LampSight : std::uint8_t { Hidden, Whole, Partly };

/// One probe per sample (the cap's point its pixel's place in a 3x3 tile
/// picks) and, per row, what its neighbourhood's probes saw; the probes
/// traced are added to `rays`. Parallel; the same for any thread count.
std::vector<LampSight> sphereLampSight(const TransportHeader& header, const SceneOccluder& occluder,
                                       const CapLamp& lamp, std::atomic<long long>& rays);

/// One sphere lamp's (or distant disc's) light on rows [first, end), added to acc[row - first]
/// (albedo not applied), returning the rays it traced: per sample L x the integral of f/albedo x
/// cos over the cap, in closed form for a diffuse sample seeing the whole cap above its horizons,
/// else over `rays` strata (an n x n grid of the square, jittered, mapped onto the cap and turned
/// by an angle seeded by the sample's index), each traced where the row's sight is Partly.
long long addSphereLamp(const TransportHeader& header, const SceneOccluder& occluder,
                        const CapLamp& lamp, const std::vector<LampSight>& sight, int rays,
                        long long first, long long end, std::vector<Rgb>& acc);

}  // namespace acpca
