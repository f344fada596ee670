// `adaptive-cpca precompute`: scene -> transport file (Embree).
#include <iostream>

#include "core/ranks.h"
#include "precompute/precompute_report.h"
#include "precompute/sampling_advice.h"
#include "precompute/scene.h"
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

void run(const PrecomputeArgs& a) {
  // Reject bad options before any work.
  PrecomputeOptions options = a.render.options(a.common.threads);
  const Scene scene = a.render.loadScene();
  refuseOutputsOverInputs(scene.files, {a.out, a.common.jsonPath});

  if (ranks::rank() == 0)
    for (const auto& w : samplingWarnings(scene, options)) std::cerr << "warning: " << w << "\n";

  ThreadLimit limit(a.common.threads);
  // Under mpirun every rank renders; rank 0 writes and reports.
  const bool lead = ranks::rank() == 0;
  const bool quiet = a.common.quiet || !lead;
  Progress progress("precompute " + scene.name, "rows", quiet);
  options.cacheProgress = stageProgress("indirect cache: paths", "image rows", quiet);
  options.cacheFillProgress = stageProgress("indirect cache: visibility", "points", quiet);
  options.progress = [&](long long done, long long total) { progress.update(done, total); };
  options.log = stderrLog("precompute", a.common.quiet);
  options.beforeImageRow = faultInjection("ACPCA_FAULT_ROW", "image row");
  const PrecomputeStats stats = precomputeTransport(scene, a.out, options);
  progress.finish();
  if (!lead) return;

  if (!a.common.quiet)
    std::cerr << "wrote " << a.out << ": " << describeInWords(stats, options, scene.camera.size);
  nlohmann::json report = sceneReport(a.out, scene);
  report.update(toJson(options));
  report.update(toJson(stats));
  writeJson(a.common.jsonPath, report);
}

}  // namespace

void registerPrecompute(CLI::App& app) {
  auto args = std::make_shared<PrecomputeArgs>();
  auto* sub = app.add_subcommand("precompute", "Ray-trace the light transport of a scene");
  args->render.add(*sub);
  sub->add_option("--out", args->out, "Transport file to write (HDF5)")->required();
  args->common.add(*sub);
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
