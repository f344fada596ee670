#pragma once
// The compressed model every method produces (design.md section 5.6): the
// global basis V_g, per cluster its bases W_i (N x n_i) and optional mean, per
// pixel its cluster and n_i coefficients, plus the image geometry. Relit value
// of a row p in cluster i: albedo_p * (u_p . (W_i^T V_g^T L) + mu_i . V_g^T L).
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "cluster/global_basis.h"
#include "cluster/partition.h"
#include "precompute/transport/transport_file.h"

namespace acpca {

enum class CoeffPrecision { F32, F16, I8 };
CoeffPrecision parseCoeffPrecision(const std::string& text);  // f32 | f16 | i8
CoeffPrecision parseBasisPrecision(const std::string& text);  // f32 | f16
const char* coeffPrecisionName(CoeffPrecision p);

inline constexpr const char* kModelFormat = "adaptive-cpca model";
inline constexpr int kModelVersion = 2;  // 2: one i8 scale per cluster basis

struct Model {
  TransportHeader geometry;  ///< camera, lattice, pixels, albedo, coverage (normals unused)
  std::string method;
  std::string settings;         ///< JSON text: the options that made the model
  Eigen::MatrixXf globalBasis;  ///< l x N
  bool hasMean = false;
  CoeffPrecision precision = CoeffPrecision::F32;
  /// F32 or F16: with F16 the cluster bases and means hold half-representable
  /// values (stored as half in the file and in the relighter).
  CoeffPrecision basisPrecision = CoeffPrecision::F32;

  // Clusters, in order; rows of cluster c are clusterRows[rowOffsets[c] .. rowOffsets[c+1]).
  std::vector<std::int32_t> clusterRows;
  std::vector<std::int64_t> rowOffsets;    ///< C + 1
  std::vector<std::int32_t> ranks;         ///< n_c
  std::vector<std::int64_t> basisOffsets;  ///< C + 1, into bases (N x n_c column-major each)
  std::vector<float> bases;
  std::vector<float> means;  ///< C x N (zeros without a mean)
  /// Coefficients, cluster by cluster, each p_c x n_c row-major in cluster row
  /// order; coefficientOffsets[c] is where cluster c starts. Only the array of
  /// `precision` is filled; i8 values are q * scale[c].
  std::vector<std::int64_t> coefficientOffsets;  ///< C + 1
  std::vector<float> coeffF32;
  std::vector<std::uint16_t> coeffF16;
  std::vector<std::int8_t> coeffI8;
  /// One per cluster basis, clusters in order (sum of n_c values): the i8 step
  /// of that basis's coefficients; 1 for f32 and f16.
  std::vector<float> coeffScale;

  // Figures recorded when compressing.
  double transportError = 0;    ///< relative Frobenius error against T
  double globalEnergyKept = 0;  ///< fraction of T's energy in the global basis
  double compressSeconds = 0;
  long long peakMemoryBytes = 0;

  int clusters() const { return static_cast<int>(ranks.size()); }
  int globalBases() const { return static_cast<int>(globalBasis.cols()); }
  long long rows() const { return geometry.rows(); }
  /// sum over clusters of n_c (p_c + N), the mean counted as a basis (eq. 17/19).
  double totalCost() const;
  double costPerPixel() const { return rows() ? totalCost() / rows() : 0; }
  /// Coefficient k of the r-th row of cluster c, decoded to float.
  float coefficient(int c, long long r, int k) const;
  /// Bytes of the arrays a relight reads per frame (bases, means, coefficients).
  long long frameBytes() const;
  /// Index of cluster c's first basis among all clusters' bases (into coeffScale).
  long long firstBasisIndex(int c) const {
    return globalBases() > 0 ? basisOffsets[c] / globalBases() : 0;
  }
  /// The cluster of every row, in the transport's row order.
  std::vector<int> clusterOfRow() const;
};

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
};

/// Ranks for an error budget: starting from none, repeatedly add to the cluster
/// whose next eigenvalue per unit cost, lambda / (p + N), is largest, until the
/// dropped energy is at most `budget`. Spectra must be descending.
std::vector<int> allocateRanks(const std::vector<Eigen::VectorXd>& spectra,
                               const std::vector<long long>& clusterSizes, int globalBases,
                               double budget);

/// Fits each cluster of the partition (PCA to the tolerance, on G) and stores
/// its coefficients. Sets transportError from the global residual, the
/// clusters' residuals and the quantization error, all exact (with half bases,
/// by reconstructing every row from the stored values).
Model buildModel(const TransportHeader& geometry, const GlobalBasis& basis,
                 const GlobalProjection& projection, const Partition& partition,
                 const ModelOptions& options);

/// Stores a model's f32 coefficients as `precision` (f16, or i8 with one scale
/// per cluster basis: the largest |value| of that basis's coefficients / 127,
/// so a basis of small coefficients keeps its own fine step); returns the squared error this adds
/// to the transport (orthonormal bases: the coefficients' squared error).
double storeCoefficients(Model& model, CoeffPrecision precision);

/// Writes atomically (temporary name, renamed when complete).
void writeModel(const Model& model, const std::string& path);
/// Reads and validates a model file; throws UserError naming the file.
Model readModel(const std::string& path);
/// True if the file is an HDF5 file whose format attribute says model.
bool isModelFile(const std::string& path);

/// Per-row RGB (albedo applied) for each lighting: the plain reference relight
/// of a model (the fast relighter must match it).
std::vector<std::vector<float>> relightModelReference(
    const Model& model, const std::vector<std::vector<double>>& lightings);

}  // namespace acpca
