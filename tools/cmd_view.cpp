// `adaptive-cpca view`: the interactive viewer (viewer/viewer.h) behind a
// command line, with a clear refusal where there is no display to open.

#include "core/error.h"
#include "lighting/environment.h"
#include "lighting/local_light.h"
#include "lighting/spec_parsing.h"
#include "tools/cli_common.h"
#include "tools/commands.h"
#include "viewer/display_check.h"
#include "viewer/viewer.h"

namespace acpca::cli {

namespace {

struct ViewArgs {
  ViewerOptions options;                   ///< the flags that set a field of it directly
  std::string background, script, rotate;  ///< background empty: env (black: a light set)
  std::vector<std::string> envs, lights;
  int threads = 0;
  bool quiet = false;
};

void run(const ViewArgs& a) {
  ViewerOptions o = a.options;
  if (!a.envs.empty()) o.envSpecs = expandEnvironmentSpecs(a.envs);
  o.background = backgroundFor(a.background, o.modelPath);
  if (!a.rotate.empty()) o.initial = parseViewerRotation(a.rotate, o.initial);
  for (const std::string& spec : a.lights) o.initial.lights.push_back(parseLocalLight(spec));
  if (!o.initial.lights.empty()) o.initial.selectedLight = 0;
  o.log = stderrLog("view", a.quiet);
  if (!a.script.empty()) o.script = readViewerScript(a.script);
  validateViewerOptions(o);
  if (const std::string problem = displayProblem(); !problem.empty())
    throw UserError(problem + "; for images without a window use `adaptive-cpca relight`");
  ThreadLimit limit(a.threads);
  Viewer viewer(o);
  viewer.run();
}

}  // namespace

void registerView(CLI::App& app) {
  auto args = std::make_shared<ViewArgs>();
  auto* sub = app.add_subcommand(
      "view",
      "Relight a model live in a window: drag to turn the lighting, drag a drawn light to move "
      "it, wheel to move it in depth (keys: n/p env map, i add a light, o remove it, Tab next "
      "light, [/] nearer/farther, c cluster boundaries, h rank heat map, l lighting inset, a/d "
      "yaw, r reset, +/- exposure, s save, q quit)");
  sub->add_option("model", args->options.modelPath, "Model file (M_FILE)")->required();
  sub->add_option("--env", args->envs,
                  "Lighting (as relight takes it; repeatable; default: sky and a sun)");
  sub->add_option("--rotate", args->rotate, "Initial YAW[,PITCH] in degrees");
  sub->add_option("--light", args->lights,
                  "A local light to start with (as relight takes it; repeatable)");
  sub->add_option("--exposure", args->options.initial.exposure, "Initial exposure in stops");
  sub->add_option("--rank-percent", args->options.initial.rankPercent,
                  "Initial share of each cluster's bases, 0..100 (the quality/speed trackbar)");
  sub->add_option("--background", args->background,
                  "env or black (default: env; black for a captured light set)");
  sub->add_option("--save-dir", args->options.saveDir,
                  "Where the s key writes EXR + PNG (default .)");
  sub->add_option("--script", args->script,
                  "Drive the window from a file of events (key, drag, dragfrom, wheel, light, "
                  "rotate, exposure, rank, env, save, screenshot, wait), then quit");
  sub->add_option("--frames", args->options.frames,
                  "Self-driving: show N frames, turning the yaw by --rotate-step each, then quit");
  sub->add_option("--rotate-step", args->options.rotateStep,
                  "Degrees of yaw per frame with --frames");
  sub->add_option("--screenshot", args->options.screenshot,
                  "PNG of the window's last frame (image and status line), written on quitting");
  addFastRotationFlag(*sub, args->options.rotationMode);
  sub->add_option("--threads", args->threads, "Worker threads (0: all cores)")
      ->check(CLI::NonNegativeNumber);
  sub->add_flag("-q,--quiet", args->quiet, "No messages on stderr");
  nameParameters(
      *sub,
      {{"--env", {"environment"}}, {"--rotate", {"rotation"}}, {"--script", {"viewer script"}}});
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
