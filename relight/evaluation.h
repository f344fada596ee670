#pragma once
// Error measures and equal-error comparison (design.md section 7).
#include <string>
#include <vector>

namespace acpca {

/// sqrt(sum (b - ref)^2 / sum ref^2) over all values (occupied pixels x RGB).
double relativeL2(const std::vector<float>& b, const std::vector<float>& reference);
/// 20 log10(max ref / RMSE).
double psnr(const std::vector<float>& b, const std::vector<float>& reference);
/// The middle value (the upper one of an even count); 0 when empty.
double median(std::vector<double> values);
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

/// The default evaluation set: sky, sun:50,30,4,1000, and (when Debian's
/// blender-data is installed) three of its studio-light HDRIs.
std::vector<std::string> defaultEvaluationSet();

}  // namespace acpca
