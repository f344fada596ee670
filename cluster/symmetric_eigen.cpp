#include "cluster/symmetric_eigen.h"

#include <dlfcn.h>
#include <lapacke.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <atomic>
#include <mutex>
#include <shared_mutex>
#include <thread>

#include "cluster/blas_core.h"
#include "core/error.h"
#include "core/warning.h"

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

/// Shared by every LAPACK call, held alone while the thread count changes:
/// OpenBLAS's count is one global, read by calls in flight.
std::shared_mutex blasCalls;

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

template <typename Scalar>
constexpr const char* syevdName() {
  return sizeof(Scalar) == 8 ? "dsyevd" : "ssyevd";
}

/// What to try when both solvers failed: the kernels this CPU runs.
std::string blasAdvice();

void tellOnceThatEigenSolves() {
  static std::once_flag told;
  std::call_once(told, [] {
    warn(concat("OpenBLAS runs its generic '", blasCore(),
                "' kernels on a CPU that has more; they answered eigenproblems wrong on "
                "such CPUs, so Eigen's solver answers every one instead, more slowly. "
                "OPENBLAS_CORETYPE=",
                cpuBlasCore(), " set before the program starts gives LAPACK's speed"));
  });
}

/// Checked, then values descending and clamped, vectors to match.
template <typename Result, typename Matrix>
Result decompose(const Matrix& a, bool wantVectors) {
  using Scalar = typename Matrix::Scalar;
  std::call_once(singleThreaded, [] { setBlasThreads(1); });
  ACPCA_CHECK(a.rows() == a.cols(), "not square: ", a.rows(), "x", a.cols());
  Result result;
  if (a.rows() == 0) return result;
  ACPCA_CHECK(a.allFinite(), "non-finite entries in a ", a.rows(), "^2 symmetric matrix");
  if (blasCoreUnsuited()) tellOnceThatEigenSolves();
  const EigenAnswer<Scalar> answer =
      blasCoreUnsuited()
          ? checkedEigenAnswer<Scalar>(a, wantVectors, eigenLibrarySolver<Scalar>(), {})
          : checkedEigenAnswer<Scalar>(a, wantVectors, lapackSolver<Scalar>(),
                                       eigenLibrarySolver<Scalar>());
  result.values = answer.ascending.reverse().template cast<double>().cwiseMax(0.0);
  if (wantVectors) result.vectors = answer.vectors.rowwise().reverse();
  return result;
}

std::string blasAdvice() {
  return concat("OpenBLAS runs its '", blasCore(), "' kernels (chosen by ", blasCoreChosenBy(),
                "), which may not suit this CPU: run again with OPENBLAS_CORETYPE=", cpuBlasCore(),
                " (docs/reliability.md, \"When a library answers wrong\")");
}

/// OpenBLAS's threads for a solve made alone, while no other LAPACK call is in flight.
class AloneBlasThreads {
 public:
  AloneBlasThreads() : lock_(blasCalls) {
    std::call_once(singleThreaded, [] { setBlasThreads(1); });
    setBlasThreads(aloneBlasThreads());
  }
  ~AloneBlasThreads() { setBlasThreads(1); }

 private:
  std::unique_lock<std::shared_mutex> lock_;
};

}  // namespace

template <typename Scalar>
const EigenSolver<Scalar>& lapackSolver() {
  static const EigenSolver<Scalar> solver{
      concat("LAPACK's ", syevdName<Scalar>(), " (OpenBLAS core ", blasCore(), ")"),
      [](const SymmetricMatrix<Scalar>& a, bool wantVectors) {
        const lapack_int n = static_cast<lapack_int>(a.rows());
        EigenAnswer<Scalar> answer;
        SymmetricMatrix<Scalar> work = a;
        answer.ascending.resize(n);
        const lapack_int info =
            syevd(wantVectors ? 'V' : 'N', n, work.data(), answer.ascending.data());
        if (info != 0) answer.failure = concat(syevdName<Scalar>(), " returned info ", info);
        if (wantVectors) answer.vectors = std::move(work);
        return answer;
      }};
  return solver;
}

template <typename Scalar>
const EigenSolver<Scalar>& eigenLibrarySolver() {
  static const EigenSolver<Scalar> solver{
      "Eigen's solver", [](const SymmetricMatrix<Scalar>& a, bool wantVectors) {
        // Reads the lower triangle only, as LAPACK does.
        const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(
            a.template cast<double>(),
            wantVectors ? Eigen::ComputeEigenvectors : Eigen::EigenvaluesOnly);
        EigenAnswer<Scalar> answer;
        if (eigen.info() != Eigen::Success) {
          answer.failure = "Eigen's solver did not converge";
          return answer;
        }
        answer.ascending = eigen.eigenvalues().template cast<Scalar>();
        if (wantVectors) answer.vectors = eigen.eigenvectors().template cast<Scalar>();
        return answer;
      }};
  return solver;
}

template <typename Scalar>
EigenAnswer<Scalar> checkedEigenAnswer(const SymmetricMatrix<Scalar>& a, bool wantVectors,
                                       const EigenSolver<Scalar>& first,
                                       const EigenSolver<Scalar>& retry) {
  EigenAnswer<Scalar> answer = first.solve(a, wantVectors);
  const std::string fault = eigenAnswerFault(a, answer, wantVectors);
  if (fault.empty()) return answer;
  const std::string what = concat("the eigen-decomposition of a ", a.rows(), "x", a.cols(), " ",
                                  sizeof(Scalar) == 8 ? "double" : "float", " matrix");
  if (!retry.solve)
    throw UserError(concat(what, " is wrong: ", first.name, ": ", fault, ". ", blasAdvice()));
  answer = retry.solve(a, wantVectors);
  const std::string again = eigenAnswerFault(a, answer, wantVectors);
  if (!again.empty())
    throw UserError(concat(what, " is wrong twice: ", first.name, ": ", fault, "; then ",
                           retry.name, ": ", again, ". ", blasAdvice()));
  static std::atomic<bool> warned{false};
  if (!warned.exchange(true))
    warn(concat(what, " by ", first.name, " was wrong (", fault, "); ", retry.name,
                " answered it instead, as it will any other that fails its checks. ",
                blasAdvice()));
  return answer;
}

template const EigenSolver<double>& lapackSolver<double>();
template const EigenSolver<float>& lapackSolver<float>();
template const EigenSolver<double>& eigenLibrarySolver<double>();
template const EigenSolver<float>& eigenLibrarySolver<float>();
template EigenAnswer<double> checkedEigenAnswer<double>(const SymmetricMatrix<double>&, bool,
                                                        const EigenSolver<double>&,
                                                        const EigenSolver<double>&);
template EigenAnswer<float> checkedEigenAnswer<float>(const SymmetricMatrix<float>&, bool,
                                                      const EigenSolver<float>&,
                                                      const EigenSolver<float>&);

SymmetricEigen symmetricEigen(const Eigen::MatrixXd& a, bool wantVectors) {
  const std::shared_lock lock(blasCalls);
  return decompose<SymmetricEigen>(a, wantVectors);
}

SymmetricEigen symmetricEigenAlone(const Eigen::MatrixXd& a, bool wantVectors) {
  const AloneBlasThreads during;
  return decompose<SymmetricEigen>(a, wantVectors);
}

EigenAnswer<double> uncheckedLapackAlone(const Eigen::MatrixXd& a, bool wantVectors) {
  const AloneBlasThreads during;
  return lapackSolver<double>().solve(a, wantVectors);
}

SymmetricEigenF symmetricEigenFloat(const Eigen::MatrixXf& a, bool wantVectors) {
  const std::shared_lock lock(blasCalls);
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
