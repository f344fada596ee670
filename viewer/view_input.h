#pragma once
// How the viewer's inputs change what it shows, as pure functions of the view
// state: keys, drags (of the lighting or of a local light), the wheel, mouse
// buttons, trackbar positions and script events. No window is involved, so
// all of it is tested without a display.
#include <string>
#include <vector>

#include "lighting/local_light.h"
#include "lighting/map_sources.h"
#include "transport/camera.h"
#include "transport/transport_file.h"

namespace acpca {

/// What the window shows; everything an input can change.
struct ViewState {
  int env = 0;
  double yaw = 0, pitch = 0;  ///< degrees
  double exposure = 0;        ///< stops
  int rankPercent = 100;      ///< share of each cluster's bases used
  bool clusterOverlay = false, rankHeatMap = false, lightingInset = false;
  std::vector<LocalLight> lights;  ///< local lights, summed with the map
  int selectedLight = -1;          ///< the light keys and the wheel move; -1: none
  /// A lamp held by the mouse: sphere lamps are lit as previewLights says
  /// until it is let go.
  bool lampHeld = false;
  /// The map being dragged: its sources are lit as previewSources says until
  /// the button is let go.
  bool mapHeld = false;
};

/// What inputs need to know about the view besides its state: the number of
/// maps, the model's camera, and the light the add key places.
struct ViewContext {
  int envs = 1;
  Camera camera;
  LocalLight newLight;
};

bool operator==(const ViewState& a, const ViewState& b);
/// Whether two lists hold the same lights (as their canonical specs say).
bool sameLights(const std::vector<LocalLight>& a, const std::vector<LocalLight>& b);

/// The light the add key places, a key light between the camera and what it
/// sees: a point light on the ray through image point (W/2, H/5) at 0.6 of
/// the pixels' median depth, as bright as a white sky of radiance 1 is from
/// above: irradiance pi at the median depth on the view axis. Needs positions.
LocalLight keyLightFor(const TransportHeader& geometry);

/// The lights as the viewer lights them while a lamp is held: each sphere
/// lamp as the point lamp of the same power at its centre (intensity L pi
/// r^2, what the sphere gives from afar), lit exactly with hard shadows at a
/// point lamp's cost; the rest as they are.
std::vector<LocalLight> previewLights(const std::vector<LocalLight>& lights);
/// A map's sources as the viewer lights them while the map is dragged: each
/// disc shrunk to a point (kHeldDiscRadius, below kPointDiscRadius) of the
/// same power, so its shadow is hard and costs a ray a sample, as a held
/// sphere lamp is lit as a point lamp.
std::vector<MapSource> previewSources(const std::vector<MapSource>& sources);
inline constexpr double kHeldDiscRadius = 1e-5;  ///< radians

/// The lights a frame of `state` is lit by: previewLights while a lamp is
/// held, else its lights.
std::vector<LocalLight> litLights(const ViewState& state);

/// What an input asks for beyond the new state.
enum class ViewAction { None, Save, Quit };

struct ViewUpdate {
  ViewState state;
  ViewAction action = ViewAction::None;
};

/// The exposure trackbar runs over -10..+10 stops in quarter stops.
inline constexpr int kExposureSteps = 80;
inline constexpr double kExposureStep = 0.25, kExposureMin = -10;

/// A key (its ASCII code): n or space / p the next / previous of the maps
/// (wrapping), c / h / l the cluster, rank and lighting overlays, a / d ten
/// degrees of yaw, r the rotation reset, + or = / - half a stop (within the
/// trackbar's range), i a new light (context.newLight, selected), o removes
/// the selected light, Tab selects the next light, [ / ] move the selected
/// light a wheel notch nearer / farther, s save, q or Esc quit; any other key
/// changes nothing.
ViewUpdate applyKey(const ViewState& state, int key, const ViewContext& context);

/// Light `index` moved across the image by (dx, dy) pixels at its own depth
/// (it stays under the cursor that drags it); selected. A light behind the
/// camera does not move.
ViewState moveLightAcross(const ViewState& state, int index, int dx, int dy, const Camera& camera);
/// The selected light moved along the line from the eye through it, a tenth
/// of its distance nearer per notch (notches > 0) or farther (< 0): its image
/// stays where it is.
ViewState moveLightInDepth(const ViewState& state, double notches, const Camera& camera);
/// How near the cursor must press to a drawn light to drag it.
inline constexpr double kLightPickPixels = 10;
/// The light drawn nearest (x, y) within `reach` pixels, or -1.
int lightUnder(const ViewState& state, double x, double y, const Camera& camera,
               double reach = kLightPickPixels);

/// A drag of the lighting's rotation by (dx, dy) pixels over an image of width x height: a full
/// width turns the lighting once around, the height half a turn (pitch within -90..90).
ViewState applyDrag(const ViewState& state, int dx, int dy, int width, int height);

/// The exposure trackbar's position for an exposure (clamped to the bar), and
/// the state a moved bar gives: a position that merely rounds the current
/// exposure leaves it alone.
int exposurePosition(double exposure);
ViewState applyExposurePosition(const ViewState& state, int position);

/// The left button over the window: a press over the image (above the status
/// strip, y < imageHeight) starts a drag, of the light pressed on (`light`,
/// from lightUnder) or else of the lighting's rotation; a release ends it,
/// and each move with the button held gives the drag since the last one.
class DragTracker {
 public:
  void press(int x, int y, int imageHeight, int light = -1);
  void release() { dragging_ = false; }
  /// Whether this move drags (then dx, dy are set).
  bool move(int x, int y, bool buttonHeld, int& dx, int& dy);
  /// The light being dragged, or -1 for the rotation.
  int light() const { return light_; }

 private:
  bool dragging_ = false;
  int x_ = 0, y_ = 0, light_ = -1;
};

}  // namespace acpca
