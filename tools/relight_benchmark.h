#pragma once
// `bench relight`: the model relighter's ms per frame and bandwidth against the
// machine's streaming-read bandwidth, a dense relight of the same image from
// memory and other models (e.g. global PCA at equal error), all in one run.
#include <CLI/CLI.hpp>

namespace acpca::cli {

void registerRelightBenchmark(CLI::App& bench);

}  // namespace acpca::cli
