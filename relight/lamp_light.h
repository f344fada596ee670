#pragma once
// Lamps lit exactly (docs/lighting.md, "Lamps"): at each traced camera
// sample of a pixel, shadow rays to the lamp through the file's surfaces
// (one to a point or spot lamp, over the cap of a sphere lamp where a
// penumbra may fall: relight/sphere_lamp.h), the lamp's irradiance and the
// sample's BRDF, as the precompute would have traced the lamp itself. The
// lattice path (relight/local_relight.h) is what files without lamp
// geometry and files with bounced light still take.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "lighting/local_light.h"
#include "lighting/map_sources.h"
#include "occlusion/scene_occluder.h"
#include "transport/transport_file.h"

namespace acpca {

/// How lamps are lit: exactly where the file allows it (else through the
/// lattice, with a warning), or through the lattice always.
enum class LampMode { Exact, Lattice };
inline constexpr EnumNames<LampMode, 2> kLampModeNames{
    "light mode", {{{LampMode::Exact, "exact"}, {LampMode::Lattice, "lattice"}}}};

/// A sphere lamp's shadow rays per camera sample in a penumbra: by default,
/// and the squares it may be (n x n strata, n from 2 to 16).
inline constexpr int kDefaultSphereLampRays = 64;
inline constexpr int kMaxSphereLampRays = 256;

/// A distant disc narrower than this (radians: 0.0115 degrees across) casts
/// no penumbra wider than 1e-4 of its occluder's distance, and is lit as a
/// point at infinity of its power: one shadow ray a sample, no probes.
inline constexpr double kPointDiscRadius = 1e-4;

/// How lamps are lit: the mode, and a sphere lamp's rays in a penumbra.
struct LampSettings {
  LampSettings(LampMode mode = LampMode::Exact, int sphereRays = kDefaultSphereLampRays)
      : mode(mode), sphereRays(sphereRays) {}
  LampMode mode;
  int sphereRays;
};

/// Reads --lamp-rays: a square from 4 to 256. Throws ParameterError ("lamp
/// rays") naming the text otherwise.
int parseSphereLampRays(const std::string& text);

/// Why the file's lamps cannot be lit exactly, in words with what to run
/// again (`model` picks the advice); empty when they can.
std::string exactLampsUnavailable(const TransportHeader& header, bool model);

/// The warning a file whose lamps go through the lattice gets, once: its
/// path and `why` (exactLampsUnavailable's words).
std::string latticeLampsWarning(const std::string& path, const std::string& why);

/// The exact lamps of one file: its surfaces in a shadow-ray scene, built on
/// first use and kept for the next frames.
class ExactLamps {
 public:
  /// `header` must outlive this and hold lamp geometry.
  explicit ExactLamps(const TransportHeader& header) : header_(header) {}
  /// Per occupied row RGB (rows x 3, albedo applied) under `lights`: each
  /// traced sample adds weight x I / d^2 (x a spot's falloff) x cos x
  /// f/albedo where its shadow ray reaches a point or spot lamp, and a
  /// sphere lamp's L x f/albedo x cos over the part of its cap the sample's
  /// rays reach. Parallel over rows; the same values for any thread count.
  /// `sphereRays`: a sphere lamp's rays per sample in a penumbra (a square).
  /// `discs`: distant discs (a map's sources), lit as sphere lamps at
  /// infinity: L x f/albedo x cos over the part of the cap the rays reach;
  /// below kPointDiscRadius, as points of their power (L x solid angle).
  std::vector<float> relight(const std::vector<LocalLight>& lights,
                             int sphereRays = kDefaultSphereLampRays,
                             const std::vector<MapSource>& discs = {}) const;
  /// The shadow rays traced so far, by every call.
  long long shadowRays() const { return rays_; }

 private:
  const TransportHeader& header_;
  mutable std::once_flag built_;
  mutable std::unique_ptr<SceneOccluder> occluder_;
  mutable std::atomic<long long> rays_{0};
};

/// The rows (rows x 3) of all of `lights`: exactly when the settings' mode
/// and the file allow (`exact` non-null), else through `lattice`. `warnOnce` is called once per
/// file with why its lamps went through the lattice.
std::vector<float> relightLocalLights(
    const std::vector<LocalLight>& lights, const LampSettings& settings, const ExactLamps* exact,
    const std::function<std::vector<float>(const std::vector<LocalLight>&)>& lattice,
    const std::function<void()>& warnOnce);

}  // namespace acpca
