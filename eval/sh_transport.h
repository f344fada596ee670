#pragma once
// The spherical-harmonics baseline: every transport row fitted onto the first n
// SH functions over the part of the sphere where it lives, by the fits of paper
// 004 (ULS, CLS, CEB). Rows are grouped by their normal (quantized to a coarse
// cube lattice); a group's support is its normal's hemisphere, widened by the
// spread of its members' normals and by every texel any member lights, so no
// transport is dropped. One Gram matrix and eigendecomposition per group serves
// all its rows. Relighting integrates the fitted function against the lighting
// over the support only, c . (Y_S^T L_S), so the error measured is the fit's.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "eval/spherical_harmonics.h"
#include "lighting/environment.h"
#include "model/model.h"
#include "transport/transport_file.h"

namespace acpca {

/// One fit of every row: P x n coefficients, row-major, and what the fit cost.
struct ShCoefficients {
  int n = 0;
  ShFit fit = ShFit::Uls;
  CoeffPrecision storage = CoeffPrecision::F32;
  std::vector<float> values;  ///< as decoded after storage
  /// Per row: |c| and sqrt(E_c), the bound of eq. 17 (before storage).
  std::vector<float> norms, bounds;
};

struct ShStatistics {
  double medianCondition = 0, maxCondition = 0;      ///< of the groups' Gram matrices
  double medianNorm = 0, maxNorm = 0;                ///< |c| over rows with energy
  double medianNormToBound = 0, maxNormToBound = 0;  ///< |c| / sqrt(E_c)
  double fitSeconds = 0;
};

class ShTransport {
 public:
  /// Reads T once. maxCoefficients: the largest n to be fitted (a square);
  /// normalResolution: the coarse cube lattice rows are grouped on (6 R^2 groups at most).
  ShTransport(const TransportReader& transport, int maxCoefficients = 64, int normalResolution = 8);

  /// Fits every row with the first n (a square <= maxCoefficients) SH functions.
  ShCoefficients fit(int n, ShFit fit) const;
  /// Condition numbers, coefficient norms (and the fit's time when given).
  ShStatistics statistics(const ShCoefficients& c) const;

  /// RGB per row (albedo applied) of the fitted transport under the lighting.
  void relight(const ShCoefficients& c, const LatticeLighting& lighting, float* rgb);
  /// Multiply-adds per pixel and channel of a relight: n, plus the per-group
  /// lighting projections spread over the rows.
  double costPerPixel(int n) const;
  /// Bytes a frame reads: coefficients at their storage, the group of each row, albedo.
  long long frameBytes(const ShCoefficients& c) const;

  long long rows() const { return rows_; }
  int groups() const { return static_cast<int>(supports_.size()); }
  int groupOfRow(long long row) const { return groupOfRow_[row]; }
  /// Texels of group g's support.
  const std::vector<int>& support(int g) const { return supports_[g]; }

 private:
  const ShSupportFit& factored(int g, int n) const;

  long long rows_ = 0;
  int maxCoefficients_ = 0, latticeSize_ = 0;
  int channels_ = 1;              ///< 3: R, G and B rows, each fitted on its own
  Eigen::MatrixXd sh_;            ///< latticeSize x maxCoefficients
  Eigen::MatrixXf shTransposed_;  ///< maxCoefficients x latticeSize, for the frame projection
  std::vector<int> groupOfRow_;
  std::vector<std::vector<int>> supports_;
  std::vector<Eigen::MatrixXd> grams_;  ///< per group, maxCoefficients^2
  /// (rows x channels) x maxCoefficients: b = Y^T W f of every row (and channel)
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> projections_;
  std::vector<double> energies_;  ///< per row (and channel): sum_j w_j f_j^2
  std::vector<float> albedo_;
  /// Factorizations by (n, group), made on first use.
  mutable std::vector<std::vector<std::unique_ptr<ShSupportFit>>> fits_;
  Eigen::MatrixXf lightingOnSupports_;  ///< per frame: maxCoefficients x (3 groups)
};

/// Stores SH coefficients as f16 or i8 and decodes them back, as [Lam06]
/// compresses them: the same coefficient of every row forms one map, and i8
/// quantizes each map uniformly with its own scale (largest |value| / 127).
void storeShCoefficients(ShCoefficients& c, CoeffPrecision storage);

}  // namespace acpca
