#pragma once
// `bench methods`' verdict: each method's cost at 1% and 3% image error
// (interpolated along its Pareto front), the adaptive methods against global
// PCA, CPCA against adaptive-binary, and adaptive-binary against CPCA with as
// many clusters (the paper's comparison).
#include <string>
#include <vector>

#include "core/study_output.h"
#include "core/table.h"
#include "eval/method_sweep.h"

namespace acpca {

/// A row per setting: method, setting, global_energy, tolerance, clusters,
/// cost_per_pixel, image_error, transport_error, seconds (methods.csv).
Table methodsTable(const std::vector<SweepResult>& rows);

/// The comparison as plain text, ready to print; `cpcaClusters` are the CPCA
/// cluster counts to set against adaptive-binary.
std::string methodComparisonText(const std::vector<SweepResult>& rows,
                                 const std::vector<int>& cpcaClusters);

/// `bench methods`: sweeps settings.methods (all when empty) over the
/// transport under `envs` (the evaluation set when empty), writes
/// OUT/methods.csv; the rows as JSON, the comparison as the summary.
StudyOutput runMethodComparison(const TransportReader& transport,
                                const std::vector<std::string>& envs, SweepSettings settings,
                                const std::string& outDir);

}  // namespace acpca
