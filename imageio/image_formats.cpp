#include "imageio/image_formats.h"

#include <algorithm>

#include "core/error.h"
#include "core/text.h"

namespace acpca {

const ImageFormatRow& imageFormatRow(ImageFormat format) {
  for (const ImageFormatRow& row : kImageFormats)
    if (row.format == format) return row;
  ACPCA_CHECK(false, "image format ", static_cast<int>(format), " has no row");
  return kImageFormats[0];
}

int storedBytesPerValue(ImageFormat format, const ImageEncoding& encoding) {
  const ImageFormatRow& row = imageFormatRow(format);
  return encoding.exrFloat ? row.bytesPerFloat : row.bytesPerValue;
}

const ImageFormatRow* imageFormatOfExtension(const std::string& extension) {
  for (const ImageFormatRow& row : kImageFormats)
    if (extension == row.extension) return &row;
  return nullptr;
}

std::vector<ImageFormat> parseImageFormatList(const std::string& list) {
  std::vector<ImageFormat> formats;
  for (const std::string& name : splitText(list, ',')) {
    ImageFormat f;
    try {
      f = kImageFormatNames.parse(name);
    } catch (const ParameterError&) {
      throw ParameterError("image format", list,
                           concat("is not a comma-separated list of ", kImageFormatNames.list()));
    }
    const std::string extension = imageExtension(f);
    if (std::any_of(formats.begin(), formats.end(),
                    [&](ImageFormat g) { return extension == imageExtension(g); }))
      throw ParameterError("image format", list,
                           concat("names two formats written as ", extension,
                                  " (a format twice, or png and png16)"));
    formats.push_back(f);
  }
  return formats;
}

}  // namespace acpca
