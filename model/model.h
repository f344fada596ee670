#pragma once
// The compressed model every method produces (docs/design.md section 5.6): the
// global basis V_g, per cluster its bases W_i (N x n_i) and optional mean, per
// pixel its cluster and n_i coefficients, plus the image geometry. Relit value
// of a row p in cluster i: albedo_p * (u_p . (W_i^T V_g^T L) + mu_i . V_g^T L).
#include <Eigen/Core>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "transport/transport_file.h"

namespace acpca {

/// How coefficients (f32, f16, i8) and cluster bases (f32, f16) are stored.
enum class CoeffPrecision { F32, F16, I8 };
inline constexpr EnumNames<CoeffPrecision, 3> kCoeffPrecisionNames{
    "coefficient precision",
    {{{CoeffPrecision::F32, "f32"}, {CoeffPrecision::F16, "f16"}, {CoeffPrecision::I8, "i8"}}}};
CoeffPrecision parseCoeffPrecision(const std::string& text);  // f32 | f16 | i8
CoeffPrecision parseBasisPrecision(const std::string& text);  // f32 | f16
const char* coeffPrecisionName(CoeffPrecision p);
/// Bytes of one stored value: 4, 2 or 1.
inline int storedBytes(CoeffPrecision p) {
  return p == CoeffPrecision::F32 ? 4 : p == CoeffPrecision::F16 ? 2 : 1;
}

/// One cluster's stored values, wherever they are held: its bases W_c^T
/// (rank rows of N values), its mean (N values) and its coefficients (rows x
/// rank, row-major, in the model's precision), with its bases' i8 steps.
struct ClusterValues {
  int rank = 0;
  long long rows = 0;
  int globalBases = 0;
  CoeffPrecision precision = CoeffPrecision::F32;
  const float* bases = nullptr;
  const float* mean = nullptr;
  const void* coefficients = nullptr;
  const float* scale = nullptr;  ///< rank values: the i8 steps, else 1
};

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
  double compressSeconds = 0;   ///< reported (--json, the log), never stored in the file

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
  /// Cluster c's values, pointing into this model's arrays.
  ClusterValues clusterValues(int c) const;
  /// The cluster of every row, in the transport's row order.
  std::vector<int> clusterOfRow() const;
};

/// What a compress made, as `compress --json` and Python's compress() report
/// it: method, clusters, global_bases, total_cost, cost_per_pixel,
/// transport_error, global_energy_kept, bytes_per_frame and seconds.
nlohmann::json summaryJson(const Model& model);
/// The same in a line of words, for the log.
std::string describeInWords(const Model& model);

/// How many clusters have each rank.
std::map<int, int> rankHistogram(const Model& model);
/// The ranks in one short line: "min 1, median 8, max 143; 1: 40, 2-4: 12, ..."
/// with buckets of powers of four.
std::string rankSummary(const Model& model);

}  // namespace acpca
