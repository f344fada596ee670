#pragma once
// What a batch writes beside its frames when asked for labels: the view's
// per-pixel labels once, and each frame's shading (dataset/pixel_labels.h).
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "dataset/pixel_labels.h"
#include "imageio/image_output.h"
#include "lighting/environment.h"
#include "relight/image_composer.h"

namespace acpca {

class FrameLabels {
 public:
  /// Frames are composed over `background`; shading files are written as
  /// frames are (EXR: `encoding`), clamped at zero unless `keepNegative`.
  FrameLabels(const TransportHeader& header, std::vector<Aov> aovs, LabelFormat format,
              Background background, const ImageEncoding& encoding, bool keepNegative);
  bool any() const { return !aovs_.empty(); }
  bool shading() const;
  /// Writes the view's labels at STEM.exr and/or STEM_AOV.npy; their paths.
  std::vector<std::string> writeView(const std::string& stem) const;
  /// The shading files of a frame at STEM: STEM.exr and/or STEM.npy.
  std::vector<std::string> shadingPaths(const std::string& stem) const;
  /// Frame's shading as STEM.exr and/or STEM.npy under temporary names (added
  /// to `files`, which the caller commits), scaled by 2^exposure as the frame
  /// is written; returns their final paths.
  std::vector<std::string> encodeShading(const Image& frame, const Environment& env,
                                         const Eigen::Matrix3d& rotation, double exposureEv,
                                         const std::string& stem,
                                         std::vector<std::unique_ptr<AtomicOutput>>& files,
                                         const FrameMetadata* metadata = nullptr) const;

 private:
  const TransportHeader& header_;
  std::vector<Aov> aovs_;
  LabelFormat format_;
  Background background_;
  ImageEncoding encoding_;
  bool keepNegative_;
  ImageComposer composer_;
};

}  // namespace acpca
