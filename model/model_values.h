#pragma once
// What a model's values must satisfy before anything relights it: finite, and
// small enough that no relit value can overflow a float.
#include <string>
#include <vector>

#include "model/model.h"

namespace acpca {

/// The largest relitBoundPerUnitLight a model file may have.
inline constexpr double kRelitBoundLimit = 1e20;

/// An upper bound on |relit value| per unit of the largest lattice light
/// value, from the triangle inequality on albedo_p * (u_p . W^T V_g^T L +
/// mu . V_g^T L): every value may be finite while their products overflow.
/// It is the product of the three factors below.
double relitBoundPerUnitLight(const Model& m);

/// What a cluster's row bound adds to each row: sum_j |mu_j|, and per basis
/// |W_k|_1 (times |step_k| for i8). Not finite when a value is not.
struct ClusterBoundTerms {
  double mean = 0;
  std::vector<double> weight;
};
ClusterBoundTerms clusterBoundTerms(const ClusterValues& v);
/// max over v's rows of mean + sum_k |u_rk| weight_k, the coefficients read in
/// their stored type (|q| for i8); 0 without rows, infinite when a
/// coefficient (or a term) is not finite.
double rowsBound(const ClusterValues& v, const ClusterBoundTerms& terms);
/// max_j sum_i |V_g(i, j)|: bounds |(V_g^T L)_j| / max|L|.
double globalBasisBound(const Eigen::MatrixXf& globalBasis);
/// The largest albedo of any row.
double largestAlbedo(const TransportHeader& geometry);

/// UserError naming ctx on a non-finite basis, mean, coefficient or scale, or
/// values whose relit bound exceeds kRelitBoundLimit.
void checkModelValues(const Model& m, const std::string& ctx);
/// The same for one cluster's bases, mean and steps, and for its coefficients.
void checkBasesFinite(const ClusterValues& v, const std::string& ctx);
void checkCoefficientsFinite(const ClusterValues& v, const std::string& ctx);
/// UserError naming ctx when bound > kRelitBoundLimit (or is NaN).
void checkRelitBound(double bound, const std::string& ctx);

}  // namespace acpca
