// `adaptive-cpca relight`: a model or a transport (dense ground truth) under
// lightings and rotations -> images (relight/batch_relight.h).
#include <iostream>

#include "core/ranks.h"
#include "core/resources.h"
#include "relight/batch_relight.h"
#include "relight/environment.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct RelightArgs {
  CommonOptions common;
  std::string exrCompression;
  std::string background = "env";
  std::vector<std::string> envs, rotations;
  bool fastRotation = false;
  BatchRelightOptions options;
};

void run(RelightArgs& a) {
  // Everything cheap is checked before any work.
  BatchRelightOptions& o = a.options;
  o.background = parseBackground(a.background);
  o.rotations.clear();
  for (const auto& spec : a.rotations) {
    const auto parsed = parseRotationSpec(spec);
    o.rotations.insert(o.rotations.end(), parsed.begin(), parsed.end());
  }
  if (o.rotations.empty()) o.rotations.push_back({});
  o.envs = expandEnvironmentSpecs(a.envs);
  o.rotationMode = a.fastRotation ? RotationMode::FastLattice : RotationMode::Exact;
  if (!a.exrCompression.empty()) o.exrCompression = kExrCompressionNames.parse(a.exrCompression);
  validateBatchRelight(o);
  {
    std::vector<std::string> inputs = o.envs;
    inputs.push_back(o.input);
    refuseOutputsOverInputs(inputs, {a.common.jsonPath});
  }

  ThreadLimit limit(a.common.threads);
  // Under mpirun the ranks share the frames; rank 0 writes and reports.
  const bool lead = ranks::rank() == 0;
  Progress progress("relight", "frames", a.common.quiet || !lead);
  o.progress = [&](long long done, long long total) { progress.update(done, total); };
  o.warn = [lead, quiet = a.common.quiet](const std::string& text) {
    if (lead && !quiet) std::cerr << "adaptive-cpca: " << text << "\n";
  };
  const BatchRelightResult result = relightBatch(o);
  progress.finish();
  if (!lead) return;
  if (!a.common.quiet) std::cerr << result.summary << "\n";
  nlohmann::json report = result.json;
  report["peak_memory_bytes"] = peakMemoryBytes();
  writeJson(a.common.jsonPath, report);
  if (!result.failed.empty()) {
    std::string list;
    for (const auto& f : result.failed) list += "\n  " + f;
    throw UserError(concat(result.failed.size(), " of ", o.envs.size(),
                           " environment maps could not be used (the others were written):", list));
  }
}

}  // namespace

void registerRelight(CLI::App& app) {
  auto args = std::make_shared<RelightArgs>();
  auto* sub = app.add_subcommand(
      "relight", "Relight a model, or a transport file (dense ground truth), under lightings");
  sub->add_option("input", args->options.input, "Model (M_FILE) or transport file (T_FILE)")
      ->required();
  sub->add_option("--env", args->envs,
                  "Lighting: image (.exr/.hdr lat-long), directory of them, constant:V, "
                  "sun:THETA,PHI,SIZE_DEG,INTENSITY or sky (repeatable)")
      ->required();
  sub->add_option("--out", args->options.out, "Output image, or directory for several")->required();
  sub->add_option("--rotate", args->rotations,
                  "YAW[,PITCH,ROLL] or a yaw sweep A:B:S (repeatable)");
  sub->add_option("--exposure", args->options.exposure, "Exposure in stops applied to the outputs");
  sub->add_option("--format", args->options.format,
                  "exr, png or both (default: from --out, exr in batch)");
  sub->add_option("--background", args->background, "env, black or alpha");
  sub->add_option("--frames", args->options.timingRepeats,
                  "Timing mode: after a warm-up, repeat the relight K times and report ms/frame");
  sub->add_option("--max-rank", args->options.maxRank,
                  "Models: use each cluster's first K bases, or a fraction (0.5 or 50%)");
  sub->add_flag("--fast-rotation", args->fastRotation,
                "Rotate by bilinear lookup on the lattice (fast, not energy-preserving)");
  sub->add_flag("--exr-float", args->options.exrFloat, "Write 32-bit float EXR instead of half");
  sub->add_option("--exr-compression", args->exrCompression,
                  "EXR codec: none, rle, zips, zip or piz (default: zips for one image, " +
                      std::string(kExrCompressionNames.name(kBatchExrCompression)) +
                      " for a batch)");
  sub->add_option("--png-level", args->options.pngLevel, "PNG deflate level, 0 (fastest) to 9")
      ->capture_default_str();
  sub->add_flag("--force", args->options.force,
                "Write even when the frames look too large for the disk");
  args->common.add(*sub);
  nameParameters(*sub, {{"--env", {"environment"}},
                        {"--rotate", {"rotation"}},
                        {"--format", {"image format"}},
                        {"--frames", {"timing frames"}},
                        {"--exr-compression", {"EXR compression"}},
                        {"--png-level", {"PNG level"}},
                        {"--max-rank", {"maximum rank"}},
                        {"--out", {"output path"}}});
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
