#include "cluster/symmetric_eigen.h"

#include <dlfcn.h>
#include <lapacke.h>

#include <algorithm>
#include <mutex>
#include <thread>

#include "core/error.h"

namespace acpca {

namespace {

/// OpenBLAS's own threads fight TBB's: keep it single-threaded. Found at run
/// time, so a reference LAPACK (no such function) works as well.
void setBlasThreads(int threads) {
  using SetThreads = void (*)(int);
  static const SetThreads set =
      reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (set) set(threads);
}

std::once_flag singleThreaded;

/// OpenBLAS threads of a solve made alone: fixed by the machine, not by --threads.
int aloneBlasThreads() {
  return static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 4u));
}

lapack_int syevd(char jobz, lapack_int n, double* a, double* w) {
  return LAPACKE_dsyevd(LAPACK_COL_MAJOR, jobz, 'L', n, a, n, w);
}
lapack_int syevd(char jobz, lapack_int n, float* a, float* w) {
  return LAPACKE_ssyevd(LAPACK_COL_MAJOR, jobz, 'L', n, a, n, w);
}

/// LAPACK's divide and conquer at the matrix's precision; values descending.
template <typename Result, typename Matrix>
Result decompose(const Matrix& a, bool wantVectors) {
  std::call_once(singleThreaded, [] { setBlasThreads(1); });
  ACPCA_CHECK(a.rows() == a.cols(), "not square: ", a.rows(), "x", a.cols());
  const lapack_int n = static_cast<lapack_int>(a.rows());
  Result result;
  if (n == 0) return result;
  ACPCA_CHECK(a.allFinite(), "non-finite entries in a ", n, "^2 symmetric matrix");
  Matrix work = a;
  Eigen::Matrix<typename Matrix::Scalar, Eigen::Dynamic, 1> ascending(n);
  const lapack_int info = syevd(wantVectors ? 'V' : 'N', n, work.data(), ascending.data());
  ACPCA_CHECK(info == 0, "syevd failed (info ", info, ") on a ", n, "^2 matrix");
  result.values = ascending.reverse().template cast<double>().cwiseMax(0.0);
  if (wantVectors) result.vectors = work.rowwise().reverse();
  return result;
}

}  // namespace

SymmetricEigen symmetricEigen(const Eigen::MatrixXd& a, bool wantVectors) {
  return decompose<SymmetricEigen>(a, wantVectors);
}

SymmetricEigen symmetricEigenAlone(const Eigen::MatrixXd& a, bool wantVectors) {
  std::call_once(singleThreaded, [] { setBlasThreads(1); });
  struct Threads {
    Threads() { setBlasThreads(aloneBlasThreads()); }
    ~Threads() { setBlasThreads(1); }
  } during;
  return decompose<SymmetricEigen>(a, wantVectors);
}

SymmetricEigenF symmetricEigenFloat(const Eigen::MatrixXf& a, bool wantVectors) {
  return decompose<SymmetricEigenF>(a, wantVectors);
}

int rankForEnergy(const Eigen::VectorXd& values, double total, double fraction) {
  if (values.size() == 0 || total <= 0 || values[0] <= 0) return 0;
  const double noise = 1e-12 * values[0];
  const double keep = fraction * total;
  double kept = 0;
  int rank = 0;
  while (rank < values.size() && values[rank] > noise && (fraction >= 1 || kept < keep))
    kept += values[rank++];
  return rank;
}

}  // namespace acpca
