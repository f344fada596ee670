#pragma once
// compress: transport file -> model, by one of the methods of docs/design.md section 5.
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "cluster/model_fit.h"
#include "cluster/partition.h"

namespace acpca {

enum class Method { Global, Block, Cpca, AdaptiveQuad, AdaptiveBinary };
inline constexpr EnumNames<Method, 5> kMethodNames{"method",
                                                   {{{Method::Global, "global"},
                                                     {Method::Block, "block"},
                                                     {Method::Cpca, "cpca"},
                                                     {Method::AdaptiveQuad, "adaptive-quad"},
                                                     {Method::AdaptiveBinary, "adaptive-binary"}}}};
Method parseMethod(const std::string& text);
const char* methodName(Method m);

struct CompressOptions {
  Method method = Method::AdaptiveQuad;
  double tolerance = 0.999;  ///< fraction of each cluster's energy kept
  /// Fraction of the sample's energy the global basis keeps.
  double globalEnergy = GlobalBasisOptions{}.energy;
  int clusters = 10;  ///< cpca; initial clusters of adaptive-binary
  /// block: block side; adaptive-quad: root block side; 0: 8 for block, 64 for adaptive-quad.
  int block = 0;
  bool exactQuadTree = false;  ///< adaptive-quad: bottom-up optimum instead of greedy
  bool allocateRanks = false;  ///< one error budget across clusters instead of per cluster
  CoeffPrecision coeffs = CoeffPrecision::F32;
  CoeffPrecision bases = CoeffPrecision::F32;  ///< F32 or F16
  int sampleRows = GlobalBasisOptions{}.sampleRows;
  /// cpca, adaptive-binary: leading global coefficients rows are clustered on (0: all N).
  int clusteringDims = kDefaultClusteringDims;
  std::uint64_t seed = GlobalBasisOptions{}.seed;
  /// Stage messages ("global basis: N = 812") for progress output.
  std::function<void(const std::string&)> log;
  /// Go on even when the projection looks too large for the memory available.
  bool force = false;
};

/// The block side `options` means for its method (resolving block = 0).
int blockSideFor(const CompressOptions& options);

/// CPCA-based methods keep a mean per cluster, as Sloan's CPCA does.
bool keepsMean(Method m);

/// The method's partition of the rows `in` holds (block side and root from
/// blockSideFor, CPCA's K and adaptive binary's initial clusters from
/// `clusters`).
Partition partitionRows(const ClusterInput& in, const CompressOptions& options);

/// The compress settings a model records (its `settings` attribute), the
/// same whether `compress` or `build` made it: every option as applied, the
/// block side resolved and the clustering width on `globalBases` bases.
nlohmann::json compressSettings(const CompressOptions& options, int globalBases);

/// The linear algebra this process runs (cluster/blas_core.h): `blas_core`,
/// `blas_core_chosen_by` and `eigensolver` ("LAPACK", or "Eigen" where
/// OpenBLAS's generic kernels do not suit the CPU). `compress` and `build`
/// report it in --json; the model's settings keep `blas_core` and `eigensolver`.
nlohmann::json linearAlgebraJson();

/// Throws ParameterError on a bad value.
void validateCompressOptions(const CompressOptions& options);

/// Throws UserError on bad options (before any work) or a bad file.
Model compressTransport(const TransportReader& transport, const CompressOptions& options);

}  // namespace acpca
