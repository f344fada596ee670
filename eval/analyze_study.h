#pragma once
// `analyze`: the paper's analyses on a transport file ([Mahajan07] sec. 3-5):
// dimensionality against patch area with log-log slopes, cost against block
// size with the global basis count N, mu and the optimal patch size p* of
// eq. 27 beside the measured optimum.
#include <string>
#include <utility>
#include <vector>

#include "core/study_output.h"
#include "transport/transport_file.h"

namespace acpca {

struct AnalyzeOptions {
  std::vector<std::pair<int, int>> centres;  ///< empty: chosen where patches are richest
  std::vector<int> blocks{2, 4, 8, 16, 32, 64};
  double globalEnergy = 0.999, tolerance = 0.999;
  double energy = 0.9995;  ///< energy that defines a patch's dimensionality
  StudyLog log;
};

void validateAnalyzeOptions(const AnalyzeOptions& options);

/// Writes dimensionality.csv, slopes.csv, block_cost.csv, the plots,
/// summary.md and analysis.json into `outDir`.
StudyOutput runAnalysis(const TransportReader& transport, const AnalyzeOptions& options,
                        const std::string& outDir);

}  // namespace acpca
