#pragma once
// `bench scaling`: one scene and camera at several resolutions, compressed
// adaptively at one tolerance; total cost against pixels beside the paper's
// prediction of 4 mu^2 per 4x pixels (paper 003 sec. 4.4).
#include <CLI/CLI.hpp>

namespace acpca::cli {

void registerScalingBenchmark(CLI::App& bench);

}  // namespace acpca::cli
