#include "imageio/codecs_library.h"

#include <exception>

#include "core/error.h"

namespace acpca {

PluginSpec imageCodecsPlugin() {
#ifdef ACPCA_IMAGE_CODECS_BUILT
  const char* built = ACPCA_IMAGE_CODECS_BUILT;
#else
  const char* built = nullptr;
#endif
  return {"libacpca_image_codecs.so", "ACPCA_IMAGE_CODECS", built, kImageCodecsEntry,
          "the image codecs (OpenImageIO; scripts/setup.sh installs it)"};
}

ImageCodecs& imageCodecs() {
  struct Loaded {
    ImageCodecs* codecs = nullptr;
    std::exception_ptr failure;
  };
  static const Loaded loaded = [] {  // once, thread-safe
    try {
      return Loaded{reinterpret_cast<ImageCodecsEntry>(loadPluginEntry(imageCodecsPlugin()))(), {}};
    } catch (const UserError&) {
      return Loaded{nullptr, std::current_exception()};
    }
  }();
  if (!loaded.codecs) std::rethrow_exception(loaded.failure);
  return *loaded.codecs;
}

}  // namespace acpca
