#include "eval/spherical_harmonics.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "cluster/symmetric_eigen.h"
#include "core/error.h"

namespace acpca {

int shBandsOf(int n, const std::string& what) {
  const int bands = static_cast<int>(std::lround(std::sqrt(std::max(0, n))));
  if (bands < 1 || bands > 16 || bands * bands != n)
    throw ParameterError(what, n,
                         "is not a spherical-harmonics count (a square: 1, 4, 9, ..., 256)");
  return bands;
}

void evaluateSh(int bands, const Vec3& d, double* out) {
  ACPCA_CHECK(bands >= 1 && bands <= 16, "SH bands ", bands);
  const double z = std::clamp(d.z() / d.norm(), -1.0, 1.0);
  const double sinTheta = std::sqrt(std::max(0.0, 1 - z * z));
  const double phi = std::atan2(d.y(), d.x());
  // Associated Legendre P_l^m(z) by the standard recurrences in m then l.
  double legendre[16][16] = {};
  double diagonal = 1;  // P_m^m = (-1)^m (2m - 1)!! sin^m
  for (int m = 0; m < bands; ++m) {
    legendre[m][m] = diagonal;
    if (m + 1 < bands) legendre[m + 1][m] = z * (2 * m + 1) * diagonal;
    for (int l = m + 2; l < bands; ++l)
      legendre[l][m] =
          ((2 * l - 1) * z * legendre[l - 1][m] - (l + m - 1) * legendre[l - 2][m]) / (l - m);
    diagonal *= -(2 * m + 1) * sinTheta;
  }
  for (int l = 0; l < bands; ++l) {
    double ratio = 1;  // (l - m)! / (l + m)!, updated as m grows
    for (int m = 0; m <= l; ++m) {
      if (m > 0) ratio /= double(l + m) * (l - m + 1);
      const double k = std::sqrt((2 * l + 1) / (4 * M_PI) * ratio) * legendre[l][m];
      const int centre = l * l + l;
      if (m == 0) {
        out[centre] = k;
      } else {
        out[centre + m] = M_SQRT2 * k * std::cos(m * phi);
        out[centre - m] = M_SQRT2 * k * std::sin(m * phi);
      }
    }
  }
}

Eigen::MatrixXd shOnLattice(const CubeLattice& lattice, int bands) {
  std::vector<Vec3> directions;
  for (int j = 0; j < lattice.size(); ++j) directions.push_back(lattice.direction(j));
  return shAtDirections(directions, bands);
}

Eigen::MatrixXd shAtDirections(const std::vector<Vec3>& directions, int bands) {
  const int n = static_cast<int>(directions.size());
  Eigen::MatrixXd y(n, shCount(bands));
  std::vector<double> values(shCount(bands));
  for (int j = 0; j < n; ++j) {
    evaluateSh(bands, directions[j], values.data());
    for (int i = 0; i < shCount(bands); ++i) y(j, i) = values[i];
  }
  return y;
}

ShFit parseShFit(const std::string& text) {
  return kShFitNames.parse(text);
}

const char* shFitName(ShFit fit) {
  return kShFitNames.name(fit);
}

ShSupportFit::ShSupportFit(const Eigen::MatrixXd& gram) {
  ACPCA_CHECK(gram.rows() == gram.cols() && gram.rows() > 0, "Gram matrix ", gram.rows(), "x",
              gram.cols());
  SymmetricEigen e = symmetricEigen(gram, true);
  eigenvalues_ = std::move(e.values);
  eigenvectors_ = std::move(e.vectors);
  const double trace = gram.trace();
  kappa_ = trace > 0 ? trace / gram.rows() : 0.5;
  cutoff_ = 1e-12 * eigenvalues_[0];
}

double ShSupportFit::conditionNumber() const {
  const double smallest = eigenvalues_[size() - 1];
  return smallest > 0 ? eigenvalues_[0] / smallest : std::numeric_limits<double>::infinity();
}

void ShSupportFit::fit(ShFit fit, const double* b, double energy, double* c, double* lambda) const {
  const int n = size();
  // b' = U^T b (eq. 24): every fit is diagonal in the eigenbasis.
  const Eigen::VectorXd rotated =
      eigenvectors_.transpose() * Eigen::Map<const Eigen::VectorXd>(b, n);
  const double bound = coefficientBound(std::max(0.0, energy));
  Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
  double ridge = 0;
  const auto unconstrained = [&] {
    for (int i = 0; i < n && eigenvalues_[i] > cutoff_; ++i) z[i] = rotated[i] / eigenvalues_[i];
  };
  if (fit == ShFit::Uls) {
    unconstrained();
  } else if (fit == ShFit::Cls) {
    unconstrained();
    if (z.squaredNorm() > bound) {
      // |c(lambda)|^2 = sum b'_i^2 / (s_i + lambda)^2 falls monotonically (eq. 22):
      // double an upper bracket from 1, then bisect (eq. 25, O(n) a step).
      const auto normSquared = [&](double l) {
        double sum = 0;
        for (int i = 0; i < n; ++i)
          sum += rotated[i] * rotated[i] / std::pow(eigenvalues_[i] + l, 2);
        return sum;
      };
      double lo = 0, hi = 1;
      for (int k = 0; k < 2000 && normSquared(hi) > bound; ++k) hi *= 2;
      for (int k = 0; k < 64; ++k) {
        const double mid = 0.5 * (lo + hi);
        (normSquared(mid) > bound ? lo : hi) = mid;
      }
      ridge = hi;
      for (int i = 0; i < n; ++i) z[i] = rotated[i] / (eigenvalues_[i] + ridge);
    }
  } else {
    // Eq. 35: leading eigen-directions in order while the accumulated |z|^2 =
    // |c|^2 (U orthonormal) stays within the bound.
    double sum = 0;
    for (int i = 0; i < n && eigenvalues_[i] > cutoff_; ++i) {
      const double zi = rotated[i] / eigenvalues_[i];
      if (sum + zi * zi > bound) break;
      sum += zi * zi;
      z[i] = zi;
    }
  }
  Eigen::Map<Eigen::VectorXd>(c, n) = eigenvectors_ * z;
  if (lambda) *lambda = ridge;
}

}  // namespace acpca
