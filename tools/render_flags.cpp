#include "tools/render_flags.h"

#include "tools/cli_common.h"

namespace acpca::cli {

void RenderFlags::add(CLI::App& app) {
  app.add_option("--scene", scene, "Built-in scene name or scene JSON file")->required();
  app.add_option("--size", size, "Image size WxH (default: the scene's)");
  app.add_option("--camera", camera,
                 "auto: frame the scene's bounds from its camera's direction; auto:THETA,PHI: "
                 "from that direction (degrees: THETA from +Y, PHI from -Z towards +X)");
  app.add_option("--cubemap", values.cubemapResolution,
                 "Cube-map face resolution R (6 R^2 directions)");
  app.add_option("--spp", values.samplesPerPixel,
                 "Camera samples per pixel: anti-aliased silhouettes and textures")
      ->capture_default_str();
  app.add_option("--aa", antialiasing,
                 "adaptive: trace every sample only where they see different surfaces "
                 "(default); full: everywhere, shadow edges too, at spp times the cost");
  app.add_flag("--force", values.force,
               "Start even when the disk or memory looks too small for the whole image");
  app.add_option("--texel-rays", values.texelRays,
                 "Occlusion rays per texel (fractional visibility)");
  app.add_option("--precision", precision,
                 "Stored precision: f16 or f32 (build rounds its rows the same way)");
  app.add_option("--bounces", values.bounces,
                 "Interreflections: light that bounces up to K times off scene surfaces "
                 "(0: direct light)")
      ->capture_default_str();
  app.add_option("--indirect-samples", values.indirectSamples,
                 "Paths per traced camera sample for the bounced light: noise falls as they rise")
      ->capture_default_str();
  app.add_option("--indirect-cache", values.indirectCacheCell,
                 "Path vertices share the visibility of one point per cell of this size, a "
                 "fraction of the scene's extent; 0 traces every vertex's own shadow rays "
                 "(unbiased, slow)")
      ->capture_default_str();
  nameParameters(app, {{"--cubemap", {"cube-map resolution"}},
                       {"--spp", {"samples per pixel"}},
                       {"--texel-rays", {"rays per texel"}},
                       {"--indirect-cache", {"indirect cache cell"}}});
}

PrecomputeOptions RenderFlags::options(int threads) const {
  PrecomputeOptions o = values;
  o.antialiasing = kAntialiasingNames.parse(antialiasing);
  o.precision = parsePrecision(precision);
  o.threads = threads;
  return o;
}

Scene RenderFlags::loadScene() const {
  Scene s = acpca::loadScene(scene);
  // --size and --camera apply to every view.
  std::vector<Camera> views = s.views.empty() ? std::vector<Camera>{s.camera} : s.views;
  for (Camera& view : views) {
    s.camera = view;
    if (!size.empty()) s.camera.size = parseImageSize(size, "--size");
    applyCameraSpec(s, camera);
    view = s.camera;
  }
  s.camera = views[0];
  if (!s.views.empty()) s.views = views;
  s.validate();
  return s;
}

void CompressFlags::add(CLI::App& app, bool streamed) {
  if (streamed)
    app.add_option("--method", method,
                   "adaptive-quad (default; the tiles are its root blocks), block, or cpca and "
                   "adaptive-binary (each group of --tile pixels clustered on its own)");
  else
    app.add_option("--method", method, "global, block, cpca, adaptive-quad or adaptive-binary")
        ->required();
  app.add_option("--tolerance", values.tolerance, "Fraction of each cluster's energy kept");
  app.add_option("--global-energy", values.globalEnergy,
                 "Fraction of energy the global basis keeps (1: every direction)");
  app.add_option("--clusters", values.clusters,
                 streamed ? "cpca: K over the image; adaptive-binary: initial clusters per group"
                          : "cpca: K; adaptive-binary: initial clusters");
  app.add_option("--block", values.block, "block: side (default 8); adaptive-quad: root side (64)");
  app.add_flag("--exact-tree", values.exactQuadTree,
               "adaptive-quad: bottom-up optimal tree instead of the paper's greedy test");
  if (!streamed) {
    app.add_flag("--allocate-ranks", values.allocateRanks,
                 "Spend one error budget, (1 - tolerance) of all energy, where it buys the most");
    app.add_flag("--force", values.force,
                 "Go on even when the projection looks too large for memory");
  }
  app.add_option("--coeffs", coeffs, "Coefficient storage: f32, f16 or i8");
  app.add_option("--bases", bases,
                 "Cluster basis storage: f32 or f16 (halves the bytes a frame reads for them)");
  app.add_option("--sample-rows", values.sampleRows, "Rows sampled for the global basis");
  app.add_option("--clustering-dims", values.clusteringDims,
                 "cpca, adaptive-binary: leading global coefficients rows are clustered on "
                 "(0: all)");
  app.add_option("--seed", values.seed, "Random seed (sampling, CPCA seeding)");
  nameParameters(app, {{"--block", {"block side"}},
                       {"--coeffs", {"coefficient precision"}},
                       {"--bases", {"basis precision"}},
                       {"--clustering-dims", {"clustering dimensions"}}});
}

CompressOptions CompressFlags::options() const {
  CompressOptions o = values;
  o.method = method.empty() ? values.method : parseMethod(method);
  o.coeffs = parseCoeffPrecision(coeffs);
  o.bases = parseBasisPrecision(bases);
  return o;
}

}  // namespace acpca::cli
