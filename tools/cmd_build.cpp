// `adaptive-cpca build`: scene -> model, tile by tile, with no transport file.
#include <iostream>

#include "cluster/compress.h"
#include "core/ranks.h"
#include "eval/error_measures.h"
#include "lighting/environment.h"
#include "pipeline/streamed_build.h"
#include "precompute/sampling_advice.h"
#include "precompute/scene_views.h"
#include "tools/cli_common.h"
#include "tools/commands.h"
#include "tools/render_flags.h"

namespace acpca::cli {

namespace {

struct BuildArgs {
  CommonOptions common;
  RenderFlags render;
  CompressFlags compress;
  std::string out;
  BuildOptions options;  ///< the flags that set a field of it directly
  std::vector<std::string> envs;
};

/// One view built into `out`; its report.
nlohmann::json buildView(const BuildArgs& a, const Scene& scene, const std::string& out,
                         BuildOptions o) {
  // Under mpirun every rank renders tiles; rank 0 writes and reports, every
  // rank logs the tiles it starts.
  const bool lead = ranks::rank() == 0;
  Progress progress("build " + scene.name, "rows", a.common.quiet || !lead);
  o.progress = [&](long long done, long long total) { progress.update(done, total); };
  o.log = stderrLog("build", a.common.quiet);
  o.beforeTile = faultInjection("ACPCA_FAULT_TILE", "tile");
  const BuildStats s = buildStreamed(scene, out, o);
  progress.finish();
  if (!lead) return nullptr;
  for (const auto& [name, error] : s.imageErrors)
    if (!a.common.quiet)
      std::cerr << "image error under " << name
                << " (raw reconstruction, before the clamp at zero): " << 100 * error << "%\n";
  if (!o.groundTruthDir.empty() && !a.common.quiet)
    std::cerr << "ground-truth images (dense relight, EXR) in " << o.groundTruthDir << "\n";
  if (!a.common.quiet)
    std::cerr << "wrote " << out << ": " << methodName(o.compress.method) << ", "
              << describeInWords(s) << "\n";
  nlohmann::json report = sceneReport(out, scene);
  report["method"] = methodName(o.compress.method);
  report.update(toJson(s));
  report.update(linearAlgebraJson());
  return report;
}

void run(const BuildArgs& a) {
  // Reject bad options before any work.
  BuildOptions o = a.options;
  o.render = a.render.options(a.common.threads);
  o.compress = a.compress.options();
  o.resumeAdvice = "the same build with --resume continues";
  o.groundTruth = a.envs.empty() && !o.groundTruthDir.empty() ? defaultEvaluationSet()
                                                              : expandEnvironmentSpecs(a.envs);
  const Scene scene = a.render.loadScene();
  refuseOutputsOverInputs(scene.files, {a.common.jsonPath});
  refuseBlindViews(scene);
  if (ranks::rank() == 0)
    for (const auto& w : samplingWarnings(scene, o.render)) std::cerr << "warning: " << w << "\n";

  ThreadLimit limit(a.common.threads);
  // Several views: a model each (STEM_vNN.EXT).
  const size_t views = scene.viewCount();
  nlohmann::json reports = nlohmann::json::array();
  for (size_t k = 0; k < views; ++k)
    reports.push_back(
        buildView(a, scene.view(k), viewOutputPath(a.out, k, views), o.forView(k, views)));
  if (ranks::rank() != 0) return;
  writeJson(a.common.jsonPath, views == 1 ? reports[0] : nlohmann::json{{"views", reports}});
}

}  // namespace

void registerBuild(CLI::App& app) {
  auto args = std::make_shared<BuildArgs>();
  auto* sub = app.add_subcommand(
      "build",
      "Render and compress a scene tile by tile into a model, with no transport file on disk");
  args->render.add(*sub);
  sub->add_option("--out", args->out,
                  "Model file to write (HDF5); a scene of several views writes STEM_vNN.h5")
      ->required();
  args->compress.add(*sub, true);
  sub->add_flag("--resume", args->options.resume,
                "Continue an interrupted build of the same scene and settings from its finished "
                "tiles (kept in OUT.tiles/)");
  sub->add_option("--ground-truth", args->options.groundTruthDir,
                  "Directory for the dense relight of every --env (EXR): the ground truth no "
                  "transport file holds, computed from the rendered rows; the model's image error "
                  "against it is reported");
  sub->add_option("--keep-transport", args->options.keepTransport,
                  "Also write the dense transport to this file, as precompute would (one "
                  "process; about a tile row's transport rows in memory; the disk must hold it)");
  sub->add_option("--env", args->envs,
                  "Lightings of the ground truth and image errors (default with --ground-truth: "
                  "the evaluation set)");
  sub->add_option("--tile", args->options.tileSide,
                  "cpca, adaptive-binary: side of the pixel groups clustered on their own "
                  "(default 256)");
  sub->add_option("--tiles-in-flight", args->options.tilesInFlight,
                  "Tiles rendered and compressed at once (each holds its rows)")
      ->capture_default_str();
  args->common.add(*sub);
  nameParameters(*sub,
                 {{"--tile", {"tile side"}}, {"--env", {"environment", "ground-truth lightings"}}});
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
