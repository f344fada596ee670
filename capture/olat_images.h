#pragma once
// The images of a one-light-at-a-time set, read a band of scanlines at a time
// from all of them at once: the transport is row-major (a pixel's values
// under every light side by side) while each image holds one light, so the
// import reads rows y0..y1 of every image, writes those pixels' rows, and
// moves on, never holding more than a band of every image.
#include <memory>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "transport/camera.h"

namespace acpca {

/// How stored values become linear radiance (the images' transfer function).
enum class TransferFunction {
  Auto,    ///< integer images (PNG, TIFF, JPEG) are sRGB, floating-point ones linear
  Linear,  ///< every image as stored (`--linear`)
  Srgb,    ///< every image sRGB-decoded (`--srgb`)
};
inline constexpr EnumNames<TransferFunction, 3> kTransferFunctionNames{
    "encoding",
    {{{TransferFunction::Auto, "auto"},
      {TransferFunction::Linear, "linear"},
      {TransferFunction::Srgb, "srgb"}}}};

/// N images of one size, each read as linear RGB float in bands.
class OlatImages {
 public:
  virtual ~OlatImages() = default;
  virtual int count() const = 0;
  virtual ImageSize size() const = 0;
  /// Image k's rows [y0, y1) as linear RGB (width x 3 floats per row) into out.
  /// Bands are asked for in increasing order. Safe to call for different
  /// images from different threads at once.
  virtual void readBand(int k, int y0, int y1, float* out) = 0;
  /// Image k's name for messages.
  virtual std::string name(int k) const = 0;
  /// Values read so far that sat at the top of their integer range.
  virtual long long saturated(int k) const = 0;
};

/// Image files, all opened up front (their sizes compared), each read
/// sequentially in bands (PNG and JPEG decode front to back). Throws
/// UserError naming the file: one missing or unreadable, sizes that differ,
/// a value that is not finite (readBand, naming the pixel).
std::unique_ptr<OlatImages> openImageFiles(const std::vector<std::string>& paths,
                                           TransferFunction transfer);

/// Images already in memory: count x height x width x 3 linear floats
/// (Python's arrays), not copied: they must outlive the reader.
std::unique_ptr<OlatImages> imagesInMemory(const float* values, int count, ImageSize size);

/// One image read whole as coverage: its first channel, as stored, clamped
/// to [0, 1] (a mask's grey or alpha). Throws UserError naming the file, or
/// when its size is not `size`.
std::vector<float> readMask(const std::string& path, ImageSize size);

}  // namespace acpca
