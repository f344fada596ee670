#pragma once
// Each subcommand registers itself on the CLI app (one file per subcommand).
#include <CLI/CLI.hpp>

#include "cluster/model.h"

namespace acpca::cli {

void registerPrecompute(CLI::App& app);
void registerCompress(CLI::App& app);
void registerRelight(CLI::App& app);
void registerEnvmap(CLI::App& app);
void registerInfo(CLI::App& app);
void registerScenes(CLI::App& app);
void registerBench(CLI::App& app);
void registerView(CLI::App& app);
void registerEval(CLI::App& app);
void registerAnalyze(CLI::App& app);

/// " n=R:COUNT" for each rank R a model's clusters have.
std::string rankHistogramText(const Model& m);

/// Peak resident memory of this process so far, in bytes.
long long peakMemoryBytes();

}  // namespace acpca::cli
