// `adaptive-cpca view`: the interactive viewer (viewer/viewer.h) behind a
// command line, with a clear refusal where there is no display to open.
#include <netdb.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>

#include "cluster/model_file.h"
#include "core/error.h"
#include "relight/spec_parsing.h"
#include "tools/cli_common.h"
#include "tools/commands.h"
#include "viewer/viewer.h"

namespace acpca::cli {

namespace {

struct ViewArgs {
  std::string model, background = "env", script, screenshot, saveDir = ".";
  std::vector<std::string> envs;
  std::string rotate;
  double exposure = 0, rotateStep = 0;
  int rankPercent = 100, frames = 0, threads = 0;
  bool fastRotation = false, quiet = false;
};

bool connects(int domain, const sockaddr* address, socklen_t length) {
  const int fd = ::socket(domain, SOCK_STREAM, 0);
  if (fd < 0) return false;
  const bool ok = ::connect(fd, address, length) == 0;
  ::close(fd);
  return ok;
}

/// Why no window can be opened, or "" when an X server answers at $DISPLAY.
/// OpenCV's Qt back end aborts the process when it cannot connect, so ask first.
std::string displayProblem() {
  const char* qpa = std::getenv("QT_QPA_PLATFORM");
  if (qpa && std::strcmp(qpa, "offscreen") == 0) return "";  // headless on purpose
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
    return "no display: DISPLAY is not set. Run it on a desktop, over ssh -X, or under "
           "xvfb-run; for images without a window use `adaptive-cpca relight`";
  // DISPLAY is [host]:number[.screen].
  const std::string text = display;
  const auto colon = text.rfind(':');
  const std::string host = colon == std::string::npos ? "" : text.substr(0, colon);
  const std::string number = text.substr(colon == std::string::npos ? 0 : colon + 1);
  const std::string server = number.substr(0, number.find('.'));
  const std::string unreachable =
      concat("no display: nothing answers at DISPLAY='", text, "' (is the X server running?)");
  if (server.empty() || server.find_first_not_of("0123456789") != std::string::npos)
    return concat("no display: cannot read DISPLAY='", text, "'");
  if (host.empty() || host == "unix") {
    sockaddr_un address{};
    address.sun_family = AF_UNIX;
    const std::string socketPath = "/tmp/.X11-unix/X" + server;
    std::strncpy(address.sun_path, socketPath.c_str(), sizeof address.sun_path - 1);
    if (connects(AF_UNIX, reinterpret_cast<sockaddr*>(&address), sizeof address)) return "";
    if (host == "unix") return unreachable;
  }
  addrinfo hints{}, *found = nullptr;
  hints.ai_socktype = SOCK_STREAM;
  const std::string port = std::to_string(6000 + std::stoi(server));
  if (::getaddrinfo(host.empty() ? "localhost" : host.c_str(), port.c_str(), &hints, &found) != 0)
    return unreachable;
  bool ok = false;
  for (addrinfo* a = found; a && !ok; a = a->ai_next)
    ok = connects(a->ai_family, a->ai_addr, a->ai_addrlen);
  ::freeaddrinfo(found);
  return ok ? "" : unreachable;
}

void run(const ViewArgs& a) {
  ViewerOptions o;
  o.modelPath = a.model;
  o.envSpecs = expandEnvironments(
      a.envs.empty() ? std::vector<std::string>{"sky", "sun:50,30,4,1000"} : a.envs);
  o.background = parseBackground(a.background);
  if (o.background == Background::Alpha)
    throw UserError("--background alpha: the viewer shows env or black");
  if (!a.rotate.empty()) {
    // The viewer turns yaw and pitch only; "YAW,PITCH" is short for "YAW,PITCH,0".
    const bool twoAngles = std::count(a.rotate.begin(), a.rotate.end(), ',') == 1;
    const auto rotations = parseRotationSpec(twoAngles ? a.rotate + ",0" : a.rotate);
    if (rotations.size() != 1 || rotations[0].roll != 0)
      throw UserError(concat("--rotate '", a.rotate, "': give one YAW[,PITCH] for the viewer"));
    o.initial.yaw = rotations[0].yaw;
    o.initial.pitch = rotations[0].pitch;
  }
  o.initial.exposure = a.exposure;
  if (a.rankPercent < 0 || a.rankPercent > 100)
    throw UserError(concat("--rank-percent ", a.rankPercent, ": give 0..100"));
  o.initial.rankPercent = a.rankPercent;
  o.rotationMode = a.fastRotation ? RotationMode::FastLattice : RotationMode::Exact;
  if (a.frames < 0) throw UserError("--frames must be >= 0");
  o.frames = a.frames;
  o.rotateStep = a.rotateStep;
  o.screenshot = a.screenshot;
  o.saveDir = a.saveDir;
  o.log = stderrLog("view", a.quiet);
  if (!a.script.empty()) o.script = readViewerScript(a.script);
  if (!isModelFile(a.model))
    throw UserError(concat("'", a.model,
                           "' is not a model file: view relights models (`compress` makes one); "
                           "a dense transport is too slow to turn interactively"));
  if (const std::string problem = displayProblem(); !problem.empty()) throw UserError(problem);
  ThreadLimit limit(a.threads);
  Viewer viewer(o);
  viewer.run();
}

}  // namespace

void registerView(CLI::App& app) {
  auto args = std::make_shared<ViewArgs>();
  auto* sub = app.add_subcommand(
      "view",
      "Relight a model live in a window: drag to turn the lighting (keys: n/p env map, c cluster "
      "boundaries, h rank heat map, l lighting inset, a/d yaw, r reset, +/- exposure, s save, q "
      "quit)");
  sub->add_option("model", args->model, "Model file (M_FILE)")->required();
  sub->add_option("--env", args->envs,
                  "Lighting (as relight takes it; repeatable; default: sky and a sun)");
  sub->add_option("--rotate", args->rotate, "Initial YAW[,PITCH] in degrees");
  sub->add_option("--exposure", args->exposure, "Initial exposure in stops");
  sub->add_option("--rank-percent", args->rankPercent,
                  "Initial share of each cluster's bases, 0..100 (the quality/speed trackbar)");
  sub->add_option("--background", args->background, "env or black");
  sub->add_option("--save-dir", args->saveDir, "Where the s key writes EXR + PNG (default .)");
  sub->add_option("--script", args->script,
                  "Drive the window from a file of events (key, drag, rotate, exposure, rank, "
                  "env, save, screenshot, wait), then quit");
  sub->add_option("--frames", args->frames,
                  "Self-driving: show N frames, turning the yaw by --rotate-step each, then quit");
  sub->add_option("--rotate-step", args->rotateStep, "Degrees of yaw per frame with --frames");
  sub->add_option("--screenshot", args->screenshot,
                  "PNG of the window's last frame (image and status line), written on quitting");
  sub->add_flag("--fast-rotation", args->fastRotation,
                "Rotate by bilinear lookup on the lattice (fast, not energy-preserving)");
  sub->add_option("--threads", args->threads, "Worker threads (0: all cores)")
      ->check(CLI::NonNegativeNumber);
  sub->add_flag("-q,--quiet", args->quiet, "No messages on stderr");
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
