#include "eval/method_comparison.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
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

namespace {

/// A method's cost at a target error: interpolated between two bracketing
/// settings, or a bound ("<= x": every setting reaching it is more accurate),
/// or unknown (value < 0: no setting reaches the target).
struct CostAt {
  double value = -1;
  bool bound = false;
};

CostAt costAt(const std::vector<ErrorCostPoint>& points, double target) {
  if (const double c = costAtError(points, target); c > 0) return {c, false};
  if (const double b = costBoundAtError(points, target); b > 0) return {b, true};
  return {};
}

std::string text(const CostAt& c, const char* format) {
  if (c.value <= 0) return "-";
  return (c.bound ? "<= " : "") + formatted(format, c.value);
}

/// a / b: exact when both are, a bound when only a is one (b exact), else "-".
std::string ratioText(const CostAt& a, const CostAt& b) {
  if (a.value <= 0 || b.value <= 0 || b.bound) return "-";
  return text({a.value / b.value, a.bound}, "%.3f");
}

}  // namespace

std::string methodComparisonText(const std::vector<SweepResult>& rows,
                                 const std::vector<int>& cpcaClusters) {
  std::map<std::string, std::vector<ErrorCostPoint>> curves;
  for (const auto& r : rows) curves[r.method].push_back({r.imageError, r.costPerPixel});
  for (const auto& r : rows)
    if (r.method == "cpca") curves["cpca " + r.setting].push_back({r.imageError, r.costPerPixel});
  std::string out = formatted("\n%-26s %14s %14s\n", "method", "cost @ 1%", "cost @ 3%");
  std::map<std::string, std::pair<CostAt, CostAt>> atError;
  for (const auto& [method, points] : curves) {
    atError[method] = {costAt(points, 0.01), costAt(points, 0.03)};
    out +=
        formatted("%-26s %14s %14s\n", method.c_str(), text(atError[method].first, "%.1f").c_str(),
                  text(atError[method].second, "%.1f").c_str());
  }
  const auto ratio = [&](const std::string& a, const std::string& b, bool onePercent) {
    const auto& x = onePercent ? atError[a].first : atError[a].second;
    const auto& y = onePercent ? atError[b].first : atError[b].second;
    return ratioText(x, y);
  };
  out +=
      "\nratios at equal image error (of the raw reconstruction, before the clamp at zero; "
      "\"<=\": a bound, every setting reaching the target being more accurate; \"-\": no "
      "setting of one of them reaches it)\n";
  for (const char* adaptive : {"adaptive-quad", "adaptive-quad-exact", "adaptive-binary"})
    out += formatted("%-22s / global  : %s @1%%  %s @3%%\n", adaptive,
                     ratio(adaptive, "global", true).c_str(),
                     ratio(adaptive, "global", false).c_str());
  for (int k : cpcaClusters) {
    const std::string c = concat("cpca K=", k);
    out += formatted("%-22s / adaptive-binary: %s @1%%  %s @3%%\n", c.c_str(),
                     ratio(c, "adaptive-binary", true).c_str(),
                     ratio(c, "adaptive-binary", false).c_str());
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

StudyOutput runMethodComparison(const TransportReader& transport,
                                const std::vector<std::string>& envs, SweepSettings settings,
                                const std::string& outDir) {
  const EvaluationData data = loadEvaluationData(transport, envs);
  const std::vector<SweepResult> rows = sweepMethods(data, settings);
  std::filesystem::create_directories(outDir);
  const std::string csv = (std::filesystem::path(outDir) / "methods.csv").string();
  const Table table = methodsTable(rows);
  table.writeCsv(csv);
  return {table.json(),
          methodComparisonText(rows, settings.cpcaClusters) + "\nall settings: " + csv + "\n"};
}

}  // namespace acpca
