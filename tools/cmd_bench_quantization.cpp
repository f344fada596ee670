// `adaptive-cpca bench quantization`: PSNR with coefficients in f32, f16 and
// i8, for the SH fits (ULS, CLS, CEB) and our models.
#include "cluster/compress.h"
#include "eval/quantization_study.h"
#include "eval/spherical_harmonics.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct QuantizationArgs {
  CommonOptions common;
  std::string input, out;
  QuantizationOptions options;
};

void run(QuantizationArgs& a) {
  QuantizationOptions& o = a.options;
  for (int n : o.shOrders) shBandsOf(n, "SH orders");
  for (const auto& m : o.methods) parseMethod(m);
  refuseOutputsOverInputs(joined(o.envs, {a.input}), {a.common.jsonPath}, {a.out});
  ThreadLimit limit(a.common.threads);
  const TransportReader transport(a.input);
  o.log = stderrLog("bench quantization", a.common.quiet);
  printStudy(runQuantizationStudy(transport, o, a.out), a.common);
}

}  // namespace

void registerBenchQuantization(CLI::App& bench) {
  auto args = std::make_shared<QuantizationArgs>();
  auto& o = args->options;
  auto* sub = bench.add_subcommand(
      "quantization",
      "PSNR with coefficients in f32, f16 and i8: SH fits (ULS, CLS, CEB) and our models");
  sub->add_option("input", args->input, "Transport file (T_FILE)")->required();
  sub->add_option("--env", o.envs, "Lightings (default: the evaluation set)");
  sub->add_option("--out", args->out, "Report directory")->required();
  sub->add_option("--sh-orders", o.shOrders, "SH coefficient counts (squares of 1..16)")
      ->delimiter(',');
  sub->add_option("--sh-groups", o.shGroups,
                  "Cube resolution the rows' normals are grouped on (1..64)")
      ->check(CLI::Range(1, 64));
  sub->add_option("--methods", o.methods,
                  "Compression methods to quantize (global, block, cpca, adaptive-quad, "
                  "adaptive-binary)")
      ->delimiter(',');
  sub->add_option("--tolerance", o.tolerance, "Energy each cluster keeps");
  sub->add_option("--global-energy", o.globalEnergy, "Energy the global basis keeps");
  sub->add_option("--cpca-clusters", o.cpcaClusters,
                  "Clusters of cpca (and adaptive-binary's start)");
  sub->add_flag("--no-sh", o.noSh, "Leave out the spherical-harmonics table");
  sub->add_flag("--no-models", o.noModels, "Leave out the models' table");
  args->common.add(*sub);
  nameParameters(*sub, {{"--env", {"environment"}}});
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
