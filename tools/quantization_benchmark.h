#pragma once
// `bench quantization`: what storing coefficients in half or 8 bits costs.
// The spherical-harmonics baseline fitted by ULS, CLS and CEB (paper 004's
// Table III on our scenes: condition numbers, coefficient norms, PSNR at f32,
// f16 and i8) beside our own PCA/CPCA models with f32, f16 and i8 coefficients.
#include <CLI/CLI.hpp>

namespace acpca::cli {

void registerQuantizationBenchmark(CLI::App& bench);

}  // namespace acpca::cli
