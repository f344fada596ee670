// A frame's colour space, camera and fields in its file, read back by
// OpenEXR's C++ library and libpng (readers nobody here wrote); the pixels
// stay the bytes they were without them.
#include <OpenEXR/ImfChromaticitiesAttribute.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFloatVectorAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <gtest/gtest.h>
#include <png.h>

#include <algorithm>
#include <fstream>

#include "imageio/frame_metadata.h"
#include "imageio/image_output.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

std::shared_ptr<FrameMetadata> sampleMetadata() {
  auto m = std::make_shared<FrameMetadata>();
  m->worldToCamera = std::array<float, 16>{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -1, -2, -3, 1};
  m->worldToNdc =
      std::array<float, 16>{0.5f, 0, 0, 0, 0, -0.5f, 0, 0, 0.5f, 0.5f, 0, 1, 0, 0, 1, 0};
  m->fields = {{"env", "sky"},
               {"yaw", 137.5},
               {"sh9", std::vector<double>(27, 0.25)},
               {"lights", {"point:0,1,0,5"}},
               {"sources", nlohmann::json::array()}};
  return m;
}

Image sampleImage(int channels) {
  Image image;
  image.width = 9, image.height = 5, image.channels = channels;
  for (int i = 0; i < image.width * image.height * channels; ++i)
    image.pixels.push_back(0.01f * static_cast<float>(i % 97));
  return image;
}

std::string bytesOfFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(FrameMetadata, ExrHeaderHoldsTypedAttributesThatOpenExrReads) {
  test::TempDir dir;
  const Image image = sampleImage(3);
  const std::string plain = dir.file("plain.exr"), tagged = dir.file("tagged.exr");
  encodeImage(image, plain, plain, ImageFormat::Exr, 0, {});
  const auto metadata = sampleMetadata();
  ImageEncoding encoding;
  encoding.metadata = metadata.get();
  encodeImage(image, tagged, tagged, ImageFormat::Exr, 0, encoding);
  Imf::InputFile in(tagged.c_str());
  const Imf::Header& h = in.header();
  const auto* chroma = h.findTypedAttribute<Imf::ChromaticitiesAttribute>("chromaticities");
  ASSERT_NE(chroma, nullptr);
  EXPECT_FLOAT_EQ(chroma->value().red.x, 0.64f);
  EXPECT_FLOAT_EQ(chroma->value().green.y, 0.60f);
  EXPECT_FLOAT_EQ(chroma->value().blue.x, 0.15f);
  EXPECT_FLOAT_EQ(chroma->value().white.x, 0.3127f);
  const auto* id = h.findTypedAttribute<Imf::StringAttribute>("colorInteropID");
  ASSERT_NE(id, nullptr);
  EXPECT_EQ(id->value(), "lin_rec709_scene");
  const auto* toCamera = h.findTypedAttribute<Imf::M44fAttribute>("worldToCamera");
  const auto* toNdc = h.findTypedAttribute<Imf::M44fAttribute>("worldToNDC");
  ASSERT_NE(toCamera, nullptr);
  ASSERT_NE(toNdc, nullptr);
  EXPECT_EQ(toCamera->value()[3][2], -3.0f) << "row 3 holds the translation (row vectors)";
  EXPECT_EQ(toNdc->value()[1][1], -0.5f);
  ASSERT_NE(h.findTypedAttribute<Imf::StringAttribute>("acpca:env"), nullptr);
  EXPECT_EQ(h.typedAttribute<Imf::StringAttribute>("acpca:env").value(), "sky");
  EXPECT_EQ(h.typedAttribute<Imf::DoubleAttribute>("acpca:yaw").value(), 137.5);
  EXPECT_EQ(h.typedAttribute<Imf::FloatVectorAttribute>("acpca:sh9").value(),
            std::vector<float>(27, 0.25f));
  EXPECT_EQ(h.typedAttribute<Imf::StringAttribute>("acpca:lights").value(), "[\"point:0,1,0,5\"]");
  EXPECT_EQ(h.typedAttribute<Imf::StringAttribute>("acpca:sources").value(), "[]");
  // The same pixels: the files differ in their headers alone, and the chunk
  // table's offsets by the header's growth.
  const std::string a = bytesOfFile(plain), b = bytesOfFile(tagged);
  const size_t pixelBytes = 9 * 5 * 3 * 2;
  EXPECT_EQ(a.substr(a.size() - pixelBytes / 2), b.substr(b.size() - pixelBytes / 2));
}

TEST(FrameMetadata, PizFilesCarryTheSameHeaderAndTheirPixels) {
  // PIZ goes through OpenEXR's own encode pipeline, in the same header writer.
  test::TempDir dir;
  const Image image = sampleImage(4);
  const auto metadata = sampleMetadata();
  for (bool isFloat : {false, true}) {
    ImageEncoding encoding;
    encoding.exrFloat = isFloat;
    encoding.exrCompression = ExrCompression::Piz;
    encoding.metadata = metadata.get();
    const std::string path = dir.file("piz.exr"), again = dir.file("again.exr");
    encodeImage(image, path, path, ImageFormat::Exr, 0, encoding);
    encodeImage(image, again, again, ImageFormat::Exr, 0, encoding);
    EXPECT_EQ(bytesOfFile(path), bytesOfFile(again)) << "no clock in the file";
    Imf::InputFile in(path.c_str());
    const Imf::Header& h = in.header();
    EXPECT_EQ(h.compression(), Imf::PIZ_COMPRESSION);
    EXPECT_EQ(h.find("capDate"), h.end());
    EXPECT_NE(h.findTypedAttribute<Imf::ChromaticitiesAttribute>("chromaticities"), nullptr);
    EXPECT_NE(h.findTypedAttribute<Imf::M44fAttribute>("worldToNDC"), nullptr);
    EXPECT_EQ(h.typedAttribute<Imf::DoubleAttribute>("acpca:yaw").value(), 137.5);
    // Every value back as written (half: the value's nearest half).
    const Imath::Box2i window = h.dataWindow();
    const int width = window.max.x + 1, height = window.max.y + 1;
    ASSERT_EQ(width, image.width);
    std::vector<float> read(static_cast<size_t>(width) * height * 4);
    Imf::FrameBuffer buffer;
    const char* names[] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; ++c)
      buffer.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(read.data() + c),
                                         4 * sizeof(float), 4 * sizeof(float) * width));
    in.setFrameBuffer(buffer);
    in.readPixels(0, height - 1);
    for (size_t k = 0; k < read.size(); ++k)
      ASSERT_NEAR(read[k], image.pixels[k], isFloat ? 0 : 1e-3 * std::max(1.0f, image.pixels[k]))
          << "value " << k << (isFloat ? " float" : " half");
  }
}

TEST(FrameMetadata, LabelsAreTaggedAsData) {
  FrameMetadata m;
  m.values = FrameMetadata::Values::Data;
  EXPECT_STREQ(m.colorInteropId(), "data");
  EXPECT_EQ(frameMetadataJson(m)["colorInteropID"], "data");
}

/// libpng's reading of a PNG's colour chunks, its text and its pixels.
struct PngRead {
  int srgbIntent = -1;
  png_fixed_point gamma = 0, whiteX = 0, redX = 0, greenY = 0;
  std::string text;
  std::vector<unsigned char> pixels;
};

PngRead readPng(const std::string& path) {
  PngRead r;
  FILE* file = std::fopen(path.c_str(), "rb");
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, file);
  png_read_png(png, info, PNG_TRANSFORM_IDENTITY, nullptr);
  png_get_sRGB(png, info, &r.srgbIntent);
  png_get_gAMA_fixed(png, info, &r.gamma);
  png_fixed_point wy, ry, gx, bx, by;
  png_get_cHRM_fixed(png, info, &r.whiteX, &wy, &r.redX, &ry, &gx, &r.greenY, &bx, &by);
  png_textp text = nullptr;
  int count = 0;
  png_get_text(png, info, &text, &count);
  for (int k = 0; k < count; ++k)
    if (std::string(text[k].key) == kPngFieldKeyword &&
        text[k].compression == PNG_ITXT_COMPRESSION_NONE)
      r.text = std::string(text[k].text, text[k].itxt_length);
  png_bytepp rows = png_get_rows(png, info);
  const size_t rowBytes = png_get_rowbytes(png, info);
  for (png_uint_32 y = 0; y < png_get_image_height(png, info); ++y)
    r.pixels.insert(r.pixels.end(), rows[y], rows[y] + rowBytes);
  png_destroy_read_struct(&png, &info, nullptr);
  std::fclose(file);
  return r;
}

TEST(FrameMetadata, PngHoldsItsSrgbChunksAndTheFieldsAsITxt) {
  test::TempDir dir;
  for (ImageFormat format : {ImageFormat::Png, ImageFormat::Png16}) {
    const Image image = sampleImage(4);
    const std::string plain = dir.file("plain.png"), tagged = dir.file("tagged.png");
    encodeImage(image, plain, plain, format, 0, {});
    const auto metadata = sampleMetadata();
    ImageEncoding encoding;
    encoding.metadata = metadata.get();
    encodeImage(image, tagged, tagged, format, 0, encoding);
    const PngRead a = readPng(plain), b = readPng(tagged);
    EXPECT_EQ(a.srgbIntent, -1) << "a picture without metadata is left as it was";
    EXPECT_EQ(b.srgbIntent, PNG_sRGB_INTENT_PERCEPTUAL);
    EXPECT_EQ(b.gamma, 45455);
    EXPECT_EQ(b.whiteX, 31270);
    EXPECT_EQ(b.redX, 64000);
    EXPECT_EQ(b.greenY, 60000);
    EXPECT_EQ(a.pixels, b.pixels);
    const nlohmann::json fields = nlohmann::json::parse(b.text);
    EXPECT_EQ(fields["env"], "sky");
    EXPECT_EQ(fields["yaw"], 137.5);
    EXPECT_EQ(fields["colorInteropID"], "lin_rec709_scene");
    EXPECT_EQ(fields["worldToCamera"][12], -1);
    // cICP, which libpng 1.6.39 does not know, by its bytes: BT.709, sRGB, RGB, full range.
    const std::string bytes = bytesOfFile(tagged);
    const size_t at = bytes.find("cICP");
    ASSERT_NE(at, std::string::npos);
    EXPECT_EQ(bytes.substr(at - 4, 12), std::string("\0\0\0\4cICP\1\15\0\1", 12));
    EXPECT_LT(at, bytes.find("IDAT")) << "colour chunks come before the image data";
  }
}

}  // namespace
}  // namespace acpca
