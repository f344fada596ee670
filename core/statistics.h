#pragma once
// Small statistics every library and test uses: the median of timings and the
// relative L2 distance between two images (or any two value arrays).
#include <vector>

namespace acpca {

/// sqrt(sum (b - ref)^2 / sum ref^2) over all values (occupied pixels x RGB).
double relativeL2(const std::vector<float>& b, const std::vector<float>& reference);
/// The middle value (the upper one of an even count); 0 when empty.
double median(std::vector<double> values);

}  // namespace acpca
