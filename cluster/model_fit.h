#pragma once
// Fitting a model to a partition: per cluster PCA on the global coefficients G
// to a tolerance (or ranks from one error budget), the coefficients stored as
// asked, and the exact transport error (docs/design.md section 5.6).
#include "cluster/global_basis.h"
#include "cluster/partition.h"
#include "model/model.h"

namespace acpca {

struct ModelOptions {
  double tolerance = 0.999;
  bool mean = false;
  CoeffPrecision precision = CoeffPrecision::F32;
  CoeffPrecision basisPrecision = CoeffPrecision::F32;  ///< F32 or F16
  /// Instead of each cluster keeping `tolerance` of its own energy, spend one
  /// error budget, (1 - tolerance) of all clusters' energy, where each basis
  /// removes the most error per unit of cost (beyond the paper).
  bool allocateRanks = false;
  /// Clusters with more values (rows x N) than this are fitted from a blocked
  /// Gram matrix instead of a double copy of their rows (memory, not results).
  long long largeClusterValues = 1LL << 24;
  /// Fits clusters below that size in single precision when the tolerance is
  /// at most 0.9999 (the residual stays exact for the basis kept).
  bool floatFits = true;
};

/// Fits each cluster of the partition (PCA to the tolerance, on G) and stores
/// its coefficients. Sets transportError from the global residual, the
/// clusters' residuals and the quantization error, all exact (with half bases,
/// by reconstructing every row from the stored values).
Model buildModel(const TransportHeader& geometry, const GlobalBasis& basis,
                 const GlobalProjection& projection, const Partition& partition,
                 const ModelOptions& options);

}  // namespace acpca
