#pragma once
// `adaptive-cpca view`: a window (OpenCV highgui) that relights a model live as
// the user turns the lighting and moves local lights. A worker thread relights and draws each frame
// into a new canvas; the UI thread only shows the latest finished canvas, so it
// never stalls on a relight and never shows a half-drawn frame.
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>
#include <thread>
#include <vector>

#include "imageio/frame_metadata.h"
#include "imageio/image_output.h"
#include "lighting/domain_lighting.h"
#include "lighting/environment.h"
#include "lighting/lighting.h"
#include "lighting/map_sources.h"
#include "lighting/sh_lighting.h"
#include "relight/image_composer.h"
#include "relight/lamp_light.h"
#include "relight/local_columns.h"
#include "relight/model_relighter.h"
#include "viewer/view_input.h"
#include "viewer/viewer_script.h"

namespace acpca {

struct ViewerOptions {
  std::string modelPath;
  std::vector<std::string> envSpecs{"sky", "sun:50,30,4,1000"};
  ViewState initial;
  RotationMode rotationMode = RotationMode::Exact;
  Background background = Background::Env;
  std::string saveDir = ".";
  /// Self-driving runs (tests, demos): a script of events, or `frames` frames
  /// turning the yaw by rotateStep each; then `screenshot` (if set) and quit.
  std::vector<ScriptEvent> script;
  int frames = 0;
  double rotateStep = 0;
  std::string screenshot;
  /// Messages for the user (saved files, the key help); none when empty.
  std::function<void(const std::string&)> log;
};

/// `view` with the yaw and pitch of "YAW[,PITCH]" (degrees); ParameterError
/// for anything else (the viewer does not roll).
ViewState parseViewerRotation(const std::string& text, ViewState view);

/// Refuses options the viewer cannot show, before any window opens.
void validateViewerOptions(const ViewerOptions& options);

class Viewer {
 public:
  explicit Viewer(const ViewerOptions& options);
  ~Viewer();
  /// Opens the window and runs until the user quits (or the script ends).
  void run();

 private:
  /// A finished frame; nothing in it changes once published.
  struct Frame {
    cv::Mat canvas;                       ///< BGR: the image with its overlays, then a status strip
    std::shared_ptr<const Image> linear;  ///< the relit image (for saving)
    ViewState state;
    long long serial = 0;
    nlohmann::json sh9, sources;  ///< its lighting's SH and the map's sources, as a manifest's
    double costPerPixel = 0;      ///< the cost metric per pixel at its rank limit
  };
  // Worker side.
  void workerLoop();
  Frame render(const ViewState& state, long long serial);
  void drawOverlays(const ViewState& state, cv::Mat& image) const;
  void drawLights(const ViewState& state, cv::Mat& image) const;
  /// The local lights' rows (relit again only when the lights or ranks change).
  void relightLocal(const ViewState& state);
  /// Map `env` with its sources split off (once; none where the model cannot
  /// light them exactly), as relight --sun auto splits it.
  const SplitEnvironment& splitOf(int env);
  /// The map's sources' rows, exact (or as points while the map is held).
  void relightSources(const ViewState& state);
  void drawStatus(const ViewState& state, cv::Mat& canvas) const;
  // UI side.
  void request();
  void showLatest();
  void waitForLatestRequest();
  bool applyKey(int key);  ///< false: quit
  /// held: the button is still down (the map's sources lit as points).
  void applyDrag(int dx, int dy, bool held);
  void applyLightDrag(int light, int dx, int dy);
  /// A lamp taken (true) or let go by the mouse or a script's press/release.
  void holdLamp(bool held);
  /// The map let go: its sources lit exactly again.
  void releaseMap();
  void applyWheel(double notches);
  void applyEvent(const ScriptEvent& event);
  void savePictures(const std::string& stem) const;
  /// What a saved frame says of itself: a batch frame's header for the same view.
  FrameMetadata headerOf(const Frame& frame) const;
  /// After a script: how long the frames took (the worker idle).
  std::string frameSummary();
  void say(const std::string& text) const {
    if (options_.log) options_.log(text);
  }
  void writeScreenshot(const std::string& path) const;
  void createTrackbars();
  void syncTrackbars();
  static void onMouse(int event, int x, int y, int flags, void* self);
  static void onTrackbar(int position, void* self);

  ViewerOptions options_;
  std::unique_ptr<ModelRelighter> relighter_;
  std::vector<std::unique_ptr<Environment>> envs_;
  std::unique_ptr<DomainLighting> domain_;       ///< the lattice, or a captured light set's cells
  std::unique_ptr<ShProjector> sh_;              ///< a frame's sh9, for the headers of saved frames
  nlohmann::json sh9_, sources_;                 ///< the last relit map's sh9 and sources
  double costPerPixel_ = 0;                      ///< its cost metric at its rank limit
  mutable std::vector<std::string> fileHashes_;  ///< the model's, then each map's ("" unhashed)
  int width_ = 0, height_ = 0, maxRank_ = 0;
  std::vector<int> clusterOfPixel_;  ///< -1 for background
  ViewContext context_;
  std::unique_ptr<ImageComposer> composer_;

  // Worker cache: the last relit image, its map part and local-light rows,
  // and what they were relit for.
  std::shared_ptr<const Image> linear_;
  Image mapPart_;
  std::vector<float> localRows_;
  std::vector<std::unique_ptr<SplitEnvironment>> splits_;  ///< per map, made on first use
  std::vector<float> sourceRows_;                          ///< empty: no source
  ViewState sourcesFor_;
  bool sourcesDone_ = false;
  std::unique_ptr<LocalLightColumns> columns_;  ///< kept while lamps move
  /// Lamps lit exactly, where the model allows (null otherwise).
  std::unique_ptr<ExactLamps> exactLamps_;
  std::string latticeLamps_;  ///< why not, in words (empty: exact)
  bool warnedLamps_ = false;
  std::string localProblem_;  ///< why the lights are not shown, if they cannot be
  LatticeLighting lighting_;
  ViewState relitFor_, localFor_;
  bool localDone_ = false;
  /// Milliseconds of each part of the last frame (0: kept from the one before).
  struct FrameTimes {
    double lighting = 0, relight = 0, lights = 0, compose = 0, draw = 0;
  };
  FrameTimes times_;
  std::vector<double> frameMs_;  ///< every frame's total, for the scripted summary

  std::mutex mutex_;
  std::condition_variable wake_, finished_;
  ViewState state_;          ///< guarded: the latest request
  long long requested_ = 0;  ///< guarded: serial of the latest request
  Frame latest_;             ///< guarded: the latest finished frame
  bool stop_ = false;
  std::thread worker_;

  // UI thread only.
  Frame onScreen_;
  ViewState ui_;
  DragTracker drag_;
  int heldLight_ = -1;          ///< the lamp a script's press holds, -1: none
  bool scriptPressed_ = false;  ///< a script's press not yet released
  bool syncing_ = false;
};

}  // namespace acpca
