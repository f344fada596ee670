#pragma once
// The boundary between imageio and its plugin (`oiio_codecs.cpp`, built as
// libacpca_image_codecs.so), which alone links OpenImageIO. The plugin
// exports one C function, kImageCodecsEntry, returning its ImageCodecs. No
// exception crosses the boundary: failures come back as text.
#include <memory>
#include <string>

#include "imageio/image_file.h"

namespace acpca {

/// What the plugin does; one instance, living as long as the process.
class ImageCodecs {
 public:
  /// Where writing failed: making a writer for the file's type, or writing.
  enum class WriteResult { Written, NoWriter, Failed };

  virtual std::unique_ptr<ImageReader> open(const std::string& path,
                                            const ImageReadOptions& options,
                                            std::string& error) = 0;
  virtual WriteResult write(const std::string& file, const ImageWriteSpec& spec, const void* pixels,
                            std::string& error) = 0;

 protected:
  ~ImageCodecs() = default;
};

/// The plugin's exported function: `extern "C" ImageCodecs* NAME()`.
inline constexpr const char* kImageCodecsEntry = "acpca_image_codecs";
using ImageCodecsEntry = ImageCodecs* (*)();

}  // namespace acpca
