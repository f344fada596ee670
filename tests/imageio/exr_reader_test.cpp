// EXRs read through OpenEXR's C++ library, without OpenImageIO, must give
// what OpenImageIO gives: the same channels in the same order and the same
// values, for Blender's world maps (DWAB) and for files of every codec; the
// files they do not cover still open, through OpenImageIO.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "imageio/exr_reader.h"
#include "imageio/image_file.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

/// Every channel of `path` as floats, by OpenImageIO.
std::vector<float> readByOpenImageIo(const std::string& path, OIIO::ImageSpec& spec) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return {};
  spec = in->spec();
  std::vector<float> v(spec.image_pixels() * spec.nchannels);
  EXPECT_TRUE(in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, v.data()));
  return v;
}

void expectSameAsOpenImageIo(const std::string& path) {
  auto reader = openExrDirectly(path);
  ASSERT_TRUE(reader) << path;
  OIIO::ImageSpec spec;
  const std::vector<float> expected = readByOpenImageIo(path, spec);
  const ImageHeader& h = reader->header();
  EXPECT_EQ(h.width, spec.width);
  EXPECT_EQ(h.height, spec.height);
  ASSERT_EQ(h.channels, spec.nchannels);
  EXPECT_EQ(h.channelNames, spec.channelnames);
  EXPECT_EQ(h.alphaChannel, spec.alpha_channel);
  EXPECT_EQ(h.stored, StoredValues::FloatingPoint);
  std::vector<float> values(expected.size());
  ASSERT_TRUE(reader->readImage(0, h.channels, PixelType::Float, values.data())) << reader->error();
  EXPECT_EQ(values, expected) << path;
  // A band of rows and a range of channels, as the OLAT importer reads.
  const int y0 = h.height / 3, y1 = h.height / 3 + 5, c0 = h.channels > 1 ? 1 : 0;
  std::vector<float> band(static_cast<size_t>(y1 - y0) * h.width * (h.channels - c0));
  ASSERT_TRUE(reader->readRows(y0, y1, c0, h.channels, PixelType::Float, band.data()));
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < h.width; ++x)
      for (int c = c0; c < h.channels; ++c)
        ASSERT_EQ(band[((y - y0) * h.width + x) * (h.channels - c0) + (c - c0)],
                  expected[(static_cast<size_t>(y) * h.width + x) * h.channels + c]);
}

TEST(ExrReader, BlendersWorldMapsReadAsOpenImageIoReadsThem) {
  const std::filesystem::path maps = "/usr/share/blender/datafiles/studiolights/world";
  int read = 0;
  for (const auto& e : std::filesystem::directory_iterator(maps))
    if (e.path().extension() == ".exr") expectSameAsOpenImageIo(e.path().string()), ++read;
  EXPECT_EQ(read, 8);
}

TEST(ExrReader, EveryCodecAndChannelSetReadsAsOpenImageIoReadsIt) {
  test::TempDir dir;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> value(0, 4);
  const int width = 37, height = 29;
  const std::vector<std::vector<std::string>> sets = {
      {"R", "G", "B"}, {"R", "G", "B", "A"}, {"Y"}, {"Y", "A"}, {"R", "G"}};
  for (const auto& names : sets)
    for (const char* codec : {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "dwaa"})
      for (bool tiled : {false, true}) {
        OIIO::ImageSpec spec(width, height, static_cast<int>(names.size()), OIIO::TypeDesc::HALF);
        spec.channelnames = names;
        spec.alpha_channel = names.back() == "A" ? static_cast<int>(names.size()) - 1 : -1;
        spec.attribute("compression", codec);
        if (tiled) spec.tile_width = spec.tile_height = 16;
        std::vector<float> v(static_cast<size_t>(width) * height * names.size());
        for (float& x : v) x = value(rng);
        const std::string path = dir.file("f.exr");
        auto out = OIIO::ImageOutput::create(path);
        ASSERT_TRUE(out && out->open(path, spec) &&
                    out->write_image(OIIO::TypeDesc::FLOAT, v.data()) && out->close());
        SCOPED_TRACE(std::string(codec) + (tiled ? " tiled " : " ") + names[0]);
        expectSameAsOpenImageIo(path);
      }
}

TEST(ExrReader, FilesItDoesNotCoverStillOpenThroughOpenImageIo) {
  test::TempDir dir;
  const auto write = [&](const std::string& path, OIIO::ImageSpec spec) {
    std::vector<float> v(spec.image_pixels() * spec.nchannels, 0.5f);
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec) && out->write_image(OIIO::TypeDesc::FLOAT, v.data()) &&
                out->close());
  };
  OIIO::ImageSpec layered(8, 6, 4, OIIO::TypeDesc::FLOAT);
  layered.channelnames = {"R", "G", "B", "normal.X"};
  write(dir.file("layered.exr"), layered);
  OIIO::ImageSpec offset(8, 6, 3, OIIO::TypeDesc::HALF);
  offset.x = 2, offset.full_width = 12, offset.full_height = 6;
  write(dir.file("offset.exr"), offset);
  for (const char* name : {"layered.exr", "offset.exr"}) {
    EXPECT_FALSE(openExrDirectly(dir.file(name))) << name;
    std::string error;
    EXPECT_TRUE(openImage(dir.file(name), error)) << name << ": " << error;
  }
  // Not an EXR at all, or not there: null here, OpenImageIO's error through openImage.
  std::ofstream(dir.file("junk.exr")) << "not an image";
  EXPECT_FALSE(openExrDirectly(dir.file("junk.exr")));
  std::string error;
  EXPECT_FALSE(openImage(dir.file("junk.exr"), error));
  EXPECT_FALSE(error.empty());
  EXPECT_FALSE(openExrDirectly(dir.file("missing.exr")));
}

}  // namespace
}  // namespace acpca
