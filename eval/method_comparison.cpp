#include "eval/method_comparison.h"

#include <cmath>
#include <cstdio>
#include <map>

#include "core/error.h"
#include "core/text.h"
#include "eval/error_measures.h"

namespace acpca {

Table methodsTable(const std::vector<SweepResult>& rows) {
  Table table({"method", "setting", "global_energy", "tolerance", "clusters", "cost_per_pixel",
               "image_error", "transport_error", "seconds"});
  for (const auto& r : rows)
    table.add({r.method, r.setting, r.globalEnergy, r.tolerance, (long long)r.clusters,
               r.costPerPixel, r.imageError, r.transportError, r.compressSeconds});
  return table;
}

std::string methodComparisonText(const std::vector<SweepResult>& rows,
                                 const std::vector<int>& cpcaClusters) {
  std::map<std::string, std::vector<ErrorCostPoint>> curves;
  for (const auto& r : rows) curves[r.method].push_back({r.imageError, r.costPerPixel});
  for (const auto& r : rows)
    if (r.method == "cpca") curves["cpca " + r.setting].push_back({r.imageError, r.costPerPixel});
  std::string out = formatted("\n%-26s %14s %14s\n", "method", "cost @ 1%", "cost @ 3%");
  std::map<std::string, std::pair<double, double>> atError;
  for (const auto& [method, points] : curves) {
    atError[method] = {costAtError(points, 0.01), costAtError(points, 0.03)};
    out += formatted("%-26s %14.1f %14.1f\n", method.c_str(), atError[method].first,
                     atError[method].second);
  }
  const auto ratio = [&](const std::string& a, const std::string& b, bool onePercent) {
    const double x = onePercent ? atError[a].first : atError[a].second;
    const double y = onePercent ? atError[b].first : atError[b].second;
    return (x > 0 && y > 0) ? x / y : NAN;
  };
  out += "\nratios at equal image error (negative or nan: target outside the sweep)\n";
  for (const char* adaptive : {"adaptive-quad", "adaptive-quad-exact", "adaptive-binary"})
    out += formatted("%-22s / global  : %.3f @1%%  %.3f @3%%\n", adaptive,
                     ratio(adaptive, "global", true), ratio(adaptive, "global", false));
  for (int k : cpcaClusters) {
    const std::string c = concat("cpca K=", k);
    out += formatted("%-22s / adaptive-binary: %.3f @1%%  %.3f @3%%\n", c.c_str(),
                     ratio(c, "adaptive-binary", true), ratio(c, "adaptive-binary", false));
  }
  // adaptive-binary against CPCA with the same number of clusters, setting by setting.
  for (size_t i = 0; i < rows.size(); ++i)
    if (rows[i].method == "adaptive-binary")
      for (size_t j = i + 1; j < rows.size(); ++j)
        if (rows[j].method == "cpca" && rows[j].globalEnergy == rows[i].globalEnergy &&
            rows[j].tolerance == rows[i].tolerance &&
            rows[j].setting == concat("K=", rows[i].clusters))
          out += formatted(
              "adaptive-binary / cpca K=%d (g=%g tol=%g): cost %.1f / %.1f = %.3f, image error "
              "%.4f vs %.4f\n",
              rows[i].clusters, rows[i].globalEnergy, rows[i].tolerance, rows[i].costPerPixel,
              rows[j].costPerPixel, rows[i].costPerPixel / rows[j].costPerPixel, rows[i].imageError,
              rows[j].imageError);
  return out;
}

}  // namespace acpca
