// `adaptive-cpca relight`: a model or a transport (dense ground truth) under
// lightings and rotations -> images (dataset/batch_relight.h).
#include <iostream>

#include "core/ranks.h"
#include "core/resources.h"
#include "dataset/batch_relight.h"
#include "lighting/environment.h"
#include "lighting/map_sources.h"
#include "tools/batch_flags.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct RelightArgs {
  CommonOptions common;
  std::string background;  ///< empty: env, or black for a captured light set
  std::string lightMode;   ///< empty: exact
  std::string maxRank;     ///< empty: every basis
  BatchFlags batch;
  BatchRelightOptions options;
  std::vector<std::string> views;  ///< the input files: one, or a file per view
};

void run(RelightArgs& a) {
  // Everything cheap is checked before any work.
  BatchRelightOptions& o = a.options;
  o.input = a.views.front();
  o.moreViews.assign(a.views.begin() + 1, a.views.end());
  o.background = backgroundFor(a.background, o.input);
  if (!a.lightMode.empty()) o.lamps.mode = kLampModeNames.parse(a.lightMode);
  o.maxRank = RankLimit::parse(a.maxRank);
  const BatchPlan plan = a.batch.apply(o, a.common.jsonPath);

  ThreadLimit limit(a.common.threads);
  // Under mpirun the ranks share the frames; rank 0 writes and reports.
  const bool lead = ranks::rank() == 0;
  Progress progress("relight", "frames", a.common.quiet || !lead);
  o.progress = [&](long long done, long long total) { progress.update(done, total); };
  o.warn = [lead, quiet = a.common.quiet](const std::string& text) {
    if (lead && !quiet) std::cerr << "adaptive-cpca: " << text << "\n";
  };
  BatchRelightResult result = relightBatch(o, plan);
  progress.finish();
  if (!lead) return;
  if (!a.common.quiet) std::cerr << result.summary << "\n";
  nlohmann::json report = std::move(result.json);  // a frame's entry each: never copied
  report["peak_memory_bytes"] = peakMemoryBytes();
  writeJson(a.common.jsonPath, report);
  refuseFailedMaps(result, o.envs.size());
}

}  // namespace

void registerRelight(CLI::App& app) {
  auto args = std::make_shared<RelightArgs>();
  auto* sub = app.add_subcommand(
      "relight", "Relight a model, or a transport file (dense ground truth), under lightings");
  sub->add_option("input", args->views,
                  "Model (M_FILE) or transport file (T_FILE); several: the views of one scene "
                  "(STEM_v00.h5 STEM_v01.h5 ...), each relit under every lighting")
      ->required();
  args->batch.add(*sub, args->options, "Output image, or directory for several");
  sub->add_option("--exposure", args->options.exposure, "Exposure in stops applied to the outputs");
  sub->add_option("--background", args->background,
                  "env, black or alpha (default: env; black for a captured light set)");
  sub->add_option("--frames", args->options.timingRepeats,
                  "Timing mode: after a warm-up, repeat the relight K times and report ms/frame");
  sub->add_option("--max-rank", args->maxRank,
                  "Models: use each cluster's first K bases, or a fraction (0.5 or 50%)");
  sub->add_option("--anchor-spread", args->options.anchorSpread,
                  "Models, local lights: texels of direction within which a cluster's pixels "
                  "share a light's direction (0: each pixel its own)")
      ->capture_default_str();
  sub->add_option("--light-mode", args->lightMode,
                  "Lamps: exact (default; shadow rays from each camera sample where the file "
                  "holds its surfaces: one to a point or spot lamp, over a sphere lamp's disc "
                  "where a penumbra may fall) or lattice (through T's texels, as before)");
  addFastRotationFlag(*sub, args->options.rotationMode);
  sub->add_flag("--exr-float", args->options.exrFloat, "Write 32-bit float EXR instead of half");
  sub->add_flag("--force", args->options.force,
                "Write even when the frames look too large for the disk");
  args->common.add(*sub);
  nameParameters(*sub, {{"--frames", {"timing frames"}},
                        {"--max-rank", {"maximum rank"}},
                        {"--light-mode", {"light mode"}}});
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
