#pragma once
// Light directions for the captured-transport suites: n points spread evenly
// over the sphere, as a light stage spreads its lamps.
#include <Eigen/Core>
#include <cmath>
#include <numbers>
#include <vector>

namespace acpca::test {

/// n unit directions on the golden-angle spiral, from near +Y down to near -Y.
inline std::vector<Eigen::Vector3d> goldenSpiral(int n) {
  std::vector<Eigen::Vector3d> d;
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double y = 1 - 2 * (i + 0.5) / n, r = std::sqrt(1 - y * y);
    d.emplace_back(r * std::cos(golden * i), y, r * std::sin(golden * i));
  }
  return d;
}

}  // namespace acpca::test
