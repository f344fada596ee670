#include "imageio/image_file.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <optional>

#include "core/error.h"
#include "imageio/codecs_library.h"
#include "imageio/exr_encoder.h"
#include "imageio/exr_reader.h"
#include "imageio/png_encoder.h"
#include "imageio/whole_file.h"

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

namespace {

bool hasExtension(const std::string& file, const char* extension) {
  const size_t n = std::strlen(extension);
  if (file.size() < n) return false;
  return std::equal(file.end() - static_cast<long>(n), file.end(), extension,
                    [](char a, char b) { return std::tolower(a) == b; });
}

}  // namespace

std::unique_ptr<ImageReader> openImage(const std::string& path, std::string& error,
                                       const ImageReadOptions& options) {
  // Common EXRs without OpenImageIO (exr_reader.h); the rest through it.
  if (hasExtension(path, ".exr"))
    if (auto reader = openExrDirectly(path)) return reader;
  return imageCodecs().open(path, options, error);
}

namespace {

/// OpenImageIO's default names of 1 to 4 channels (empty for more).
std::vector<std::string> channelNamesOf(const ImageWriteSpec& s) {
  if (!s.channelNames.empty()) return s.channelNames;
  switch (s.channels) {
    case 1:
      return {"Y"};
    case 2:
      return {"R", "G"};
    case 3:
      return {"R", "G", "B"};
    case 4:
      return {"R", "G", "B", "A"};
  }
  return {};
}

/// A PNG of 8 or 16 bits by png_encoder.h; nullopt for settings it does not know.
std::optional<bool> writePngDirectly(const std::string& file, const ImageWriteSpec& s,
                                     const void* pixels, std::string& error) {
  int level = 6;  // zlib's default, as OpenImageIO's
  for (const auto& [name, value] : s.integerAttributes) {
    if (name != "png:compressionLevel") return std::nullopt;
    level = value;
  }
  const std::vector<PngChunk> chunks =
      s.metadata ? srgbFrameChunks(*s.metadata) : std::vector<PngChunk>();
  const std::vector<unsigned char> bytes = encodePng(
      {s.width, s.height, s.channels, s.type == PixelType::UInt8 ? 8 : 16, pixels, &chunks}, level);
  return writeWholeFile(file, bytes.data(), bytes.size(), error);
}

/// An EXR of half or float values by exr_encoder.h; nullopt for other
/// settings, or more than 4 unnamed channels.
std::optional<bool> writeExrDirectly(const std::string& file, const ImageWriteSpec& s,
                                     const void* pixels, std::string& error) {
  ExrPixels p{s.width, s.height, channelNamesOf(s), s.type == PixelType::Float, pixels};
  if (p.channelNames.size() != static_cast<size_t>(s.channels)) return std::nullopt;
  ExrCodec codec = ExrCodec::Zip;  // OpenImageIO's default
  std::vector<std::pair<std::string, std::string>> attributes;
  for (const auto& [name, value] : s.textAttributes) {
    if (name == "DateTime" && value.empty()) continue;  // none is written
    if (name != "compression") {
      attributes.emplace_back(name, value);
      continue;
    }
    if (value == "none")
      codec = ExrCodec::None;
    else if (value == "rle")
      codec = ExrCodec::Rle;
    else if (value == "zips")
      codec = ExrCodec::Zips;
    else if (value == "piz")
      codec = ExrCodec::Piz;
    else if (value != "zip")
      return std::nullopt;
  }
  return writeExr(file, p, codec, attributes, s.metadata, error);
}

/// Writes `file` with the encoders of this library when they cover its
/// type and settings; nullopt when they do not (OpenImageIO writes it then).
std::optional<bool> writeDirectly(const std::string& file, const ImageWriteSpec& s,
                                  const void* pixels, std::string& error) {
  if (hasExtension(file, ".png") && (s.type == PixelType::UInt8 || s.type == PixelType::UInt16) &&
      s.channels >= 1 && s.channels <= 4 && s.textAttributes.empty())
    return writePngDirectly(file, s, pixels, error);
  if (hasExtension(file, ".exr") && (s.type == PixelType::Half || s.type == PixelType::Float) &&
      s.integerAttributes.empty())
    return writeExrDirectly(file, s, pixels, error);
  return std::nullopt;
}

}  // namespace

void writeImageFile(const std::string& file, const ImageWriteSpec& spec, const void* pixels,
                    const std::string& path, const std::string& what) {
  std::string error;
  if (const std::optional<bool> written = writeDirectly(file, spec, pixels, error)) {
    if (*written) return;
    throw UserError(concat(path, ": cannot write ", what, ": ", error));
  }
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
