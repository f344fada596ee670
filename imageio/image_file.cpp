#include "imageio/image_file.h"

#include "core/error.h"
#include "imageio/codecs_library.h"

namespace acpca {

size_t pixelTypeBytes(PixelType type) {
  switch (type) {
    case PixelType::UInt8:
      return 1;
    case PixelType::UInt16:
    case PixelType::Half:
      return 2;
    case PixelType::Float:
      break;
  }
  return 4;
}

std::unique_ptr<ImageReader> openImage(const std::string& path, std::string& error,
                                       const ImageReadOptions& options) {
  return imageCodecs().open(path, options, error);
}

void writeImageFile(const std::string& file, const ImageWriteSpec& spec, const void* pixels,
                    const std::string& path, const std::string& what) {
  std::string error;
  switch (imageCodecs().write(file, spec, pixels, error)) {
    case ImageCodecs::WriteResult::Written:
      return;
    case ImageCodecs::WriteResult::NoWriter:
      throw UserError(concat(path, ": cannot create an image writer: ", error));
    case ImageCodecs::WriteResult::Failed:
      break;
  }
  throw UserError(concat(path, ": cannot write ", what, ": ", error));
}

}  // namespace acpca
