#pragma once
// `bench methods`: every compression method over a sweep of settings, each
// model relit under the evaluation set and compared with the dense ground
// truth; costs compared at equal image error (design.md section 7).
#include <CLI/CLI.hpp>

namespace acpca::cli {

void registerMethodSweep(CLI::App& bench);

}  // namespace acpca::cli
