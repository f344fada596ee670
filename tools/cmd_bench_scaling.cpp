// `adaptive-cpca bench scaling`: cost and time against resolution, with the
// paper's 4 mu^2 prediction.
#include "eval/scaling_study.h"
#include "precompute/scene.h"
#include "precompute/transport_renderer.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct ScalingArgs {
  CommonOptions common;
  std::string scene, out;
  ScalingOptions options;
};

void run(ScalingArgs& a) {
  const Scene scene = loadScene(a.scene);
  refuseOutputsOverInputs(scene.files, {a.common.jsonPath}, {a.out});
  ScalingOptions& o = a.options;
  o.sceneName = scene.name;
  o.log = stderrLog("bench scaling", a.common.quiet);
  ThreadLimit limit(a.common.threads);
  o.precompute = [&scene, &limit](int width, int cubemap, const std::string& path) {
    PrecomputeOptions p;
    p.cubemapResolution = cubemap;
    p.threads = limit.threads();
    precomputeTransport(scene.atWidth(width), path, p);
  };
  validateScalingOptions(o);
  printStudy(runScalingStudy(o, a.out), a.common);
}

}  // namespace

void registerBenchScaling(CLI::App& bench) {
  auto args = std::make_shared<ScalingArgs>();
  auto& o = args->options;
  auto* sub = bench.add_subcommand(
      "scaling", "Cost and time against resolution, with the paper's 4 mu^2 prediction");
  sub->add_option("--scene", args->scene, "Built-in scene name or scene JSON file")->required();
  sub->add_option("--sizes", o.sizes, "Image widths (height follows the scene's aspect)")
      ->delimiter(',');
  sub->add_option("--out", args->out, "Report directory")->required();
  sub->add_option("--method", o.method, "adaptive-quad (default) or another method");
  sub->add_option("--tolerance", o.tolerance, "Energy each cluster keeps");
  sub->add_option("--global-energy", o.globalEnergy, "Energy the global basis keeps");
  sub->add_option("--cubemap", o.cubemap, "Cube-map resolution R");
  sub->add_option("--frames", o.frames, "Timed relight frames per size (median)")
      ->check(CLI::PositiveNumber);
  sub->add_flag("--keep-transports", o.keepTransports,
                "Keep transport_<size>.h5 in the report directory");
  args->common.add(*sub);
  nameParameters(*sub, {{"--cubemap", {"cube-map resolution"}}});
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
