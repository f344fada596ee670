// The image codecs plugin: OpenImageIO behind the ImageCodecs boundary
// (image_codecs.h). Built as a module of its own, loaded on the first image.
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <exception>

#include "imageio/image_codecs.h"

namespace acpca {

namespace {

OIIO::TypeDesc typeOf(PixelType type) {
  switch (type) {
    case PixelType::UInt8:
      return OIIO::TypeDesc::UINT8;
    case PixelType::UInt16:
      return OIIO::TypeDesc::UINT16;
    case PixelType::Half:
      return OIIO::TypeDesc::HALF;
    case PixelType::Float:
      break;
  }
  return OIIO::TypeDesc::FLOAT;
}

StoredValues storedValuesOf(const OIIO::TypeDesc& format) {
  if (format == OIIO::TypeDesc::UINT8) return StoredValues::UInt8;
  if (format == OIIO::TypeDesc::UINT16) return StoredValues::UInt16;
  return format.is_floating_point() ? StoredValues::FloatingPoint : StoredValues::OtherInteger;
}

/// What went wrong inside OpenImageIO when it threw instead of reporting.
std::string thrownReason() {
  try {
    throw;
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "an unknown error";
  }
}

class OiioReader : public ImageReader {
 public:
  explicit OiioReader(std::unique_ptr<OIIO::ImageInput> in) : in_(std::move(in)) {
    const OIIO::ImageSpec& spec = in_->spec();
    header_.width = spec.width;
    header_.height = spec.height;
    header_.depth = spec.depth;
    header_.channels = spec.nchannels;
    header_.stored = storedValuesOf(spec.format);
    header_.alphaChannel = spec.alpha_channel;
    header_.channelNames = spec.channelnames;
    header_.colorSpace = spec.get_string_attribute("oiio:ColorSpace");
  }

  const ImageHeader& header() const override { return header_; }

  bool readImage(int firstChannel, int endChannel, PixelType type, void* out) override {
    try {
      return in_->read_image(0, 0, firstChannel, endChannel, typeOf(type), out);
    } catch (...) {
      thrown_ = thrownReason();
      return false;
    }
  }

  bool readRows(int y0, int y1, int firstChannel, int endChannel, PixelType type,
                void* out) override {
    try {
      return in_->read_scanlines(0, 0, y0, y1, 0, firstChannel, endChannel, typeOf(type), out);
    } catch (...) {
      thrown_ = thrownReason();
      return false;
    }
  }

  std::string error() override {
    std::string reason = in_->geterror();
    return reason.empty() ? std::exchange(thrown_, {}) : reason;
  }

 private:
  std::unique_ptr<OIIO::ImageInput> in_;
  ImageHeader header_;
  std::string thrown_;
};

OIIO::ImageSpec specOf(const ImageWriteSpec& s) {
  OIIO::ImageSpec spec(s.width, s.height, s.channels, typeOf(s.type));
  if (!s.channelNames.empty()) {
    spec.channelnames = s.channelNames;
    const auto indexOf = [&](const char* name) {
      const auto at = std::find(s.channelNames.begin(), s.channelNames.end(), name);
      return at == s.channelNames.end() ? -1 : static_cast<int>(at - s.channelNames.begin());
    };
    spec.alpha_channel = indexOf("A");
    spec.z_channel = indexOf("Z");
  }
  for (const auto& [name, value] : s.textAttributes) spec.attribute(name, value);
  for (const auto& [name, value] : s.integerAttributes) spec.attribute(name, value);
  return spec;
}

class OiioCodecs final : public ImageCodecs {
 public:
  std::unique_ptr<ImageReader> open(const std::string& path, const ImageReadOptions& options,
                                    std::string& error) override {
    try {
      OIIO::ImageSpec config;
      if (options.unassociatedAlpha) config.attribute("oiio:UnassociatedAlpha", 1);
      auto in = OIIO::ImageInput::open(path, &config);
      if (!in) {
        error = OIIO::geterror();
        return nullptr;
      }
      return std::make_unique<OiioReader>(std::move(in));
    } catch (...) {
      error = thrownReason();
      return nullptr;
    }
  }

  WriteResult write(const std::string& file, const ImageWriteSpec& s, const void* pixels,
                    std::string& error) override {
    try {
      auto out = OIIO::ImageOutput::create(file);
      if (!out) {
        error = OIIO::geterror();
        return WriteResult::NoWriter;
      }
      if (out->open(file, specOf(s)) && out->write_image(typeOf(s.type), pixels) && out->close())
        return WriteResult::Written;
      error = out->geterror();
      return WriteResult::Failed;
    } catch (...) {
      error = thrownReason();
      return WriteResult::Failed;
    }
  }
};

}  // namespace

}  // namespace acpca

extern "C" __attribute__((visibility("default"))) acpca::ImageCodecs* acpca_image_codecs() {
  static acpca::OiioCodecs codecs;
  return &codecs;
}
