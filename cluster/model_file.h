#pragma once
// The model file (HDF5, docs/formats.md): the image header shared with
// transport files, then the global basis, clusters, bases, means and
// coefficients in their stored precision.
#include <string>

#include "cluster/model.h"

namespace acpca {

inline constexpr const char* kModelFormat = "adaptive-cpca model";
inline constexpr int kModelVersion = 2;  // 2: one i8 scale per cluster basis

/// Writes atomically (temporary name, renamed when complete).
void writeModel(const Model& model, const std::string& path);
/// Reads and validates a model file; throws UserError naming the file.
Model readModel(const std::string& path);
/// True if the file is an HDF5 file whose format attribute says model.
bool isModelFile(const std::string& path);

}  // namespace acpca
