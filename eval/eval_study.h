#pragma once
// `eval`: error against run time for every method (docs/design.md section 7). The
// method sweep with timing, the dense relight, Ng 2003's Haar-wavelet baseline
// and [Lam06]'s spherical-harmonics fits, all judged against one dense
// relight of the evaluation set; the report (CSV/JSON, images, plots and
// summary.md) is written to a directory.
#include <functional>
#include <string>
#include <vector>

#include "eval/eval_report.h"
#include "eval/method_sweep.h"
#include "eval/spherical_harmonics.h"
#include "transport/transport_file.h"

namespace acpca {

struct EvalOptions {
  std::vector<std::string> envs;  ///< empty: the evaluation set
  /// dense, haar, sh and the sweep's methods.
  std::vector<std::string> methods{"dense",         "global",          "block", "cpca",
                                   "adaptive-quad", "adaptive-binary", "haar",  "sh"};
  SweepSettings sweep = defaultSweep();
  std::vector<int> haarTerms{20, 50, 100, 200};
  int haarBits = 6;
  std::vector<int> shOrders{16, 25, 49, 64};
  std::vector<ShFit> shFits{ShFit::Uls, ShFit::Cls, ShFit::Ceb};
  int shGroups = 8;
  std::function<void(const std::string&)> log;

  /// eval's sweep: two global energies, three tolerances, four block sides and
  /// CPCA cluster counts (at the highest energy only: its fits are the slowest).
  static SweepSettings defaultSweep();
  /// The quick sweep for the headline size (`eval --quick`): every method, one
  /// global energy, two tolerances, fewer blocks, CPCA counts, Haar terms and
  /// SH orders; about half an hour at 1024x1024 on two cores (docs/results.md).
  void useQuickSweep();
};

/// Throws ParameterError for an unknown method, a non-positive Haar term count,
/// an SH order that is not a square of 1..16 or a group resolution outside 1..64.
void validateEvalOptions(const EvalOptions& options);

/// Runs everything and writes the report into `dir` (created if missing).
EvalReport runEvaluation(const TransportReader& transport, const EvalOptions& options,
                         const std::string& dir);

}  // namespace acpca
