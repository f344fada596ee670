#pragma once
// Real spherical harmonics and the noise-resistant fits of [Lam06] (Leung,
// Wong et al.): a function known only on part of the sphere (a transport row
// lives on its normal's hemisphere) fitted by least squares onto the first n
// SH functions, plain (ULS), ridge-constrained (CLS) or truncated in the Gram
// matrix's eigenbasis (CEB). docs/algorithms.md has the summary.
#include <Eigen/Core>
#include <string>

#include "core/enum_names.h"
#include "transport/cube_lattice.h"

namespace acpca {

/// Number of SH functions in the first `bands` bands: bands^2.
inline int shCount(int bands) {
  return bands * bands;
}
/// The band count of n functions; throws UserError naming `what` unless n is a
/// square of 1..16.
int shBandsOf(int n, const std::string& what);

/// The n = bands^2 orthonormal real SH functions at unit direction d, in the
/// order (l, m) = (0,0), (1,-1), (1,0), (1,1), (2,-2), ...; +Z is the pole.
void evaluateSh(int bands, const Vec3& d, double* out);

/// SH functions at every texel centre of the lattice: latticeSize x bands^2.
Eigen::MatrixXd shOnLattice(const CubeLattice& lattice, int bands);
/// The same at any directions (a captured light set's lights): directions x coefficients.
Eigen::MatrixXd shAtDirections(const std::vector<Vec3>& directions, int bands);

enum class ShFit {
  Uls,  ///< unconstrained least squares, c = A^-1 b (eq. 8)
  Cls,  ///< constrained least squares: the smallest ridge lambda meeting |c|^2 <= E_c (eq. 19-25)
  Ceb,  ///< constrained eigen basis: leading eigen-directions while |c|^2 <= E_c (eq. 35)
};
inline constexpr EnumNames<ShFit, 3> kShFitNames{
    "SH fit", {{{ShFit::Uls, "uls"}, {ShFit::Cls, "cls"}, {ShFit::Ceb, "ceb"}}}};
ShFit parseShFit(const std::string& text);  // uls | cls | ceb
const char* shFitName(ShFit fit);

/// The Gram matrix A = Y^T W Y of the SH functions over one support (W: the
/// texels' solid angles), factored once as A = U S U^T (eq. 12) and shared by
/// every function fitted on that support: each fit is then O(n^2).
class ShSupportFit {
 public:
  explicit ShSupportFit(const Eigen::MatrixXd& gram);
  int size() const { return static_cast<int>(eigenvalues_.size()); }
  const Eigen::VectorXd& eigenvalues() const { return eigenvalues_; }  ///< descending
  /// s_max / s_min; infinite when A is singular.
  double conditionNumber() const;
  /// The bound E_c on |c|^2 for a function of this energy (integral of f^2 over
  /// the support). Eq. 16-17 with the mean squared norm kappa of the SH
  /// functions over the support (1/2 on a hemisphere) in place of 1/2.
  double coefficientBound(double energy) const { return energy / kappa_; }
  /// Coefficients c (size() values) from the projection b = Y^T W f (at least
  /// size() values, the first used) and the function's energy. Eigenvalues
  /// below 1e-12 of the largest count as zero (ULS takes the pseudo-inverse).
  /// lambda, when given, receives CLS's ridge parameter (0 for the others).
  void fit(ShFit fit, const double* b, double energy, double* c, double* lambda = nullptr) const;

 private:
  Eigen::VectorXd eigenvalues_;
  Eigen::MatrixXd eigenvectors_;
  double kappa_ = 0.5, cutoff_ = 0;
};

}  // namespace acpca
