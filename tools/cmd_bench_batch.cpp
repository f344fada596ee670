// `adaptive-cpca bench batch`: a relight batch end to end, stage by stage,
// against the streaming read and the relight alone (eval/batch_benchmark.h).
#include "eval/batch_benchmark.h"
#include "relight/environment.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct BatchBenchArgs {
  CommonOptions common;
  std::vector<std::string> envs, rotations;
  std::string exrCompression;
  BatchBenchmarkOptions options;
};

void run(BatchBenchArgs& a) {
  BatchRelightOptions& o = a.options.batch;
  o.rotations.clear();
  for (const auto& spec : a.rotations) {
    const auto parsed = parseRotationSpec(spec);
    o.rotations.insert(o.rotations.end(), parsed.begin(), parsed.end());
  }
  if (o.rotations.empty()) o.rotations.push_back({});
  o.envs = expandEnvironmentSpecs(a.envs);
  if (!a.exrCompression.empty()) o.exrCompression = kExrCompressionNames.parse(a.exrCompression);
  validateBatchRelight(o);
  {
    std::vector<std::string> inputs = o.envs;
    inputs.push_back(o.input);
    refuseOutputsOverInputs(inputs, {a.common.jsonPath});
  }
  ThreadLimit limit(a.common.threads);
  StudyOutput out = runBatchBenchmark(a.options);
  CommonOptions loud = a.common;
  loud.quiet = false;  // the table is the result
  printStudy(out, loud);
}

}  // namespace

void registerBenchBatch(CLI::App& bench) {
  auto args = std::make_shared<BatchBenchArgs>();
  BatchRelightOptions& o = args->options.batch;
  auto* sub = bench.add_subcommand(
      "batch", "A relight batch end to end, stage by stage, vs streaming read and relight alone");
  sub->add_option("input", o.input, "Model (M_FILE) or transport file (T_FILE)")->required();
  sub->add_option("--env", args->envs, "Lightings, as relight takes them (repeatable)")->required();
  sub->add_option("--rotate", args->rotations, "YAW[,PITCH,ROLL] or a sweep A:B:S (repeatable)");
  sub->add_option("--out", o.out, "Directory the frames go to")->required();
  sub->add_option("--format", o.format, "exr, png or both (default exr)");
  sub->add_option("--exr-compression", args->exrCompression,
                  "EXR codec: none, rle, zips, zip, piz");
  sub->add_option("--png-level", o.pngLevel, "PNG deflate level, 0-9")->capture_default_str();
  sub->add_option("--stream-gib", args->options.streamGiB,
                  "Array size of the streaming-read loop (GiB)")
      ->capture_default_str();
  args->common.add(*sub);
  nameParameters(*sub, {{"--env", {"environment"}},
                        {"--rotate", {"rotation"}},
                        {"--format", {"image format"}},
                        {"--exr-compression", {"EXR compression"}},
                        {"--png-level", {"PNG level"}},
                        {"--out", {"output path"}},
                        {"--stream-gib", {"stream size (GiB)"}}});
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
