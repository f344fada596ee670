// `adaptive-cpca analyze`: the paper's analyses on a transport file
// (eval/analyze_study.h).
#include "eval/analyze_study.h"
#include "eval/dimensionality_study.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct AnalyzeArgs {
  CommonOptions common;
  std::string input, out;
  std::vector<std::string> centres;
  AnalyzeOptions options;
};

void run(AnalyzeArgs& a) {
  a.options.centres = parseCentres(a.centres);
  validateAnalyzeOptions(a.options);
  refuseOutputsOverInputs({a.input}, {a.common.jsonPath}, {a.out});
  ThreadLimit limit(a.common.threads);
  const TransportReader transport(a.input);
  a.options.log = stderrLog("analyze", a.common.quiet);
  printStudy(runAnalysis(transport, a.options, a.out), a.common);
}

}  // namespace

void registerAnalyze(CLI::App& app) {
  auto args = std::make_shared<AnalyzeArgs>();
  auto& o = args->options;
  auto* sub = app.add_subcommand(
      "analyze", "Dimensionality vs patch area (slopes), cost vs block size, mu, N and p*");
  sub->add_option("input", args->input, "Transport file (T_FILE)")->required();
  sub->add_option("--out", args->out, "Report directory")->required();
  sub->add_option("--centre", args->centres,
                  "Patch centre X,Y in pixels (repeatable; default: six spread over the object)");
  sub->add_option("--blocks", o.blocks, "Block sides for the cost curve")->delimiter(',');
  sub->add_option("--global-energy", o.globalEnergy, "Energy the global basis keeps");
  sub->add_option("--tolerance", o.tolerance, "Energy each block's bases keep");
  sub->add_option("--energy", o.energy, "Energy that defines a patch's dimensionality");
  args->common.add(*sub);
  nameParameters(*sub, {{"--centre", {"patch centre"}},
                        {"--blocks", {"block sides"}},
                        {"--energy", {"dimensionality energy"}}});
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
