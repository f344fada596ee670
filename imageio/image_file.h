#pragma once
// Image files, read and written through OpenImageIO. Only this library knows
// OpenImageIO, and it does not link it: the codecs live in a plugin of their
// own (`image_codecs.h`) that is loaded on the first image a process reads or
// writes, so a command that touches no image never pays for loading
// OpenImageIO and the hundreds of libraries it pulls (docs/architecture.md).
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace acpca {

struct FrameMetadata;  // imageio/frame_metadata.h

/// How pixel values are handed over in memory.
enum class PixelType { UInt8, UInt16, Half, Float };

/// The bytes one value of `type` takes.
size_t pixelTypeBytes(PixelType type);

/// How a file stores its values (what decoding it needs).
enum class StoredValues { UInt8, UInt16, OtherInteger, FloatingPoint };

/// What an image file's header says.
struct ImageHeader {
  int width = 0, height = 0, depth = 1, channels = 0;
  StoredValues stored = StoredValues::FloatingPoint;
  int alphaChannel = -1;  ///< -1: none
  std::vector<std::string> channelNames;
  std::string colorSpace;  ///< as the file declares it ("sRGB", "Linear", ...); may be empty
};

/// An open image file. Reads return false and leave the reason in error().
class ImageReader {
 public:
  virtual ~ImageReader() = default;
  virtual const ImageHeader& header() const = 0;
  /// Channels [firstChannel, endChannel) of the whole image, as `type`,
  /// pixel-interleaved, row by row.
  virtual bool readImage(int firstChannel, int endChannel, PixelType type, void* out) = 0;
  /// The same, of image rows [y0, y1) only.
  virtual bool readRows(int y0, int y1, int firstChannel, int endChannel, PixelType type,
                        void* out) = 0;
  virtual std::string error() = 0;
};

/// How a file is opened for reading.
struct ImageReadOptions {
  /// Colour as stored: a reader would otherwise multiply colours by alpha.
  bool unassociatedAlpha = false;
};

/// Opens `path`; null, with the codec's reason in `error`, when it cannot.
/// Throws UserError when the image codecs themselves cannot be loaded.
std::unique_ptr<ImageReader> openImage(const std::string& path, std::string& error,
                                       const ImageReadOptions& options = {});

/// What an image file is written as.
struct ImageWriteSpec {
  ImageWriteSpec(int width, int height, int channels, PixelType type,
                 std::vector<std::string> channelNames = {})
      : width(width),
        height(height),
        channels(channels),
        type(type),
        channelNames(std::move(channelNames)) {}

  int width, height, channels;
  PixelType type;  ///< stored as, and handed over as
  /// Empty: R, G, B, A by count. Else one per channel; those named "A" and "Z"
  /// are the alpha and depth channels.
  std::vector<std::string> channelNames;
  /// The codec's attributes ("compression", "png:compressionLevel", ...).
  std::vector<std::pair<std::string, std::string>> textAttributes;
  std::vector<std::pair<std::string, int>> integerAttributes;
  /// A frame's colour space, camera and fields (null: none), written by this
  /// library's PNG and EXR encoders.
  const FrameMetadata* metadata = nullptr;
};

/// Writes `pixels` (width x height x channels values of spec.type) into
/// `file`, the codec chosen by its extension. Errors name `path` (the name
/// the user knows, where `file` is its temporary) and `what` ("the image").
void writeImageFile(const std::string& file, const ImageWriteSpec& spec, const void* pixels,
                    const std::string& path, const std::string& what = "the image");

}  // namespace acpca
