#include "eval/codec_benchmark.h"

#include <tbb/task_arena.h>

#include <filesystem>
#include <functional>

#include "core/error.h"
#include "core/half.h"
#include "core/statistics.h"
#include "core/stopwatch.h"
#include "core/text.h"
#include "imageio/codecs_library.h"
#include "imageio/image_file.h"
#include "imageio/image_output.h"
#include "relight/memory_bandwidth.h"

namespace acpca {

namespace {

namespace fs = std::filesystem;

Image readRgb(const std::string& path) {
  std::string error;
  auto in = openImage(path, error);
  if (!in) throw UserError(concat(path, ": cannot read the frame: ", error));
  const ImageHeader& h = in->header();
  if (h.channels < 3) throw UserError(concat(path, ": a frame of RGB is needed"));
  Image image{h.width, h.height, 3,
              std::vector<float>(static_cast<size_t>(h.width) * h.height * 3)};
  if (!in->readImage(0, 3, PixelType::Float, image.pixels.data()))
    throw UserError(concat(path, ": cannot read the frame: ", in->error()));
  return image;
}

/// The median ms of `repeats` runs of `work` on one core.
double medianMs(int repeats, const std::function<void()>& work) {
  tbb::task_arena one(1);
  std::vector<double> ms;
  one.execute([&] {
    for (int k = 0; k < repeats; ++k) {
      const Stopwatch watch;
      work();
      ms.push_back(watch.milliseconds());
    }
  });
  return median(ms);
}

struct CodecCase {
  const char* name;
  ImageFormat format;
  ImageEncoding encoding;
};

}  // namespace

StudyOutput runCodecBenchmark(const CodecBenchmarkOptions& o) {
  if (o.repeats < 1) throw ParameterError("repeats", o.repeats, "must be at least 1");
  if (!(o.streamGiB > 0 && o.streamGiB <= 64))
    throw ParameterError("stream size (GiB)", o.streamGiB, "is out of range (0, 64]");
  const Image image = readRgb(o.image);
  const BandwidthMeasurement stream = measureStreamingRead(o.streamGiB * (1 << 30), 5);
  const auto encoding = [](ExrCompression c, bool isFloat, int level) {
    ImageEncoding e;
    e.exrCompression = c, e.exrFloat = isFloat, e.pngLevel = level;
    return e;
  };
  const CodecCase cases[] = {
      {"png, level 1", ImageFormat::Png, encoding(ExrCompression::Rle, false, 1)},
      {"png, level 6", ImageFormat::Png, encoding(ExrCompression::Rle, false, 6)},
      {"png16, level 1", ImageFormat::Png16, encoding(ExrCompression::Rle, false, 1)},
      {"exr half, none", ImageFormat::Exr, encoding(ExrCompression::None, false, 1)},
      {"exr half, rle", ImageFormat::Exr, encoding(ExrCompression::Rle, false, 1)},
      {"exr half, zips", ImageFormat::Exr, encoding(ExrCompression::Zips, false, 1)},
      {"exr half, zip", ImageFormat::Exr, encoding(ExrCompression::Zip, false, 1)},
      {"exr float, zip", ImageFormat::Exr, encoding(ExrCompression::Zip, true, 1)}};
  // The values each encoder is handed, made once: sRGB codes, halves, floats.
  const std::vector<unsigned char> codes = SrgbEncoder(0).encode(image);
  std::vector<std::uint16_t> codes16, halves(image.pixels.size());
  Srgb16Encoder(0).encodeInto(image, codes16);
  floatToHalfIeee(image.pixels.data(), halves.data(), halves.size());

  const std::string ours = (fs::path(o.directory) / ".bench-codecs-ours").string();
  const std::string theirs = (fs::path(o.directory) / ".bench-codecs-oiio").string();
  std::string text = formatted("%-16s %10s %12s %7s %11s %11s %12s\n", "format", "ms imageio",
                               "ms OIIO", "ratio", "bytes", "bytes OIIO", "ms frame");
  nlohmann::json rows = nlohmann::json::array();
  for (const CodecCase& c : cases) {
    const std::string extension = imageExtension(c.format);
    const bool exr = c.format == ImageFormat::Exr;
    ImageWriteSpec spec{
        image.width, image.height, 3,
        exr ? (c.encoding.exrFloat ? PixelType::Float : PixelType::Half)
            : (c.format == ImageFormat::Png ? PixelType::UInt8 : PixelType::UInt16)};
    if (exr)
      spec.textAttributes = {{"compression", kExrCompressionNames.name(c.encoding.exrCompression)},
                             {"DateTime", ""}};
    else
      spec.integerAttributes = {{"png:compressionLevel", c.encoding.pngLevel}};
    const void* values =
        !exr ? (c.format == ImageFormat::Png ? static_cast<const void*>(codes.data())
                                             : codes16.data())
        : c.encoding.exrFloat ? static_cast<const void*>(image.pixels.data())
                              : halves.data();
    const double imageioMs =
        medianMs(o.repeats, [&] { writeImageFile(ours + extension, spec, values, o.image); });
    const double oiioMs = medianMs(o.repeats, [&] {
      std::string error;
      if (imageCodecs().write(theirs + extension, spec, values, error) !=
          ImageCodecs::WriteResult::Written)
        throw UserError(concat(theirs + extension, ": OpenImageIO cannot write it: ", error));
    });
    const double frameMs = medianMs(o.repeats, [&] {
      encodeImage(image, ours + extension, ours + extension, c.format, 0, c.encoding);
    });
    const auto bytes = fs::file_size(ours + extension),
               oiioBytes = fs::file_size(theirs + extension);
    fs::remove(ours + extension), fs::remove(theirs + extension);
    text +=
        formatted("%-16s %10.3f %12.3f %7.2f %11llu %11llu %12.3f\n", c.name, imageioMs, oiioMs,
                  imageioMs > 0 ? oiioMs / imageioMs : 0.0, static_cast<unsigned long long>(bytes),
                  static_cast<unsigned long long>(oiioBytes), frameMs);
    rows.push_back({{"format", c.name},
                    {"imageio_ms", imageioMs},
                    {"openimageio_ms", oiioMs},
                    {"bytes", bytes},
                    {"openimageio_bytes", oiioBytes},
                    {"frame_ms", frameMs}});
  }
  text += formatted(
      "%dx%d frame of %s, one core each, median of %d; ratio = OpenImageIO / imageio; ms "
      "frame = imageio's whole frame from linear floats (sRGB codes or halves made too)\n"
      "streaming read, %.2f GiB array: %.1f GB/s (median of 5)\n",
      image.width, image.height, o.image.c_str(), o.repeats, o.streamGiB, stream.gbPerSecondMedian);
  StudyOutput out;
  out.summary = text;
  out.json = {{"image", o.image},
              {"width", image.width},
              {"height", image.height},
              {"codecs", rows},
              {"streaming_read_gb_per_s", stream.gbPerSecondMedian}};
  return out;
}

}  // namespace acpca
