#pragma once
// The sRGB transfer function (IEC 61966-2-1) both ways: textures and captured
// images are decoded with it, PNG output encodes with it.

namespace acpca {

/// Encoded value of a linear one in [0, 1] (clamped).
double linearToSrgb(double v);
/// Linear value of an encoded one in [0, 1] (clamped).
double srgbToLinear(double encoded);

}  // namespace acpca
