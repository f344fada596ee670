// `adaptive-cpca precompute`: scene -> transport file (Embree).
#include <iostream>

#include "core/ranks.h"
#include "precompute/precompute_report.h"
#include "precompute/sampling_advice.h"
#include "precompute/scene.h"
#include "precompute/scene_views.h"
#include "precompute/transport_renderer.h"
#include "tools/cli_common.h"
#include "tools/commands.h"
#include "tools/render_flags.h"

namespace acpca::cli {

namespace {

struct PrecomputeArgs {
  CommonOptions common;
  RenderFlags render;
  std::string out;
};

/// One view rendered into `out`; its report.
nlohmann::json precomputeView(const PrecomputeArgs& a, const Scene& scene, const std::string& out,
                              PrecomputeOptions options) {
  // Under mpirun every rank renders; rank 0 writes and reports.
  const bool lead = ranks::rank() == 0;
  const bool quiet = a.common.quiet || !lead;
  Progress progress("precompute " + scene.name, "rows", quiet);
  options.cacheProgress = stageProgress("indirect cache: paths", "image rows", quiet);
  options.cacheFillProgress = stageProgress("indirect cache: visibility", "points", quiet);
  options.progress = [&](long long done, long long total) { progress.update(done, total); };
  options.log = stderrLog("precompute", a.common.quiet);
  options.beforeImageRow = faultInjection("ACPCA_FAULT_ROW", "image row");
  const PrecomputeStats stats = precomputeTransport(scene, out, options);
  progress.finish();
  if (!quiet)
    std::cerr << "wrote " << out << ": " << describeInWords(stats, options, scene.camera.size);
  nlohmann::json report = sceneReport(out, scene);
  report.update(toJson(options));
  report.update(toJson(stats));
  return report;
}

void run(const PrecomputeArgs& a) {
  // Reject bad options before any work.
  const PrecomputeOptions options = a.render.options(a.common.threads);
  const Scene scene = a.render.loadScene();
  const size_t views = scene.viewCount();
  std::vector<std::string> outs{a.common.jsonPath};
  for (size_t k = 0; k < views; ++k) outs.push_back(viewOutputPath(a.out, k, views));
  refuseOutputsOverInputs(scene.files, outs);
  refuseBlindViews(scene);

  if (ranks::rank() == 0)
    for (const auto& w : samplingWarnings(scene, options)) std::cerr << "warning: " << w << "\n";

  ThreadLimit limit(a.common.threads);
  // Several views: a file each, STEM_vNN.EXT, and a report each.
  nlohmann::json reports = nlohmann::json::array();
  for (size_t k = 0; k < views; ++k)
    reports.push_back(precomputeView(a, scene.view(k), viewOutputPath(a.out, k, views), options));
  if (ranks::rank() != 0) return;
  writeJson(a.common.jsonPath, views == 1 ? reports[0] : nlohmann::json{{"views", reports}});
}

}  // namespace

void registerPrecompute(CLI::App& app) {
  auto args = std::make_shared<PrecomputeArgs>();
  auto* sub = app.add_subcommand("precompute", "Ray-trace the light transport of a scene");
  args->render.add(*sub);
  sub->add_option("--out", args->out,
                  "Transport file to write (HDF5); a scene of several views writes STEM_vNN.h5")
      ->required();
  args->common.add(*sub);
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
