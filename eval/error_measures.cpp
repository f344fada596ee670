#include "eval/error_measures.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "core/error.h"

namespace acpca {

double psnr(const std::vector<float>& b, const std::vector<float>& reference) {
  double diff = 0, peak = 0;
  for (size_t i = 0; i < b.size(); ++i) {
    diff += (double(b[i]) - reference[i]) * (double(b[i]) - reference[i]);
    peak = std::max(peak, double(reference[i]));
  }
  const double rmse = std::sqrt(diff / std::max<size_t>(1, b.size()));
  return rmse > 0 ? 20 * std::log10(peak / rmse) : INFINITY;
}

double aggregateError(const std::vector<double>& perMap) {
  double sum = 0;
  for (double e : perMap) sum += e * e;
  return perMap.empty() ? 0 : std::sqrt(sum / perMap.size());
}

double costAtError(std::vector<ErrorCostPoint> points, double target) {
  std::sort(points.begin(), points.end(), [](const auto& a, const auto& b) {
    return a.error < b.error || (a.error == b.error && a.cost < b.cost);
  });
  // Pareto front: a setting counts only if it is cheaper than every setting that
  // is more accurate. Along the front, error rises as cost falls.
  std::vector<ErrorCostPoint> front;
  for (const auto& p : points)
    if (p.error > 0 && p.cost > 0 && (front.empty() || p.cost < front.back().cost))
      front.push_back(p);
  for (size_t i = 0; i + 1 < front.size(); ++i) {
    const auto& lo = front[i];      // smaller error, larger cost
    const auto& hi = front[i + 1];  // larger error, smaller cost
    if (lo.error <= target && target <= hi.error) {
      const double t =
          (std::log(target) - std::log(lo.error)) / (std::log(hi.error) - std::log(lo.error));
      return std::exp(std::log(lo.cost) + t * (std::log(hi.cost) - std::log(lo.cost)));
    }
  }
  if (front.size() == 1 && front[0].error == target) return front[0].cost;
  return -1;
}

double costBoundAtError(const std::vector<ErrorCostPoint>& points, double target) {
  double bound = -1;
  for (const auto& p : points)
    if (p.error > 0 && p.error <= target && p.cost > 0 && (bound < 0 || p.cost < bound))
      bound = p.cost;
  return bound;
}

std::vector<std::string> hdriSearchPath() {
  std::vector<std::string> dirs;
  const char* path = std::getenv("ACPCA_HDRI_PATH");
  if (!path) return {"/usr/share/blender/datafiles/studiolights/world"};
  std::string dir;
  for (const char* c = path;; ++c) {
    if (*c == ':' || *c == 0) {
      if (!dir.empty()) dirs.push_back(dir);
      dir.clear();
      if (*c == 0) break;
    } else {
      dir += *c;
    }
  }
  return dirs;
}

std::vector<std::string> defaultEvaluationSet() {
  std::vector<std::string> set{"sky", "sun:50,30,4,1000"};
  for (const auto& dir : hdriSearchPath()) {
    std::vector<std::string> maps;
    std::error_code ec;
    for (const auto& e : std::filesystem::directory_iterator(dir, ec))
      if (e.path().extension() == ".exr" || e.path().extension() == ".hdr")
        maps.push_back(e.path().string());
    std::sort(maps.begin(), maps.end());
    for (const auto& m : maps)
      if (set.size() < 5) set.push_back(m);
  }
  return set;
}

}  // namespace acpca
