#pragma once
// What the penumbra tests share (sphere lamps, distant discs): a floor's
// lit share by image column, where it crosses a level, and the closed form
// of a disc cut by a straight edge.
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numbers>
#include <utility>
#include <vector>

#include "transport/transport_file.h"

namespace acpca::test {

/// (floor x, lit share) per image column, ascending in x.
using ShareProfile = std::vector<std::pair<double, double>>;

/// Each column's mean of rows / whole(position) over the floor's rows with
/// |z| < maxZ (y < 0.5: not what stands on it), against the column's x.
inline ShareProfile floorColumnProfile(const TransportHeader& h, const std::vector<float>& rows,
                                       double maxZ,
                                       const std::function<double(const Vec3&)>& whole) {
  std::map<int, std::pair<double, int>> columns;  // column -> (share sum, count)
  std::map<int, double> xOfColumn;
  const int width = h.camera.size.width;
  for (long long r = 0; r < h.rows(); ++r) {
    const Vec3 p(h.positions[3 * r], h.positions[3 * r + 1], h.positions[3 * r + 2]);
    if (std::abs(p.z()) > maxZ || p.y() > 0.5) continue;
    auto& [sum, count] = columns[h.pixels[r] % width];
    sum += rows[3 * r] / whole(p), ++count;
    xOfColumn[h.pixels[r] % width] = p.x();
  }
  ShareProfile profile;
  for (const auto& [column, sc] : columns)
    profile.push_back({xOfColumn[column], sc.first / sc.second});
  std::sort(profile.begin(), profile.end());
  return profile;
}

/// The first x where a rising profile passes `share`, between columns.
inline double profileCrossing(const ShareProfile& profile, double share) {
  for (size_t i = 1; i < profile.size(); ++i)
    if (profile[i].second >= share) {
      const auto [x0, s0] = profile[i - 1];
      const auto [x1, s1] = profile[i];
      return x0 + (share - s0) / (s1 - s0) * (x1 - x0);
    }
  return profile.back().first;
}

/// The visible share of a disc cut by a line at signed distance t radii from
/// its centre (t > 0: the centre on the visible side): 1 - segment / disc.
inline double visibleShare(double t) {
  t = std::clamp(t, -1.0, 1.0);
  return 1 - (std::acos(t) - t * std::sqrt(1 - t * t)) / std::numbers::pi;
}

/// Where a share rising with x in [lo, hi] passes `level`, by bisection.
inline double risingCrossing(const std::function<double(double)>& share, double level, double lo,
                             double hi) {
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (share(mid) < level ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace acpca::test
