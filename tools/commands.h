#pragma once
// Each subcommand registers itself on the CLI app (one file per subcommand).
#include <CLI/CLI.hpp>

namespace acpca::cli {

void registerPrecompute(CLI::App& app);
void registerCompress(CLI::App& app);
void registerBuild(CLI::App& app);
void registerRelight(CLI::App& app);
void registerEnvmap(CLI::App& app);
void registerInfo(CLI::App& app);
void registerImport(CLI::App& app);
void registerScenes(CLI::App& app);
void registerBench(CLI::App& app);
void registerView(CLI::App& app);
void registerEval(CLI::App& app);
void registerAnalyze(CLI::App& app);
void registerWeb(CLI::App& app);
// `bench` groups these (cmd_bench_*.cpp).
void registerBenchMethods(CLI::App& bench);
void registerBenchRelight(CLI::App& bench);
void registerBenchBatch(CLI::App& bench);
void registerBenchCodecs(CLI::App& bench);
void registerBenchScaling(CLI::App& bench);
void registerBenchQuantization(CLI::App& bench);
void registerBenchEigen(CLI::App& bench);

}  // namespace acpca::cli
