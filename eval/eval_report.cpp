#include "eval/eval_report.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/table.h"
#include "eval/error_measures.h"

namespace acpca {

namespace {

namespace fs = std::filesystem;

/// Cost or time at a target error along a method's settings: log-log between
/// the two settings that bracket it (docs/design.md section 7), or, when every
/// setting that reaches it is beyond the sweep's range, at most the cheapest
/// of those (a bound); NAN when no setting reaches it.
struct AtError {
  double value = NAN;
  bool bound = false;
};

AtError atError(const std::vector<SweepResult>& rows, double target, bool time) {
  std::vector<ErrorCostPoint> points;
  for (const auto& r : rows) {
    const double y = time ? r.msPerFrame : r.costPerPixel;
    if (std::isfinite(y) && y > 0 && r.imageError > 0) points.push_back({r.imageError, y});
  }
  if (const double v = costAtError(points, target); v > 0) return {v, false};
  if (const double b = costBoundAtError(points, target); b > 0) return {b, true};
  return {};
}

std::string cell(double v, const char* format = "%.1f") {
  if (!std::isfinite(v)) return "-";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

std::string cell(const AtError& a, const char* format = "%.1f") {
  return (a.bound && std::isfinite(a.value) ? "≤ " : "") + cell(a.value, format);
}

}  // namespace

std::string drawPlots(const std::string& kind, const std::string& dir) {
  // Debian's python3-matplotlib serves Debian's own interpreter, which may not
  // be the python3 first on PATH.
  const char* python = std::getenv("ACPCA_PYTHON");
  const std::string interpreter = python && *python ? python : "/usr/bin/python3";
  const std::string script = ACPCA_PLOT_SCRIPT;
  if (!fs::exists(interpreter)) return concat(interpreter, " is missing");
  if (!fs::exists(script)) return concat(script, " is missing");
  const std::string command =
      concat("'", interpreter, "' '", script, "' ", kind, " '", dir, "' 2>&1");
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return "cannot start the plot script";
  std::string output;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = pclose(pipe);
  return status == 0 ? "" : concat("the plot script failed: ", output);
}

nlohmann::json evalReportJson(const EvalReport& report) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& r : report.results) {
    nlohmann::json perMap = nlohmann::json::array();
    for (size_t k = 0; k < r.errors.size(); ++k)
      perMap.push_back({{"env", report.envs[k]},
                        {"rel_l2", finiteOrNull(r.errors[k])},
                        {"psnr", finiteOrNull(r.psnrs[k])}});
    rows.push_back({{"method", r.method},
                    {"setting", r.setting},
                    {"global_energy", r.globalEnergy},
                    {"tolerance", r.tolerance},
                    {"global_bases", r.globalBases},
                    {"clusters", r.clusters},
                    {"cost_per_pixel", r.costPerPixel},
                    {"model_bytes", r.modelBytes},
                    {"ms_per_frame", finiteOrNull(r.msPerFrame)},
                    {"compress_seconds", r.compressSeconds},
                    {"basis_seconds", r.basisSeconds},
                    {"transport_error", finiteOrNull(r.transportError)},
                    {"image_error", finiteOrNull(r.imageError)},
                    {"maps", perMap}});
  }
  nlohmann::json pictures = nlohmann::json::array();
  for (const auto& p : report.pictures)
    pictures.push_back({{"method", p.method},
                        {"setting", p.setting},
                        {"relit", p.relit},
                        {"error", p.error},
                        {"clusters", p.clusters}});
  return {{"input", report.input},
          {"envs", report.envs},
          {"seconds", report.seconds},
          {"results", rows},
          {"pictures", pictures}};
}

void writeEvalReport(const EvalReport& report, const std::string& dir) {
  const fs::path root(dir);
  Table perMap({"method", "setting", "env", "rel_l2", "psnr", "ms_per_frame", "cost_per_pixel",
                "model_bytes", "global_energy", "tolerance", "clusters", "compress_seconds"});
  Table settings({"method", "setting", "global_energy", "tolerance", "global_bases", "clusters",
                  "image_error", "psnr_mean", "ms_per_frame", "cost_per_pixel", "model_bytes",
                  "transport_error", "compress_seconds", "basis_seconds"});
  for (const auto& r : report.results) {
    double psnrSum = 0;
    for (size_t k = 0; k < r.errors.size(); ++k) {
      perMap.add({r.method, r.setting, report.envs[k], r.errors[k], r.psnrs[k], r.msPerFrame,
                  r.costPerPixel, r.modelBytes, r.globalEnergy, r.tolerance, (long long)r.clusters,
                  r.compressSeconds});
      psnrSum += r.psnrs[k];
    }
    settings.add({r.method, r.setting, r.globalEnergy, r.tolerance, (long long)r.globalBases,
                  (long long)r.clusters, r.imageError,
                  psnrSum / std::max<size_t>(1, r.errors.size()), r.msPerFrame, r.costPerPixel,
                  r.modelBytes, r.transportError, r.compressSeconds, r.basisSeconds});
  }
  perMap.writeCsv((root / "results.csv").string());
  settings.writeCsv((root / "settings.csv").string());
  writeTextFile((root / "results.json").string(), evalReportJson(report).dump(2) + "\n");
  const std::string plotProblem = drawPlots("eval", dir);

  // summary.md: which method wins at which error.
  std::map<std::string, std::vector<SweepResult>> byMethod;
  for (const auto& r : report.results) byMethod[r.method].push_back(r);
  std::ostringstream md;
  md << "# Evaluation of " << report.input << "\n\n"
     << "Lightings (" << report.envs.size() << "):";
  for (const auto& e : report.envs) md << " `" << e << "`";
  md << ". Error is the relative L2 over occupied pixels and RGB against the dense relight, of "
        "the raw reconstruction (before the clamp at zero written frames get), aggregated as "
        "the RMS over the maps; cost is multiply-adds per pixel and channel "
        "(eq. 18); ms per frame is the median after a warm-up, same threads, same run. Values "
        "at 1% and 3% are interpolated in log-log between the two settings of a method that "
        "bracket the target; `≤ x`: every setting of the method that reaches the target is "
        "more accurate, so it gets there at most that dear (x is the cheapest of them); `-`: no "
        "setting reaches it. "
     << report.results.size() << " settings in " << cell(report.seconds, "%.0f") << " s.\n\n";
  md << "| method | settings | best error | cost @ 1% | cost @ 3% | ms @ 1% | ms @ 3% |\n"
     << "|---|---:|---:|---:|---:|---:|---:|\n";
  struct Winner {
    std::string method;
    AtError at{INFINITY, false};
  };
  std::map<std::pair<double, bool>, Winner> winners;
  std::map<std::pair<double, bool>, std::map<std::string, AtError>> values;
  for (const auto& [method, rows] : byMethod) {
    double bestError = INFINITY;
    for (const auto& r : rows) bestError = std::min(bestError, r.imageError);
    md << "| " << method << " | " << rows.size() << " | " << cell(100 * bestError, "%.2f%%");
    for (bool time : {false, true})
      for (double target : {0.01, 0.03}) {
        AtError v = atError(rows, target, time);
        if (method == "dense" && std::isfinite(rows[0].msPerFrame))  // exact at every target
          v = {time ? rows[0].msPerFrame : rows[0].costPerPixel, false};
        values[{target, time}][method] = v;
        // A bound competes with its value: the method is at least that cheap.
        if (std::isfinite(v.value) && v.value < winners[{target, time}].at.value)
          winners[{target, time}] = {method, v};
      }
    const auto& v = values;
    md << " | " << cell(v.at({0.01, false}).at(method)) << " | "
       << cell(v.at({0.03, false}).at(method)) << " | "
       << cell(v.at({0.01, true}).at(method), "%.2f") << " | "
       << cell(v.at({0.03, true}).at(method), "%.2f") << " |\n";
  }
  md << "\n## Who wins\n\n";
  for (double target : {0.01, 0.03})
    for (bool time : {false, true}) {
      const Winner& w = winners[{target, time}];
      md << "- At " << cell(100 * target, "%.0f") << "% error, " << (time ? "fastest" : "cheapest")
         << ": ";
      if (w.method.empty()) {
        md << "no method's settings bracket this error.\n";
        continue;
      }
      md << "**" << w.method << "** (" << (w.at.bound ? "at most " : "")
         << cell(w.at.value, time ? "%.2f ms" : "%.1f per pixel") << ")";
      for (const char* other : {"global", "dense"}) {
        const auto& m = values[{target, time}];
        // Against an exact figure a bound gives "at least"; bound against bound says nothing.
        if (w.method == other || !m.count(other) || !std::isfinite(m.at(other).value) ||
            m.at(other).bound)
          continue;
        md << ", " << (w.at.bound ? "at least " : "")
           << cell(m.at(other).value / w.at.value, "%.1f") << "x less than " << other;
      }
      md << ".\n";
    }
  md << "\nThe 6x32x32 lattice itself differs from a full-resolution map by about 1-3% in the "
        "relit image (adaptive-cpca's docs/design.md, section 7), so compression error well below "
        "1% buys little.\n";
  md << "\n## Plots\n\n";
  if (plotProblem.empty())
    md << "![error vs ms per frame](error_vs_ms.png)\n\n![error vs cost per "
          "pixel](error_vs_cost.png)\n";
  else
    md << "No plots: " << plotProblem << "\n";
  md << "\n## Pictures (first map, most accurate setting of each method)\n\n"
     << "Ground truth: ![truth](images/truth.png)\n\n"
     << "| method | setting | relit | error (0..10% of the RMS pixel) | clusters |\n"
     << "|---|---|---|---|---|\n";
  for (const auto& p : report.pictures)
    md << "| " << p.method << " | " << p.setting << " | ![](" << p.relit << ") | ![](" << p.error
       << ") | " << (p.clusters.empty() ? std::string("-") : "![](" + p.clusters + ")") << " |\n";
  md << "\nEvery number: settings.csv (a row per setting), results.csv (a row per setting and "
        "map), results.json.\n";
  writeTextFile((root / "summary.md").string(), md.str());
}

}  // namespace acpca
