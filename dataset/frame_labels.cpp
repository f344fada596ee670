#include "dataset/frame_labels.h"

#include <algorithm>
#include <cmath>

#include "imageio/npy_file.h"

namespace acpca {

FrameLabels::FrameLabels(const TransportHeader& header, std::vector<Aov> aovs, LabelFormat format,
                         Background background, const ImageEncoding& encoding, bool keepNegative)
    : header_(header),
      aovs_(std::move(aovs)),
      format_(format),
      background_(background),
      encoding_(encoding),
      keepNegative_(keepNegative),
      composer_(header) {}

bool FrameLabels::shading() const {
  return std::find(aovs_.begin(), aovs_.end(), Aov::Shading) != aovs_.end();
}

std::vector<std::string> FrameLabels::writeView(const std::string& stem) const {
  return writeViewLabels(viewLabels(header_, aovs_), header_, stem, format_);
}

std::vector<std::string> FrameLabels::encodeShading(
    const Image& frame, const Environment& env, const Eigen::Matrix3d& rotation, double exposureEv,
    const std::string& stem, std::vector<std::unique_ptr<AtomicOutput>>& files,
    const FrameMetadata* metadata) const {
  // The frame less its background part, divided by coverage x albedo.
  std::vector<float> background(frame.pixels.size());
  composer_.background(background_, env, rotation, background.data(), true);
  Image shading{frame.width, frame.height, 3,
                std::vector<float>(frame.pixels.size() / frame.channels * 3)};
  frameShading(header_, frame.pixels.data(), background.data(), frame.channels,
               shading.pixels.data(), keepNegative_);
  if (format_ != LabelFormat::Npy) {
    files.push_back(std::make_unique<AtomicOutput>(stem + ".exr"));
    ImageEncoding encoding = encoding_;
    encoding.metadata = metadata;  // the frame's: its lighting and camera
    encodeImage(shading, files.back()->tempPath(), stem + ".exr", ImageFormat::Exr, exposureEv,
                encoding);
  }
  if (format_ != LabelFormat::Exr) {
    // Scaled as the EXR is, so shading x albedo equals the frame's file.
    const float scale = static_cast<float>(std::exp2(exposureEv));
    for (float& v : shading.pixels) v *= scale;
    files.push_back(std::make_unique<AtomicOutput>(stem + ".npy"));
    writeNpy(files.back()->tempPath(), stem + ".npy",
             {static_cast<size_t>(frame.height), static_cast<size_t>(frame.width), 3},
             shading.pixels.data());
  }
  return shadingPaths(stem);
}

std::vector<std::string> FrameLabels::shadingPaths(const std::string& stem) const {
  std::vector<std::string> paths;
  if (format_ != LabelFormat::Npy) paths.push_back(stem + ".exr");
  if (format_ != LabelFormat::Exr) paths.push_back(stem + ".npy");
  return paths;
}

}  // namespace acpca
