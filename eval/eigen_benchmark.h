#pragma once
// `bench eigen`: the global basis's eigensolve (symmetricEigenAlone, checked,
// cluster/symmetric_eigen.h) against the same LAPACK solve unchecked, on a
// Gram matrix of the global basis's size, beside the machine's streaming read:
// what checking every answer costs, as seconds and a ratio measured in one run.
#include "core/study_output.h"

namespace acpca {

struct EigenBenchmarkOptions {
  int size = 3700;           ///< n of the n x n Gram matrix (a 256x256 plant's N at 6x32x32)
  int repeats = 3;           ///< solves of each kind, alternating; the median counts
  bool eigenSolver = false;  ///< also time Eigen's solver once (the fallback; slow when large)
  double streamGiB = 0.5;
};

/// Table (solver, median seconds, ratio to the unchecked solve) as text and JSON.
StudyOutput runEigenBenchmark(const EigenBenchmarkOptions& options);

}  // namespace acpca
