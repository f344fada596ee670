#pragma once
// The numbers of the built-in maps and of a disc's integration
// (docs/lighting.md, "The built-in `sky`"), named once: the analytic
// environments draw from them, and the Python package's generated contract
// (python/write_contract.cpp) carries them to its pure-Python side.
#include <array>

namespace acpca {

/// The built-in sky's sun: THETA and PHI (degrees, as `sun:` takes them), its
/// angular diameter, and its radiance.
inline constexpr double kSkySunTheta = 35, kSkySunPhi = 60, kSkySunSize = 2;
inline constexpr std::array<double, 3> kSkySunRadiance{2000, 1900, 1700};
/// The sky without its sun: (1 - t) zenith + t horizon + glow with t = (1 -
/// y)^kSkyHorizonPower and glow kSkyGlowStrength exp(-kSkyGlowSharpness (1 -
/// cos angle to the sun)) in kSkyGlowColour; kSkyGround below the horizon.
inline constexpr std::array<double, 3> kSkyZenith{0.16, 0.30, 0.64};
inline constexpr std::array<double, 3> kSkyHorizon{0.60, 0.66, 0.76};
inline constexpr std::array<double, 3> kSkyGround{0.10, 0.09, 0.08};
inline constexpr std::array<double, 3> kSkyGlowColour{1.0, 0.9, 0.7};
inline constexpr double kSkyGlowStrength = 0.5, kSkyGlowSharpness = 40;
inline constexpr int kSkyHorizonPower = 4;
/// The smooth sky is integrated on sub x sub cells of exact area per texel.
inline constexpr int kSkySubCells = 4;

/// A disc is integrated on rings of equal solid angle: kDiscRingsPerTexel
/// rings for each texel its diameter spans, clamped to kMinDiscRings ..
/// kMaxDiscRings, each of twice as many segments.
inline constexpr int kDiscRingsPerTexel = 16, kMinDiscRings = 8, kMaxDiscRings = 512;

/// A map file's pixels are split into sub-cells at most 1/kMapSubCellsPerTexel
/// of a texel across (lat-long maps and cube crosses alike).
inline constexpr int kMapSubCellsPerTexel = 8;
/// Most pixels a map may hold (16k x 16k).
inline constexpr long long kMaxMapPixels = 1LL << 28;

}  // namespace acpca
