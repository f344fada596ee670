// `adaptive-cpca bench rays`: the precompute's occlusion-ray rate against raw
// Embree loops on the same scene points and directions, measured in one run.
#include <cstdio>

#include "precompute/ray_benchmark.h"
#include "precompute/scene.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct RaysArgs {
  CommonOptions common;
  std::string scene = "plant", size = "256x256", camera;
  int cubemap = 32, rows = 32, repeats = 3;
};

void runRays(const RaysArgs& a) {
  Scene scene = loadScene(a.scene);
  refuseOutputsOverInputs(scene.files, {a.common.jsonPath});
  scene.camera.size = parseImageSize(a.size, "--size");
  applyCameraSpec(scene, a.camera);
  ThreadLimit limit(a.common.threads);
  const RayBenchmarkReport r =
      runRayBenchmark(scene, a.cubemap, limit.threads(), a.rows, std::max(1, a.repeats));
  std::printf("scene %s: %lld triangles, %s image, middle %d rows, 6x%dx%d lattice, %d threads\n",
              scene.name.c_str(), r.triangles, a.size.c_str(), a.rows, a.cubemap, a.cubemap,
              r.threads);
  std::printf("%s", r.table().c_str());
  nlohmann::json report = r.json();
  report.update({{"scene", scene.name}, {"cubemap", a.cubemap}});
  writeJson(a.common.jsonPath, report);
}

}  // namespace

void registerBench(CLI::App& app) {
  auto* bench = app.add_subcommand("bench", "Benchmarks that print absolute figures and ratios");
  bench->require_subcommand(1);
  auto args = std::make_shared<RaysArgs>();
  auto* rays = bench->add_subcommand("rays", "Occlusion rays/s: precompute vs raw Embree loops");
  rays->add_option("--scene", args->scene, "Built-in scene or scene JSON");
  rays->add_option("--size", args->size, "Image size WxH");
  rays->add_option("--camera", args->camera, "auto or auto:THETA,PHI, as for precompute");
  rays->add_option("--cubemap", args->cubemap, "Cube-map face resolution R");
  rays->add_option("--rows", args->rows, "Image rows (from the middle) to trace");
  rays->add_option("--repeats", args->repeats, "Runs of each loop; the fastest counts");
  args->common.add(*rays);
  nameParameters(*rays, {{"--cubemap", {"cube-map resolution"}}});
  rays->callback([args] { runRays(*args); });
  registerBenchMethods(*bench);
  registerBenchRelight(*bench);
  registerBenchBatch(*bench);
  registerBenchCodecs(*bench);
  registerBenchScaling(*bench);
  registerBenchQuantization(*bench);
  registerBenchEigen(*bench);
}

}  // namespace acpca::cli
