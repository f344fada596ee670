// `adaptive-cpca bench relight`: relighter ms/frame and GB/s against the
// streaming-read bandwidth, a dense relight and baseline models.
#include "eval/relight_benchmark.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct RelightBenchArgs {
  CommonOptions common;
  RelightBenchmarkOptions options;
};

void run(RelightBenchArgs& a) {
  validateRelightBenchmarkOptions(a.options);
  const RelightBenchmarkOptions& o = a.options;
  refuseOutputsOverInputs(joined(joined(o.envs, o.baselines), {o.model, o.transport}),
                          {a.common.jsonPath});
  ThreadLimit limit(a.common.threads);
  a.options.threads = limit.threads();
  printBenchmark(runRelightBenchmark(a.options), a.common);
}

}  // namespace

void registerBenchRelight(CLI::App& bench) {
  auto args = std::make_shared<RelightBenchArgs>();
  auto& o = args->options;
  auto* sub = bench.add_subcommand(
      "relight", "Relighter ms/frame and GB/s vs streaming read, dense and baseline models");
  sub->add_option("model", o.model, "Model to measure (M_FILE)")->required();
  sub->add_option("--transport", o.transport,
                  "Its transport file: time a dense relight from memory and measure errors");
  sub->add_option("--baseline", o.baselines, "Other models to time (repeatable)");
  sub->add_option("--env", o.envs,
                  "Lightings for the errors, the first one timed (default: the evaluation set)");
  sub->add_option("--frames", o.frames, "Timed frames per model (after 2 warm-ups)");
  sub->add_option("--dense-frames", o.denseFrames, "Timed frames of the dense relight");
  sub->add_option("--stream-gib", o.streamGiB, "Array size of the streaming-read loop (GiB)");
  args->common.add(*sub);
  nameParameters(*sub, {{"--env", {"environment"}},
                        {"--frames", {"timed frames"}},
                        {"--stream-gib", {"stream size (GiB)"}}});
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
