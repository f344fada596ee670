// The PNG and EXR encoders judged by decoders nobody here wrote: libpng and
// OpenImageIO read every PNG back to the very values, and OpenEXR's own C++
// writer makes the very chunk bytes of RLE (its reader decodes ZIP and ZIPS).
#include <gtest/gtest.h>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>
#include <OpenEXR/openexr.h>
#include <OpenImageIO/imageio.h>
#include <png.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <random>

#include "core/error.h"
#include "core/half.h"
#include "imageio/exr_encoder.h"
#include "imageio/image_file.h"
#include "imageio/png_encoder.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

/// Values like a frame's: smooth areas (runs after the predictor), noise,
/// a flat background and saturated spots.
std::vector<float> frameLike(int width, int height, int channels, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0, 0.02f);
  std::vector<float> v(static_cast<size_t>(width) * height * channels);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < channels; ++c) {
        const size_t i = (static_cast<size_t>(y) * width + x) * channels + c;
        if (x < width / 4)
          v[i] = 0.25f;  // flat
        else if (y < height / 3)
          v[i] = 0.5f + 0.4f * std::sin(0.05f * x + 0.11f * y + c);  // smooth
        else
          v[i] = std::abs(0.3f + noise(rng)) * (x % 17 == 0 ? 40.0f : 1.0f);  // noisy, bright dots
      }
  return v;
}

std::vector<unsigned char> bytesOf(const std::vector<float>& v, int bits) {
  std::vector<unsigned char> out(v.size() * bits / 8);
  for (size_t i = 0; i < v.size(); ++i) {
    const double x = std::clamp(v[i], 0.0f, 1.0f);
    if (bits == 8) {
      out[i] = static_cast<unsigned char>(std::lround(x * 255));
    } else {
      const auto w = static_cast<std::uint16_t>(std::lround(x * 65535));
      std::memcpy(&out[2 * i], &w, 2);
    }
  }
  return out;
}

void writeFile(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), static_cast<long>(bytes.size()));
}

TEST(PngEncoder, LibpngReadsEveryByteBackAtEveryLevelAndChannelCount) {
  test::TempDir dir;
  const png_uint_32 formats[5] = {0, PNG_FORMAT_GRAY, PNG_FORMAT_GA, PNG_FORMAT_RGB,
                                  PNG_FORMAT_RGBA};
  for (int channels = 1; channels <= 4; ++channels)
    for (auto [width, height] : {std::pair{1, 1}, {37, 5}, {128, 96}})
      for (int level : {0, 1, 3, 4, 6, 9}) {
        const auto values = bytesOf(frameLike(width, height, channels, 3 + level), 8);
        const std::string path = dir.file("p.png");
        writeFile(path, encodePng({width, height, channels, 8, values.data()}, level));
        png_image image{};
        image.version = PNG_IMAGE_VERSION;
        ASSERT_TRUE(png_image_begin_read_from_file(&image, path.c_str())) << image.message;
        ASSERT_EQ(image.width, png_uint_32(width));
        ASSERT_EQ(image.height, png_uint_32(height));
        ASSERT_EQ(image.format, formats[channels]) << "channels " << channels;
        std::vector<unsigned char> back(PNG_IMAGE_SIZE(image));
        ASSERT_TRUE(png_image_finish_read(&image, nullptr, back.data(), 0, nullptr))
            << image.message;
        EXPECT_EQ(back, values) << width << "x" << height << "x" << channels << " level " << level;
      }
}

TEST(PngEncoder, SixteenBitValuesReadBackThroughOpenImageIO) {
  test::TempDir dir;
  for (int channels : {1, 3, 4})
    for (int level : {1, 6}) {
      const int width = 33, height = 20;
      const auto bytes = bytesOf(frameLike(width, height, channels, 11), 16);
      const std::string path = dir.file("p16.png");
      writeFile(path, encodePng({width, height, channels, 16, bytes.data()}, level));
      OIIO::ImageSpec asStored;  // colour not multiplied by alpha
      asStored.attribute("oiio:UnassociatedAlpha", 1);
      auto in = OIIO::ImageInput::open(path, &asStored);
      ASSERT_TRUE(in) << OIIO::geterror();
      EXPECT_EQ(in->spec().format, OIIO::TypeDesc::UINT16);
      std::vector<std::uint16_t> back(bytes.size() / 2);
      ASSERT_TRUE(in->read_image(0, 0, 0, channels, OIIO::TypeDesc::UINT16, back.data()));
      EXPECT_EQ(std::memcmp(back.data(), bytes.data(), bytes.size()), 0) << channels;
    }
}

TEST(PngEncoder, HigherLevelsGiveSmallerFiles) {
  const int width = 200, height = 150;
  const auto values = bytesOf(frameLike(width, height, 3, 5), 8);
  const size_t stored = encodePng({width, height, 3, 8, values.data()}, 0).size();
  const size_t fast = encodePng({width, height, 3, 8, values.data()}, 1).size();
  const size_t best = encodePng({width, height, 3, 8, values.data()}, 9).size();
  EXPECT_GT(stored, values.size());  // level 0 stores
  EXPECT_LT(fast, stored * 3 / 4);
  EXPECT_LE(best, fast);
}

std::vector<std::uint16_t> halvesOf(const std::vector<float>& v) {
  std::vector<std::uint16_t> h(v.size());
  floatToHalfIeee(v.data(), h.data(), v.size());
  return h;
}

/// Each chunk's stored bytes (after its frame), through OpenEXR's core reader.
std::vector<std::vector<unsigned char>> chunksOf(const std::string& path) {
  exr_context_t context = nullptr;
  EXPECT_EQ(exr_start_read(&context, path.c_str(), nullptr), EXR_ERR_SUCCESS) << path;
  int32_t chunks = 0, lines = 0;
  exr_get_chunk_count(context, 0, &chunks);
  exr_get_scanlines_per_chunk(context, 0, &lines);
  exr_attr_box2i_t window;
  exr_get_data_window(context, 0, &window);
  std::vector<std::vector<unsigned char>> out;
  for (int32_t k = 0; k < chunks; ++k) {
    exr_chunk_info_t info;
    EXPECT_EQ(exr_read_scanline_chunk_info(context, 0, window.min.y + k * lines, &info),
              EXR_ERR_SUCCESS);
    out.emplace_back(info.packed_size);
    EXPECT_EQ(exr_read_chunk(context, 0, &info, out.back().data()), EXR_ERR_SUCCESS);
  }
  exr_finish(&context);
  return out;
}

/// The file written by OpenEXR's C++ library, one thread.
void writeByOpenExr(const std::string& path, int width, int height,
                    const std::vector<std::string>& names, const std::uint16_t* halves,
                    Imf::Compression compression) {
  Imf::setGlobalThreadCount(0);
  Imf::Header header(width, height);
  header.compression() = compression;
  Imf::FrameBuffer frame;
  const size_t channels = names.size();
  for (size_t c = 0; c < channels; ++c) {
    header.channels().insert(names[c], Imf::Channel(Imf::HALF));
    frame.insert(names[c],
                 Imf::Slice(Imf::HALF, (char*)(halves + c), 2 * channels, 2 * channels * width));
  }
  Imf::OutputFile out(path.c_str(), header, 0);
  out.setFrameBuffer(frame);
  out.writePixels(height);
}

/// Every channel of `path` as floats, interleaved in `names`' order, by
/// OpenEXR's C++ reader.
std::vector<float> readByOpenExr(const std::string& path, const std::vector<std::string>& names,
                                 int& width, int& height) {
  Imf::InputFile in(path.c_str());
  const auto window = in.header().dataWindow();
  width = window.max.x - window.min.x + 1, height = window.max.y - window.min.y + 1;
  std::vector<float> v(static_cast<size_t>(width) * height * names.size());
  Imf::FrameBuffer frame;
  const size_t channels = names.size();
  for (size_t c = 0; c < channels; ++c) {
    EXPECT_NE(in.header().channels().findChannel(names[c]), nullptr) << names[c];
    frame.insert(names[c],
                 Imf::Slice(Imf::FLOAT, (char*)(v.data() + c), 4 * channels, 4 * channels * width));
  }
  in.setFrameBuffer(frame);
  in.readPixels(window.min.y, window.max.y);
  return v;
}

TEST(ExrEncoder, RunLengthChunksAreOpenExrsOwnBytes) {
  test::TempDir dir;
  for (auto [width, height] : {std::pair{1, 1}, {53, 7}, {1000, 40}}) {
    const std::vector<std::string> names{"R", "G", "B"};
    const auto halves = halvesOf(frameLike(width, height, 3, 17));
    std::string error;
    ASSERT_TRUE(writeExr(dir.file("ours.exr"), {width, height, names, false, halves.data()},
                         ExrCodec::Rle, {}, nullptr, error))
        << error;
    writeByOpenExr(dir.file("theirs.exr"), width, height, names, halves.data(),
                   Imf::RLE_COMPRESSION);
    const auto ours = chunksOf(dir.file("ours.exr")), theirs = chunksOf(dir.file("theirs.exr"));
    ASSERT_EQ(ours.size(), static_cast<size_t>(height));
    EXPECT_EQ(ours, theirs) << width << "x" << height;
  }
}

TEST(ExrEncoder, RunLengthCodeMatchesOpenExrOnRunsAtEveryLength) {
  // Runs of 1 to 300 equal bytes between literals of every length, through
  // whole files so that OpenEXR's own encoder is the judge.
  test::TempDir dir;
  std::mt19937 rng(5);
  const int width = 50000;  // every run length from 1 to 300 once
  std::vector<std::uint16_t> halves(width);
  size_t i = 0;
  for (int run = 1; i < halves.size(); run = run % 300 + 1) {
    const auto value = static_cast<std::uint16_t>(rng());
    for (int k = 0; k < run && i < halves.size(); ++k) halves[i++] = value;
    for (int k = 0; k < run % 7 && i < halves.size(); ++k) halves[i++] = rng();
  }
  std::string error;
  ASSERT_TRUE(writeExr(dir.file("ours.exr"), {width, 1, {"Y"}, false, halves.data()}, ExrCodec::Rle,
                       {}, nullptr, error));
  writeByOpenExr(dir.file("theirs.exr"), width, 1, {"Y"}, halves.data(), Imf::RLE_COMPRESSION);
  EXPECT_EQ(chunksOf(dir.file("ours.exr")), chunksOf(dir.file("theirs.exr")));
}

TEST(ExrEncoder, EveryCodecDecodesToTheValuesWrittenHalfAndFloat) {
  test::TempDir dir;
  // Names out of order: the file sorts them, the reader finds each by name.
  const std::vector<std::string> names{"Z", "normal.X", "A", "B", "R"};
  const int width = 61, height = 37;
  const auto values = frameLike(width, height, 5, 23);
  const auto halves = halvesOf(values);
  std::vector<float> rounded(halves.size());
  halfToFloat(halves.data(), rounded.data(), halves.size());
  for (ExrCodec codec : {ExrCodec::None, ExrCodec::Rle, ExrCodec::Zips, ExrCodec::Zip})
    for (bool isFloat : {false, true}) {
      const std::string path = dir.file("c.exr");
      std::string error;
      ASSERT_TRUE(writeExr(path,
                           {width, height, names, isFloat,
                            isFloat ? static_cast<const void*>(values.data()) : halves.data()},
                           codec, {{"objects", "duck;floor"}}, nullptr, error))
          << error;
      int w = 0, h = 0;
      EXPECT_EQ(readByOpenExr(path, names, w, h), isFloat ? values : rounded)
          << "codec " << static_cast<int>(codec) << (isFloat ? " float" : " half");
      EXPECT_EQ(w, width);
      EXPECT_EQ(h, height);
      Imf::InputFile in(path.c_str());
      const auto* objects = in.header().findTypedAttribute<Imf::StringAttribute>("objects");
      ASSERT_NE(objects, nullptr);
      EXPECT_EQ(objects->value(), "duck;floor");
    }
}

TEST(ExrEncoder, ZipFilesAreSmallerThanRunLengthOnes) {
  test::TempDir dir;
  const int width = 256, height = 64;
  const auto halves = halvesOf(frameLike(width, height, 3, 29));
  std::uintmax_t size[4];
  for (ExrCodec codec : {ExrCodec::None, ExrCodec::Rle, ExrCodec::Zips, ExrCodec::Zip}) {
    std::string error;
    const std::string path = dir.file("s.exr");
    ASSERT_TRUE(writeExr(path, {width, height, {"R", "G", "B"}, false, halves.data()}, codec, {},
                         nullptr, error));
    size[static_cast<int>(codec)] = test::fs::file_size(path);
  }
  EXPECT_LT(size[1], size[0]);
  EXPECT_LT(size[2], size[1]);
  EXPECT_LT(size[3], size[2]);
}

TEST(ImageFile, WritesThroughTheEncodersWithTheirNamesAndErrors) {
  test::TempDir dir;
  const int width = 20, height = 10;
  const auto halves = halvesOf(frameLike(width, height, 4, 31));
  ImageWriteSpec spec{width, height, 4, PixelType::Half};
  spec.textAttributes = {{"compression", "rle"}, {"DateTime", ""}};
  writeImageFile(dir.file("a.exr"), spec, halves.data(), "a.exr");
  auto in = OIIO::ImageInput::open(dir.file("a.exr"));
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().nchannels, 4);
  EXPECT_EQ(in->spec().alpha_channel, 3);  // "A" read as alpha
  EXPECT_EQ(in->spec().get_string_attribute("compression"), "rle");
  EXPECT_FALSE(in->spec().find_attribute("DateTime"));
  // A directory that is not there: the error names the path the user knows.
  try {
    writeImageFile(dir.file("gone/a.exr"), spec, halves.data(), "frames/a.exr", "the frame");
    FAIL() << "no error";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("frames/a.exr: cannot write the frame"), std::string::npos)
        << e.what();
  }
  const auto bytes = bytesOf(frameLike(width, height, 3, 37), 8);
  ImageWriteSpec png{width, height, 3, PixelType::UInt8};
  png.integerAttributes = {{"png:compressionLevel", 1}};
  EXPECT_THROW(writeImageFile(dir.file("gone/a.png"), png, bytes.data(), "a.png"), UserError);
}

}  // namespace
}  // namespace acpca
