// `adaptive-cpca eval`: error against run time for every method, written as
// CSV/JSON, images, plots and summary.md (eval/eval_study.h).
#include <iostream>

#include "eval/eval_study.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct EvalArgs {
  CommonOptions common;
  std::string input, out;
  std::vector<std::string> shFits;  ///< none given: the library's default
  bool quick = false;
  EvalOptions options;
  CLI::App* command = nullptr;
};

/// --quick sets the sweep's lists the command line left alone.
void applyQuickSweep(EvalArgs& a) {
  EvalOptions quick = a.options;
  quick.useQuickSweep();
  EvalOptions& o = a.options;
  const auto given = [&](const char* flag) { return a.command->count(flag) > 0; };
  if (!given("--global-energies")) o.sweep.globalEnergies = quick.sweep.globalEnergies;
  if (!given("--tolerances")) o.sweep.tolerances = quick.sweep.tolerances;
  if (!given("--block-sizes")) o.sweep.blockSizes = quick.sweep.blockSizes;
  if (!given("--cpca-clusters")) o.sweep.cpcaClusters = quick.sweep.cpcaClusters;
  o.sweep.cpcaMatchingBinary = quick.sweep.cpcaMatchingBinary;
  if (!given("--haar-terms")) o.haarTerms = quick.haarTerms;
  if (!given("--sh-orders")) o.shOrders = quick.shOrders;
}

void run(EvalArgs& a) {
  if (a.quick) applyQuickSweep(a);
  EvalOptions& o = a.options;
  if (!a.shFits.empty()) o.shFits.clear();
  for (const auto& f : a.shFits) o.shFits.push_back(parseShFit(f));
  validateEvalOptions(o);
  refuseOutputsOverInputs(joined(o.envs, {a.input}), {a.common.jsonPath}, {a.out});
  ThreadLimit limit(a.common.threads);
  const TransportReader transport(a.input);
  o.log = stderrLog("eval", a.common.quiet);
  const EvalReport report = runEvaluation(transport, o, a.out);
  writeJson(a.common.jsonPath, evalReportJson(report));
  if (!a.common.quiet)
    std::cerr << "eval: done in " << report.seconds << " s: " << a.out << "/summary.md\n";
}

}  // namespace

void registerEval(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  auto& o = args->options;
  auto* sub = app.add_subcommand(
      "eval", "Error against run time for every method: CSV/JSON, plots, images, summary.md");
  sub->add_option("input", args->input, "Transport file (T_FILE)")->required();
  sub->add_option("--env", o.envs, "Evaluation lightings (default: the evaluation set)");
  sub->add_option("--out", args->out, "Report directory")->required();
  sub->add_option("--methods", o.methods,
                  "dense, global, block, cpca, adaptive-quad, adaptive-quad-exact, "
                  "adaptive-binary, haar, sh (default: all but adaptive-quad-exact)")
      ->delimiter(',');
  sub->add_option("--tolerances", o.sweep.tolerances, "Cluster tolerances to sweep")
      ->delimiter(',');
  sub->add_option("--global-energies", o.sweep.globalEnergies, "Global energies to sweep")
      ->delimiter(',');
  sub->add_option("--block-sizes", o.sweep.blockSizes, "Fixed block sides")->delimiter(',');
  sub->add_option("--cpca-clusters", o.sweep.cpcaClusters, "CPCA cluster counts")->delimiter(',');
  sub->add_option("--haar-terms", o.haarTerms, "Wavelet terms kept of the lighting")
      ->delimiter(',');
  sub->add_option(
      "--haar-bits", o.haarBits,
      "Wavelet-domain transport: drop coefficients below 2^-bits of their row's largest");
  sub->add_option("--sh-orders", o.shOrders,
                  "Spherical-harmonics coefficient counts (squares of 1..16)")
      ->delimiter(',');
  sub->add_option("--sh-fits", args->shFits, "SH fits of [Lam06]: uls, cls, ceb")->delimiter(',');
  sub->add_option("--sh-groups", o.shGroups,
                  "Cube resolution the rows' normals are grouped on for the SH fits (1..64)")
      ->check(CLI::Range(1, 64));
  sub->add_flag("--quick", args->quick,
                "The quick sweep for large images: g 0.999, tolerances 0.99 and 0.999, blocks 8 "
                "and 16, CPCA K = 10, 1000 and adaptive-binary's count, Haar k = 50 and 200, SH n "
                "= 16 and 64 (lists "
                "given on the command line win)");
  sub->add_option("--frames", o.sweep.timingFrames, "Timed frames per setting (median)")
      ->check(CLI::PositiveNumber);
  args->common.add(*sub);
  args->command = sub;
  nameParameters(
      *sub,
      {{"--env", {"environment"}}, {"--sh-fits", {"SH fit"}}, {"--frames", {"timing frames"}}});
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
