// `adaptive-cpca bench methods`: every method's cost at equal image error.
#include "eval/method_comparison.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct MethodsArgs {
  CommonOptions common;
  std::string input, out;
  SweepSettings settings;
  std::vector<std::string> envs;
};

void run(MethodsArgs& a) {
  if (a.settings.methods.empty()) a.settings.methods = sweepMethodNames();
  checkSweepMethods(a.settings.methods);
  refuseOutputsOverInputs(joined(a.envs, {a.input}), {a.common.jsonPath}, {a.out});
  ThreadLimit limit(a.common.threads);
  const TransportReader transport(a.input);
  a.settings.log = stderrLog("bench methods", a.common.quiet);
  printBenchmark(runMethodComparison(transport, a.envs, a.settings, a.out), a.common);
}

}  // namespace

void registerBenchMethods(CLI::App& bench) {
  auto args = std::make_shared<MethodsArgs>();
  auto* sub = bench.add_subcommand("methods", "Cost of every method at equal image error");
  sub->add_option("input", args->input, "Transport file")->required();
  sub->add_option("--out", args->out, "Directory for methods.csv")->required();
  sub->add_option("--global-energies", args->settings.globalEnergies, "Global energies to sweep")
      ->delimiter(',');
  sub->add_option("--tolerances", args->settings.tolerances, "Cluster tolerances to sweep")
      ->delimiter(',');
  sub->add_option("--cpca-clusters", args->settings.cpcaClusters, "CPCA cluster counts")
      ->delimiter(',');
  sub->add_option("--env", args->envs, "Evaluation lightings (default: the evaluation set)");
  sub->add_option("--methods", args->settings.methods,
                  "Methods to run: global, block, adaptive-quad, adaptive-quad-exact, "
                  "adaptive-binary, cpca (default all)")
      ->delimiter(',');
  args->common.add(*sub);
  nameParameters(*sub, {{"--env", {"environment"}}});
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
