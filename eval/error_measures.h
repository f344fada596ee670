#pragma once
// Error measures over an evaluation set and equal-error comparison (docs/design.md
// section 7). relativeL2 and median live in core/statistics.h.
#include <string>
#include <vector>

#include "core/statistics.h"

namespace acpca {

/// 20 log10(max ref / RMSE).
double psnr(const std::vector<float>& b, const std::vector<float>& reference);
/// RMS of per-map relative L2 errors: the aggregate over an evaluation set.
double aggregateError(const std::vector<double>& perMap);

/// One setting of a method: its aggregate image error and its cost.
struct ErrorCostPoint {
  double error = 0;
  double cost = 0;
};
/// Cost of reaching `targetError`, interpolating the method's Pareto front
/// (cheapest cost for at most a given error) linearly in log-log between the
/// two settings that bracket the target. Negative when no two settings bracket it.
double costAtError(std::vector<ErrorCostPoint> points, double targetError);
/// When no two settings bracket the target but some are already more accurate:
/// the cost of the cheapest of those, an upper bound on the cost of reaching
/// the target (the method gets there at most that dear). Negative otherwise.
double costBoundAtError(const std::vector<ErrorCostPoint>& points, double targetError);

/// Where the evaluation set's HDRIs are looked for: the directories of
/// $ACPCA_HDRI_PATH (colon-separated) when set, else the world maps of Debian's
/// blender-data (/usr/share/blender/datafiles/studiolights/world).
std::vector<std::string> hdriSearchPath();

/// The default evaluation set: sky, sun:50,30,4,1000, and the first three
/// .exr/.hdr maps (by name) found along hdriSearchPath().
std::vector<std::string> defaultEvaluationSet();

}  // namespace acpca
