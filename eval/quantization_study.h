#pragma once
// `bench quantization`: what storing coefficients in half or 8 bits costs.
// The spherical-harmonics baseline fitted by ULS, CLS and CEB ([Lam06]'s
// Table III on our scenes: condition numbers, coefficient norms, PSNR at f32,
// f16 and i8) beside our own PCA/CPCA models with f32, f16 and i8 coefficients.
#include <string>
#include <vector>

#include "core/study_output.h"
#include "transport/transport_file.h"

namespace acpca {

struct QuantizationOptions {
  std::vector<std::string> envs;  ///< empty: the evaluation set
  std::vector<int> shOrders{16, 25, 49, 64};
  int shGroups = 8;  ///< cube resolution the rows' normals are grouped on
  std::vector<std::string> methods{"global", "cpca", "adaptive-binary"};
  double tolerance = 0.999, globalEnergy = 0.999;
  int cpcaClusters = 100;
  bool noSh = false, noModels = false;
  StudyLog log;
};

/// Fits, stores and relights every variant; writes sh.csv, models.csv and
/// summary.md into `outDir`.
StudyOutput runQuantizationStudy(const TransportReader& transport,
                                 const QuantizationOptions& options, const std::string& outDir);

}  // namespace acpca
