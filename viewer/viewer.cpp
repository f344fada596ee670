#include "viewer/viewer.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/highgui.hpp>  // the mouse events' codes; calls go through windowSystem()
#include <opencv2/imgproc.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/file_hash.h"
#include "core/stopwatch.h"
#include "core/warning.h"
#include "imageio/image_output.h"
#include "lighting/envmap_export.h"
#include "lighting/map_source_listing.h"
#include "model/model.h"
#include "pictures/pictures.h"
#include "relight/lamp_light.h"
#include "relight/local_relight.h"
#include "relight/rank_limit.h"
#include "viewer/window_system.h"

namespace acpca {

static_assert(kHeldDiscRadius < kPointDiscRadius, "a held map's sources are lit as points");

namespace {

constexpr const char* kWindow = "adaptive-cpca view";
constexpr const char* kExposureBar = "exposure";
constexpr const char* kRankBar = "rank %";
constexpr const char* kEnvBar = "env map";

EnvRotation rotationOf(const ViewState& s) {
  return EnvRotation{s.yaw, s.pitch, 0};
}

bool sameRelight(const ViewState& a, const ViewState& b) {
  return a.env == b.env && a.yaw == b.yaw && a.pitch == b.pitch && a.rankPercent == b.rankPercent;
}

}  // namespace

Viewer::Viewer(const ViewerOptions& options) : options_(options) {
  {
    const std::shared_ptr<const PackedModel> packed = readPackedModel(options.modelPath);
    relighter_ = std::make_unique<ModelRelighter>(packed);
    const TransportHeader& g = packed->geometry;
    width_ = g.camera.size.width;
    height_ = g.camera.size.height;
    clusterOfPixel_ = clusterOfPixel(g, packed->clusterOfRow());
    maxRank_ =
        packed->ranks.empty() ? 0 : *std::max_element(packed->ranks.begin(), packed->ranks.end());
  }
  latticeLamps_ = exactLampsUnavailable(relighter_->geometry(), true);
  if (latticeLamps_.empty()) exactLamps_ = std::make_unique<ExactLamps>(relighter_->geometry());
  for (const auto& spec : options.envSpecs) envs_.push_back(loadEnvironment(spec));
  if (envs_.empty()) throw ParameterError("environment", "", "give at least one lighting");
  const TransportHeader& g = relighter_->geometry();
  domain_ = std::make_unique<DomainLighting>(g);
  sh_ = std::make_unique<ShProjector>(*domain_);
  requireBackgroundShown(g, options.background, options.modelPath);
  composer_ = std::make_unique<ImageComposer>(g);
  context_.envs = static_cast<int>(envs_.size());
  context_.camera = g.camera;
  if (g.hasPositions() && g.rows() > 0) context_.newLight = keyLightFor(g);
  requireLocalLightsApply(g, options.modelPath, true, options.initial.lights);
  ui_ = options.initial;
  ui_.env = std::clamp(ui_.env, 0, static_cast<int>(envs_.size()) - 1);
}

Viewer::~Viewer() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (worker_.joinable()) worker_.join();
}

// ---- worker thread ---------------------------------------------------------

void Viewer::workerLoop() {
  long long done = 0;
  for (;;) {
    ViewState state;
    long long serial;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || requested_ > done; });
      if (stop_) return;
      state = state_;
      serial = requested_;  // older requests are superseded, not drawn
    }
    Frame frame = render(state, serial);
    {
      std::lock_guard lock(mutex_);
      latest_ = std::move(frame);
    }
    finished_.notify_all();
    done = serial;
  }
}

Viewer::Frame Viewer::render(const ViewState& state, long long serial) {
  // What this frame does: parts it keeps from the last one cost nothing.
  times_ = {};
  const bool mapChanged = !linear_ || !sameRelight(state, relitFor_);
  if (mapChanged) {
    const Environment& env = *envs_[state.env];
    const SplitEnvironment& split = splitOf(state.env);
    const EnvRotation rotation = rotationOf(state);
    Stopwatch t;
    // The lattice lights what the sources leave; the background is the whole map.
    lighting_ = (*domain_)(split.rest ? *split.rest : env, rotation, options_.rotationMode);
    const std::vector<MapSource> sources = turnedSources(split.sources, rotation);
    sh9_ = sh9Json(sh_->project(lighting_), sources);
    sources_ = sourcesJson(sources);
    times_.lighting = t.milliseconds();
    relighter_->setRankFraction(state.rankPercent / 100.0);
    costPerPixel_ = costMetricPerPixel(*relighter_);  // walks every row: once a relight
    // Into the buffer of the last frame's map part, with the composer made
    // at open (its background rays are the camera's): a 1024x1024 frame
    // spent a third of its time making both anew.
    t.restart();
    mapPart_.width = width_;
    mapPart_.height = height_;
    mapPart_.channels = ImageComposer::channels(options_.background);
    mapPart_.pixels.resize(static_cast<size_t>(width_) * height_ * mapPart_.channels);
    composer_->background(options_.background, env, rotationMatrix(rotation),
                          mapPart_.pixels.data());
    times_.compose = t.milliseconds();
    t.restart();
    relighter_->relightInto(lighting_, mapPart_.pixels.data(), mapPart_.channels);
    times_.relight = t.milliseconds();
    relitFor_ = state;
  }
  // The lights' part depends on the lights and the ranks in use only.
  const bool lightsChanged = !localDone_ || !sameLights(litLights(state), litLights(localFor_)) ||
                             state.rankPercent != localFor_.rankPercent;
  if (lightsChanged) relightLocal(state);
  const bool sourcesChanged = !sourcesDone_ || state.env != sourcesFor_.env ||
                              state.yaw != sourcesFor_.yaw || state.pitch != sourcesFor_.pitch ||
                              state.mapHeld != sourcesFor_.mapHeld;
  if (sourcesChanged) relightSources(state);
  if (mapChanged || lightsChanged || sourcesChanged) {
    // As relight sums them: the map's image, then the lights' and the
    // sources' rows added.
    const Stopwatch t;
    Image image = mapPart_;
    for (const std::vector<float>* rows : {&localRows_, &sourceRows_})
      if (!rows->empty()) composer_->addRows(rows->data(), image.pixels.data(), image.channels);
    linear_ = std::make_shared<const Image>(std::move(image));
    times_.compose += t.milliseconds();
  }
  const Stopwatch drawWatch;
  cv::Mat image = toneMappedBgr(*linear_, state.exposure);
  drawOverlays(state, image);
  drawLights(state, image);
  Frame frame;
  times_.draw = drawWatch.milliseconds();
  frameMs_.push_back(times_.lighting + times_.relight + times_.lights + times_.compose +
                     times_.draw);
  drawStatus(state, image);
  frame.canvas = image;
  frame.linear = linear_;
  frame.state = state;
  frame.serial = serial;
  frame.sh9 = sh9_;
  frame.sources = sources_;
  frame.costPerPixel = costPerPixel_;
  return frame;
}

void Viewer::relightLocal(const ViewState& state) {
  localFor_ = state;
  localDone_ = true;
  localProblem_.clear();
  localRows_.clear();
  if (state.lights.empty()) return;
  const Stopwatch t;
  try {
    requireLocalLightsApply(relighter_->geometry(), options_.modelPath, true, state.lights);
    // As a batch lights them (relight_source.h): the same image for the same
    // lamps; while a lamp is held, sphere lamps as points (previewLights).
    localRows_ = relightLocalLights(
        litLights(state), LampMode::Exact, exactLamps_.get(),
        [&](const std::vector<LocalLight>& some) {
          if (!columns_) columns_ = std::make_unique<LocalLightColumns>(relighter_->packed());
          return modelLocalRelight(*relighter_, some, kAnchorSpreadTexels, columns_.get());
        },
        [&] {
          if (!std::exchange(warnedLamps_, true))
            warn(latticeLampsWarning(options_.modelPath, latticeLamps_));
        });
  } catch (const UserError& error) {
    localProblem_ = error.what();  // shown in the status line; the map still shows
  }
  times_.lights = t.milliseconds();
}

const SplitEnvironment& Viewer::splitOf(int env) {
  if (splits_.size() != envs_.size()) splits_.resize(envs_.size());
  std::unique_ptr<SplitEnvironment>& split = splits_[env];
  if (!split) {
    split = std::make_unique<SplitEnvironment>();
    if (exactLamps_) *split = envs_[env]->splitSources(*parseSourceFinding("auto"));
  }
  return *split;
}

void Viewer::relightSources(const ViewState& state) {
  sourcesFor_ = state;
  sourcesDone_ = true;
  sourceRows_.clear();
  const SplitEnvironment& split = splitOf(state.env);
  if (split.sources.empty()) return;
  const Stopwatch t;
  const Eigen::Matrix3d rotation = rotationMatrix(rotationOf(state));
  std::vector<MapSource> turned;
  for (const MapSource& source : state.mapHeld ? previewSources(split.sources) : split.sources)
    turned.push_back(source.turned(rotation));
  sourceRows_ = exactLamps_->relight({}, kDefaultSphereLampRays, turned);
  times_.lights += t.milliseconds();
}

void Viewer::request() {
  {
    std::lock_guard lock(mutex_);
    state_ = ui_;
    ++requested_;
  }
  wake_.notify_all();
}

void Viewer::showLatest() {
  {
    std::lock_guard lock(mutex_);
    if (latest_.serial == onScreen_.serial) return;
    onScreen_ = latest_;  // shares the finished canvas; the worker draws the next into a new one
  }
  windowSystem().show(kWindow, onScreen_.canvas);
}

void Viewer::waitForLatestRequest() {
  {
    std::unique_lock lock(mutex_);
    finished_.wait(lock, [&] { return latest_.serial >= requested_; });
  }
  showLatest();
  windowSystem().waitKey(1);  // lets the window draw it
}

void Viewer::applyDrag(int dx, int dy, bool held) {
  ui_ = acpca::applyDrag(ui_, dx, dy, width_, height_);
  ui_.mapHeld = held;
  request();
}

void Viewer::releaseMap() {
  if (!ui_.mapHeld) return;
  ui_.mapHeld = false;
  request();  // let go: the sources lit exactly
}

void Viewer::applyLightDrag(int light, int dx, int dy) {
  ui_ = moveLightAcross(ui_, light, dx, dy, context_.camera);
  request();
}

void Viewer::holdLamp(bool held) {
  if (ui_.lampHeld == held) return;
  ui_.lampHeld = held;
  request();  // let go: the frame at full quality
}

void Viewer::applyWheel(double notches) {
  const ViewState next = moveLightInDepth(ui_, notches, context_.camera);
  if (next == ui_) return;
  ui_ = next;
  request();
}

bool Viewer::applyKey(int key) {
  if (key == 'i' && !relighter_->geometry().hasPositions()) {
    say(concat(options_.modelPath,
               ": has no pixel positions, which local lights need; precompute its transport "
               "again and compress (or build) it again"));
    return true;
  }
  const ViewUpdate u = acpca::applyKey(ui_, key, context_);
  if (u.action == ViewAction::Quit) return false;
  if (u.action == ViewAction::Save) savePictures("");
  if (u.state == ui_) return true;
  ui_ = u.state;
  syncTrackbars();
  request();
  return true;
}

void Viewer::savePictures(const std::string& stem) const {
  if (!onScreen_.linear) return;
  namespace fs = std::filesystem;
  const ViewState& s = onScreen_.state;
  const fs::path base = stem.empty()
                            ? fs::path(options_.saveDir) /
                                  concat("view_", envs_[s.env]->name(), "_", rotationOf(s).label())
                            : fs::path(stem);
  const FrameMetadata header = headerOf(onScreen_);
  for (ImageFormat format : {ImageFormat::Exr, ImageFormat::Png}) {
    const std::string path = base.string() + imageExtension(format);
    ImageEncoding encoding;
    encoding.metadata = &header;
    AtomicOutput output(path);
    encodeImage(*onScreen_.linear, output.tempPath(), path, format, s.exposure, encoding);
    output.commit();
    std::string lights;  // what relight --light takes, to make the same image in a batch
    for (const LocalLight& light : s.lights) lights += " --light " + light.canonicalSpec();
    say(concat("saved ", path, lights.empty() ? "" : " under" + lights));
  }
}

FrameMetadata Viewer::headerOf(const Frame& frame) const {
  const ViewState& s = frame.state;
  if (fileHashes_.empty()) {  // once: the model's hash reads the whole file
    fileHashes_.push_back(sha256OfFile(options_.modelPath));
    for (const std::string& spec : options_.envSpecs)
      fileHashes_.push_back(isAnalyticEnvironment(spec) ? "" : sha256OfFile(spec));
  }
  nlohmann::json lights = nlohmann::json::array();
  for (const LocalLight& light : s.lights) lights.push_back(light.canonicalSpec());
  const EnvRotation rotation = rotationOf(s);
  FrameMetadata m;
  m.fields = {{"env", options_.envSpecs[s.env]},
              {"yaw", rotation.yaw},
              {"pitch", rotation.pitch},
              {"roll", rotation.roll},
              {"exposure", s.exposure},
              {"lights", lights},
              {"sh9", frame.sh9},
              {"sources", frame.sources},
              {"source", std::filesystem::path(options_.modelPath).filename().string()},
              {"source_sha256", fileHashes_[0]},
              {"method", relighter_->packed()->method},
              {"cost_per_pixel", frame.costPerPixel},
              {"version", ACPCA_VERSION}};
  if (!fileHashes_[s.env + 1].empty()) m.fields["env_sha256"] = fileHashes_[s.env + 1];
  const TransportHeader& g = relighter_->geometry();
  if (!g.isLightSet()) m.setCamera(g.camera.worldToCamera(), g.camera.worldToNdc());
  return m;
}

void Viewer::writeScreenshot(const std::string& path) const {
  writePng(onScreen_.canvas, path);
  say(concat("screenshot ", path));
}

void Viewer::createTrackbars() {
  windowSystem().addTrackbar(kExposureBar, kWindow, kExposureSteps, &Viewer::onTrackbar, this);
  windowSystem().addTrackbar(kRankBar, kWindow, 100, &Viewer::onTrackbar, this);
  if (envs_.size() > 1)
    windowSystem().addTrackbar(kEnvBar, kWindow, static_cast<int>(envs_.size()) - 1,
                               &Viewer::onTrackbar, this);
  syncTrackbars();
}

void Viewer::syncTrackbars() {
  // Setting a position calls onTrackbar, which would read the bars not yet set.
  syncing_ = true;
  windowSystem().setTrackbar(kExposureBar, kWindow, exposurePosition(ui_.exposure));
  windowSystem().setTrackbar(kRankBar, kWindow, ui_.rankPercent);
  if (envs_.size() > 1) windowSystem().setTrackbar(kEnvBar, kWindow, ui_.env);
  syncing_ = false;
}

void Viewer::onTrackbar(int, void* self) {
  auto* v = static_cast<Viewer*>(self);
  if (v->syncing_) return;
  ViewState next = applyExposurePosition(v->ui_, windowSystem().trackbar(kExposureBar, kWindow));
  if (const int rank = windowSystem().trackbar(kRankBar, kWindow); rank >= 0)
    next.rankPercent = rank;
  if (v->envs_.size() > 1)
    if (const int env = windowSystem().trackbar(kEnvBar, kWindow); env >= 0) next.env = env;
  if (next.exposure == v->ui_.exposure && next.rankPercent == v->ui_.rankPercent &&
      next.env == v->ui_.env)
    return;
  v->ui_ = next;
  v->request();
}

void Viewer::onMouse(int event, int x, int y, int flags, void* self) {
  auto* v = static_cast<Viewer*>(self);
  int dx = 0, dy = 0;
  if (event == cv::EVENT_LBUTTONDOWN) {
    const int light = lightUnder(v->ui_, x, y, v->context_.camera);
    v->drag_.press(x, y, v->height_, light);
    v->holdLamp(light >= 0);
  } else if (event == cv::EVENT_LBUTTONUP) {
    v->drag_.release();
    v->holdLamp(false);
    v->releaseMap();
  } else if (event == cv::EVENT_MOUSEWHEEL) {
    // One notch is 120; forward (away from the user) brings the light nearer.
    v->applyWheel(windowSystem().wheelDelta(flags) / 120.0);
  } else if (event == cv::EVENT_MOUSEMOVE &&
             v->drag_.move(x, y, (flags & cv::EVENT_FLAG_LBUTTON) != 0, dx, dy)) {
    if (v->drag_.light() >= 0)
      v->applyLightDrag(v->drag_.light(), dx, dy);
    else
      v->applyDrag(dx, dy, true);
  }
}

void Viewer::run() {
  windowSystem().open(kWindow);
  createTrackbars();
  windowSystem().onMouse(kWindow, &Viewer::onMouse, this);
  worker_ = std::thread([this] { workerLoop(); });
  request();
  waitForLatestRequest();

  std::vector<ScriptEvent> script = options_.script;
  // --frames turns the map as a drag does: held (its sources lit as points)
  // from the first step to the last, then let go (the last frame exact).
  if (options_.frames > 0) script.push_back({ScriptEvent::Kind::Press, -1, -1});
  for (int k = 0; k < options_.frames; ++k)
    script.push_back({ScriptEvent::Kind::Rotate, options_.initial.yaw + k * options_.rotateStep,
                      options_.initial.pitch});
  if (options_.frames > 0) script.push_back({ScriptEvent::Kind::Release, 0, 0});
  if (!options_.screenshot.empty())
    script.push_back({ScriptEvent::Kind::Screenshot, 0, 0, options_.screenshot});
  const bool scripted = !options_.script.empty() || options_.frames > 0;
  if (!scripted) script.clear();  // interactive: the screenshot is taken on quitting
  if (scripted) {
    for (const auto& event : script) applyEvent(event);
    waitForLatestRequest();
    say(frameSummary());
  } else {
    say("drag to turn the lighting, drag a drawn light to move it, wheel to move it in depth; "
        "keys: n/p env map, i add a light, o remove it, Tab next light, [/] nearer/farther, "
        "c clusters, h rank heat map, l lighting inset, a/d yaw, r reset, +/- exposure, s save, "
        "q quit");
    for (;;) {
      showLatest();
      const int key = windowSystem().waitKey(8);
      if (key >= 0 && !applyKey(key & 0xff)) break;
      if (!windowSystem().visible(kWindow)) break;  // closed
    }
    if (!options_.screenshot.empty()) writeScreenshot(options_.screenshot);
  }
  windowSystem().closeAll();
}

}  // namespace acpca
