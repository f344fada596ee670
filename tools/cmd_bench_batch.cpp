// `adaptive-cpca bench batch`: a relight batch end to end, stage by stage,
// against the streaming read and the relight alone (dataset/batch_benchmark.h).
#include "dataset/batch_benchmark.h"
#include "tools/batch_flags.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct BatchBenchArgs {
  CommonOptions common;
  BatchFlags batch;
  BatchBenchmarkOptions options;
};

void run(BatchBenchArgs& a) {
  a.options.plan = a.batch.apply(a.options.batch, a.common.jsonPath);
  // As `relight` would: black behind a captured light set.
  a.options.batch.background = backgroundFor("", a.options.batch.input);
  ThreadLimit limit(a.common.threads);
  printBenchmark(runBatchBenchmark(a.options), a.common);
}

}  // namespace

void registerBenchBatch(CLI::App& bench) {
  auto args = std::make_shared<BatchBenchArgs>();
  BatchRelightOptions& o = args->options.batch;
  auto* sub = bench.add_subcommand(
      "batch", "A relight batch end to end, stage by stage, vs streaming read and relight alone");
  sub->add_option("input", o.input, "Model (M_FILE) or transport file (T_FILE)")->required();
  args->batch.add(*sub, o, "Directory the frames go to");
  sub->add_option("--stream-gib", args->options.streamGiB,
                  "Array size of the streaming-read loop (GiB)")
      ->capture_default_str();
  args->common.add(*sub);
  nameParameters(*sub, {{"--stream-gib", {"stream size (GiB)"}}});
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
