// The viewer's drawing over the relit frame: the lights, the cluster
// boundaries and rank heat map, the lighting inset, and the status line.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "core/error.h"
#include "lighting/envmap_export.h"
#include "pictures/pictures.h"
#include "viewer/viewer.h"

namespace acpca {

void Viewer::drawLights(const ViewState& state, cv::Mat& image) const {
  for (size_t i = 0; i < state.lights.size(); ++i) {
    Eigen::Vector2d pixel;
    double depth = 0;
    if (!context_.camera.project(state.lights[i].position, pixel, depth)) continue;
    // cv::circle takes the centre in 1/16 pixels: (x + 0.5, y + 0.5) is pixel (x, y)'s centre.
    const cv::Point centre(static_cast<int>(std::lround(16 * (pixel.x() - 0.5))),
                           static_cast<int>(std::lround(16 * (pixel.y() - 0.5))));
    const bool selected = static_cast<int>(i) == state.selectedLight;
    cv::circle(image, centre, 16 * 6, cv::Scalar(0, 0, 0), selected ? cv::FILLED : 3, cv::LINE_AA,
               4);
    cv::circle(image, centre, 16 * 5, cv::Scalar(0, 220, 255), selected ? cv::FILLED : 1,
               cv::LINE_AA, 4);
  }
}

void Viewer::drawOverlays(const ViewState& state, cv::Mat& image) const {
  if (state.rankHeatMap) {
    // Ranks in use (after the rank limit) on a perceptual colour scale.
    const std::vector<int>& active = relighter_->activeRanks();
    cv::Mat level(height_, width_, CV_8UC1, cv::Scalar(0));
    for (int p = 0; p < width_ * height_; ++p)
      if (const int c = clusterOfPixel_[p]; c >= 0)
        level.data[p] =
            static_cast<unsigned char>(std::lround(255.0 * active[c] / std::max(1, maxRank_)));
    cv::Mat colours;
    cv::applyColorMap(level, colours, cv::COLORMAP_VIRIDIS);
    for (int p = 0; p < width_ * height_; ++p)
      if (clusterOfPixel_[p] >= 0)
        image.at<cv::Vec3b>(p / width_, p % width_) = colours.at<cv::Vec3b>(p / width_, p % width_);
  }
  if (state.clusterOverlay) drawClusterBoundaries(image, clusterOfPixel_, {0, 230, 255});
  if (state.lightingInset) {
    // What the lattice holds of the rotated lighting, as a small lat-long.
    const int w = std::clamp(width_ / 3, 16, 256), h = w / 2;
    const Image inset =
        latticeToLatLong(domain_->mapLighting(lighting_), domain_->mapLattice(), w, h);
    const cv::Mat picture = toneMappedBgr(inset, state.exposure);
    if (w + 2 <= width_ && h + 2 <= height_) {
      image(cv::Rect(0, 0, w + 2, h + 2)).setTo(cv::Scalar(255, 255, 255));
      picture.copyTo(image(cv::Rect(1, 1, w, h)));
    }
  }
}

void Viewer::drawStatus(const ViewState& state, cv::Mat& canvas) const {
  const double yaw = std::fmod(std::fmod(state.yaw, 360.0) + 360.0, 360.0);
  std::string lights;
  if (!state.lights.empty())
    lights = concat("  lights ", state.lights.size(),
                    state.selectedLight >= 0 ? concat(" (", state.selectedLight + 1, ": ",
                                                      state.lights[state.selectedLight].spec, ")")
                                             : std::string(),
                    localProblem_.empty() ? "" : concat(" not shown: ", localProblem_),
                    state.lampHeld && std::any_of(state.lights.begin(), state.lights.end(),
                                                  [](const LocalLight& l) {
                                                    return heldAsPoint(l).has_value();
                                                  })
                        ? " (held: sphere lamps lit as points)"
                        : "");
  char text[1024];
  std::snprintf(
      text, sizeof text,
      "%s (%d/%zu)  yaw %.1f pitch %.1f  EV %+.2f  rank %d%%%s%s  |  this frame: lighting "
      "%.1f ms, relight %.1f ms, lights %.1f ms, compose %.1f ms, draw %.1f ms: %.0f fps",
      envs_[state.env]->name().c_str(), state.env + 1, envs_.size(), yaw, state.pitch,
      state.exposure, state.rankPercent,
      state.rankHeatMap ? concat(" (heat map 0..", maxRank_, ")").c_str() : "", lights.c_str(),
      times_.lighting, times_.relight, times_.lights, times_.compose, times_.draw,
      1000.0 / (times_.lighting + times_.relight + times_.lights + times_.compose + times_.draw));
  // The strip grows a line per chunk of text that would not fit the width.
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  const double scale = 0.45;
  int baseline = 0;
  const std::string all = text;
  std::vector<std::string> lines;
  for (std::string rest = all; !rest.empty();) {
    // Break at the last space that fits (or mid-word when no space does).
    size_t take = rest.size();
    auto fits = [&](size_t n) {
      return cv::getTextSize(rest.substr(0, n), font, scale, 1, &baseline).width <= canvas.cols - 8;
    };
    while (take > 1 && !fits(take)) {
      const size_t space = rest.rfind(' ', take - 1);
      take = space != std::string::npos && space > 0 ? space : take - 1;
    }
    lines.push_back(rest.substr(0, take));
    rest = rest.substr(std::min(rest.size(), take + (take < rest.size() && rest[take] == ' ')));
  }
  const int lineHeight = 18;
  cv::Mat strip(lineHeight * static_cast<int>(lines.size()) + 4, canvas.cols, CV_8UC3,
                cv::Scalar(32, 32, 32));
  for (size_t i = 0; i < lines.size(); ++i)
    cv::putText(strip, lines[i], {4, 14 + lineHeight * static_cast<int>(i)}, font, scale,
                cv::Scalar(235, 235, 235), 1, cv::LINE_AA);
  cv::vconcat(canvas, strip, canvas);
}

// ---- UI thread ---------------------------------------------------------------

}  // namespace acpca
