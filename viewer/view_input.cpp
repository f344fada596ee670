#include "viewer/view_input.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"

namespace acpca {

namespace {

/// The light moved to `position`, its spec written anew.
void placeLight(LocalLight& light, const Vec3& position) {
  light.position = position;
  light.spec = light.canonicalSpec();
}

}  // namespace

bool sameLights(const std::vector<LocalLight>& a, const std::vector<LocalLight>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(),
                    [](const LocalLight& x, const LocalLight& y) {
                      return x.canonicalSpec() == y.canonicalSpec();
                    });
}

LocalLight keyLightFor(const TransportHeader& g) {
  ACPCA_CHECK(g.hasPositions() && g.rows() > 0, "keyLightFor needs pixel positions");
  const Camera& camera = g.camera;
  const Vec3 forward = camera.forward();
  std::vector<double> depths(g.rows());
  for (long long row = 0; row < g.rows(); ++row)
    depths[row] = (Vec3(g.positions[3 * row], g.positions[3 * row + 1], g.positions[3 * row + 2]) -
                   camera.eye)
                      .dot(forward);
  // The median ignores a floor or backdrop stretching far away.
  std::nth_element(depths.begin(), depths.begin() + g.rows() / 2, depths.end());
  const double depth = std::max(depths[g.rows() / 2], 1e-6);
  const Vec3 ray = camera.rayDirection(0.5 * camera.size.width, 0.2 * camera.size.height);
  LocalLight light;
  light.position = camera.eye + 0.6 * depth / ray.dot(forward) * ray;
  const Vec3 lit = camera.eye + depth * forward;
  light.emission = Rgb::Constant(std::numbers::pi * (lit - light.position).squaredNorm());
  light.spec = light.canonicalSpec();
  return light;
}

std::vector<LocalLight> previewLights(const std::vector<LocalLight>& lights) {
  std::vector<LocalLight> lit = lights;
  for (LocalLight& light : lit)
    if (std::optional<LocalLight> point = heldAsPoint(light)) light = std::move(*point);
  return lit;
}

std::vector<MapSource> previewSources(const std::vector<MapSource>& sources) {
  std::vector<MapSource> points = sources;
  for (MapSource& disc : points) {
    const Rgb energy = disc.energy();
    disc.radius = kHeldDiscRadius;
    disc.radiance = energy / disc.solidAngle();
  }
  return points;
}

std::vector<LocalLight> litLights(const ViewState& state) {
  return state.lampHeld ? previewLights(state.lights) : state.lights;
}

bool operator==(const ViewState& a, const ViewState& b) {
  return a.env == b.env && a.yaw == b.yaw && a.pitch == b.pitch && a.exposure == b.exposure &&
         a.rankPercent == b.rankPercent && a.clusterOverlay == b.clusterOverlay &&
         a.rankHeatMap == b.rankHeatMap && a.lightingInset == b.lightingInset &&
         a.selectedLight == b.selectedLight && a.lampHeld == b.lampHeld && a.mapHeld == b.mapHeld &&
         sameLights(a.lights, b.lights);
}

ViewUpdate applyKey(const ViewState& state, int key, const ViewContext& context) {
  const int envs = context.envs;
  ViewUpdate u{state};
  ViewState& s = u.state;
  const int lights = static_cast<int>(s.lights.size());
  switch (key) {
    case 'i':
      s.lights.push_back(context.newLight);
      s.selectedLight = lights;
      break;
    case 'o':
      if (s.selectedLight >= 0) {
        s.lights.erase(s.lights.begin() + s.selectedLight);
        s.selectedLight = std::min(s.selectedLight, lights - 2);  // -1 when none is left
      }
      break;
    case '\t':
      if (lights > 0) s.selectedLight = (s.selectedLight + 1) % lights;
      break;
    case '[':
    case ']':
      s = moveLightInDepth(s, key == '[' ? 1 : -1, context.camera);
      break;
    case 27:
    case 'q':
      u.action = ViewAction::Quit;
      break;
    case 'n':
    case ' ':
      s.env = (s.env + 1) % envs;
      break;
    case 'p':
      s.env = (s.env + envs - 1) % envs;
      break;
    case 'c':
      s.clusterOverlay = !s.clusterOverlay;
      break;
    case 'h':
      s.rankHeatMap = !s.rankHeatMap;
      break;
    case 'l':
      s.lightingInset = !s.lightingInset;
      break;
    case 'a':
    case 'd':
      s.yaw += key == 'a' ? -10 : 10;
      break;
    case 'r':
      s.yaw = s.pitch = 0;
      break;
    case '+':
    case '=':
      s.exposure = std::min(s.exposure + 0.5, -kExposureMin);
      break;
    case '-':
      s.exposure = std::max(s.exposure - 0.5, kExposureMin);
      break;
    case 's':
      u.action = ViewAction::Save;
      break;
    default:
      break;
  }
  return u;
}

ViewState applyDrag(const ViewState& state, int dx, int dy, int width, int height) {
  ViewState s = state;
  s.yaw += dx * 360.0 / width;
  s.pitch = std::clamp(s.pitch + dy * 180.0 / height, -90.0, 90.0);
  return s;
}

int exposurePosition(double exposure) {
  const int position = static_cast<int>(std::lround((exposure - kExposureMin) / kExposureStep));
  return std::clamp(position, 0, kExposureSteps);
}

ViewState applyExposurePosition(const ViewState& state, int position) {
  ViewState s = state;
  if (position >= 0 && position != exposurePosition(s.exposure))
    s.exposure = kExposureMin + std::min(position, kExposureSteps) * kExposureStep;
  return s;
}

ViewState moveLightAcross(const ViewState& state, int index, int dx, int dy, const Camera& camera) {
  ViewState s = state;
  if (index < 0 || index >= static_cast<int>(s.lights.size())) return s;
  s.selectedLight = index;
  LocalLight& light = s.lights[index];
  Eigen::Vector2d pixel;
  double depth = 0;
  if (camera.project(light.position, pixel, depth))
    placeLight(light, light.position + camera.imagePlaneOffset(dx, dy, depth));
  return s;
}

ViewState moveLightInDepth(const ViewState& state, double notches, const Camera& camera) {
  ViewState s = state;
  if (s.selectedLight < 0 || s.selectedLight >= static_cast<int>(s.lights.size())) return s;
  LocalLight& light = s.lights[s.selectedLight];
  // Scaling the offset from the eye keeps the light on its pixel's ray.
  placeLight(light, camera.eye + std::pow(0.9, notches) * (light.position - camera.eye));
  return s;
}

int lightUnder(const ViewState& state, double x, double y, const Camera& camera, double reach) {
  int nearest = -1;
  double best = reach * reach;
  for (size_t i = 0; i < state.lights.size(); ++i) {
    Eigen::Vector2d pixel;
    double depth = 0;
    if (!camera.project(state.lights[i].position, pixel, depth)) continue;
    // Pixel (x, y) spans [x, x + 1): its centre is where the light is drawn.
    const double d2 = (pixel - Eigen::Vector2d(x + 0.5, y + 0.5)).squaredNorm();
    if (d2 <= best) best = d2, nearest = static_cast<int>(i);
  }
  return nearest;
}

void DragTracker::press(int x, int y, int imageHeight, int light) {
  if (y >= imageHeight) return;  // the status strip
  dragging_ = true;
  x_ = x, y_ = y;
  light_ = light;
}

bool DragTracker::move(int x, int y, bool buttonHeld, int& dx, int& dy) {
  if (!dragging_ || !buttonHeld) return false;
  dx = x - x_, dy = y - y_;
  x_ = x, y_ = y;
  return true;
}

}  // namespace acpca
