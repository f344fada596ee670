#pragma once
// The files of an `eval` report (CSV, JSON, summary.md) and the plots, drawn
// by eval/plot_report.py with Debian's python3-matplotlib.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/table.h"
#include "eval/method_sweep.h"

namespace acpca {

/// Pictures of one method's most accurate setting, paths relative to the report.
struct ReportPicture {
  std::string method, setting;
  std::string relit{}, error{}, clusters{};  ///< clusters empty for unclustered methods
};

struct EvalReport {
  std::string input;
  std::vector<std::string> envs;
  std::vector<SweepResult> results;
  std::vector<ReportPicture> pictures;
  double seconds = 0;
};

nlohmann::json evalReportJson(const EvalReport& report);
/// results.csv (a row per method, setting and map), settings.csv (a row per
/// setting, aggregated), results.json, the plots and summary.md, in dir.
void writeEvalReport(const EvalReport& report, const std::string& dir);

/// Runs tools/plot_report.py KIND DIR with the interpreter that has matplotlib;
/// returns "" on success, else why no plot was drawn (the report says so).
std::string drawPlots(const std::string& kind, const std::string& dir);

}  // namespace acpca
