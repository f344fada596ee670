#include "eval/eigen_benchmark.h"

#include <cmath>
#include <random>
#include <vector>

#include "cluster/blas_core.h"
#include "cluster/symmetric_eigen.h"
#include "core/error.h"
#include "core/statistics.h"
#include "core/stopwatch.h"
#include "core/text.h"
#include "relight/memory_bandwidth.h"

namespace acpca {

namespace {

/// x^T x of 2n rows whose column k is scaled by (1 + k)^-1: a spectrum that
/// falls as a transport's does, so divide and conquer deflates as it would.
Eigen::MatrixXd transportLikeGram(int n) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd x(2 * n, n);
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < 2 * n; ++i) x(i, k) = normal(rng) / (1.0 + k);
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(n, n);
  gram.selfadjointView<Eigen::Lower>().rankUpdate(x.transpose());
  return gram;
}

}  // namespace

StudyOutput runEigenBenchmark(const EigenBenchmarkOptions& o) {
  if (o.size < 2 || o.size > 20000) throw ParameterError("size", o.size, "must be in [2, 20000]");
  if (o.repeats < 1) throw ParameterError("repeats", o.repeats, "must be at least 1");
  if (!(o.streamGiB > 0 && o.streamGiB <= 64))
    throw ParameterError("stream size (GiB)", o.streamGiB, "is out of range (0, 64]");
  const BandwidthMeasurement stream = measureStreamingRead(o.streamGiB * (1 << 30), 5);
  const Eigen::MatrixXd gram = transportLikeGram(o.size);
  // Alternating, so that a machine's drift falls on both alike.
  std::vector<double> unchecked, checked, checks;
  for (int r = 0; r < o.repeats; ++r) {
    Stopwatch watch;
    const EigenAnswer<double> raw = uncheckedLapackAlone(gram, true);
    const SymmetricEigen before{raw.ascending.reverse().cwiseMax(0.0),
                                raw.vectors.rowwise().reverse()};
    unchecked.push_back(watch.seconds());
    watch.restart();
    const SymmetricEigen after = symmetricEigenAlone(gram, true);
    checked.push_back(watch.seconds());
    watch.restart();
    const std::string fault = eigenAnswerFault(gram, raw, true);
    checks.push_back(watch.seconds());
    if (!fault.empty() || after.values.size() != before.values.size())
      throw UserError(concat("bench eigen: LAPACK's answer failed its checks: ", fault));
  }
  const double before = median(unchecked), after = median(checked), check = median(checks);
  std::string text = formatted("%-34s %10s %8s\n", "solve of the global basis", "seconds", "ratio");
  text += formatted("%-34s %10.3f %8.3f\n", "LAPACK, unchecked (before)", before, 1.0);
  text += formatted("%-34s %10.3f %8.3f\n", "symmetricEigenAlone, checked", after, after / before);
  text += formatted("%-34s %10.3f %8.3f\n", "the checks alone", check, check / before);
  nlohmann::json rows = {{"unchecked_seconds", before},
                         {"checked_seconds", after},
                         {"checks_seconds", check},
                         {"checked_over_unchecked", after / before}};
  if (o.eigenSolver) {
    Stopwatch watch;
    const EigenAnswer<double> eigen = eigenLibrarySolver<double>().solve(gram, true);
    const double seconds = watch.seconds();
    text += formatted("%-34s %10.3f %8.3f\n", "Eigen's solver (the fallback)", seconds,
                      seconds / before);
    rows["eigen_solver_seconds"] = seconds;
    if (!eigenAnswerFault(gram, eigen, true).empty())
      throw UserError("bench eigen: Eigen's answer failed its checks");
  }
  text += formatted(
      "%dx%d Gram matrix with vectors, median of %d; OpenBLAS core %s (chosen by %s)\n"
      "streaming read, %.2f GiB array: %.1f GB/s (median of 5)\n",
      o.size, o.size, o.repeats, blasCore().c_str(), blasCoreChosenBy().c_str(), o.streamGiB,
      stream.gbPerSecondMedian);
  StudyOutput out;
  out.summary = text;
  rows.update({{"size", o.size},
               {"repeats", o.repeats},
               {"blas_core", blasCore()},
               {"blas_core_chosen_by", blasCoreChosenBy()},
               {"streaming_read_gb_per_s", stream.gbPerSecondMedian}});
  out.json = rows;
  return out;
}

}  // namespace acpca
