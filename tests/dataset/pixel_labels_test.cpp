// Parsing AOV lists, refusing labels a file cannot give, and the .npy layout.
#include "dataset/pixel_labels.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>

#include "core/error.h"
#include "imageio/npy_file.h"
#include "tests/temp_dir.h"

namespace acpca {
namespace {

TEST(AovList, NamesAndPresetsGiveEachAovOnceInTheirOrder) {
  EXPECT_EQ(parseAovList("shading,albedo,albedo"), (std::vector<Aov>{Aov::Albedo, Aov::Shading}));
  EXPECT_EQ(parseAovList("all").size(), 8u);
  EXPECT_EQ(parseAovList("intrinsic"), (std::vector<Aov>{Aov::Albedo, Aov::Mask, Aov::Shading}));
  EXPECT_EQ(parseAovList("geometry,mask"),
            (std::vector<Aov>{Aov::Normal, Aov::Tangent, Aov::Depth, Aov::Position, Aov::Mask,
                              Aov::Object}));
  EXPECT_TRUE(parseAovList("").empty());
  for (const char* bad : {"albedo,,mask", "albedo,", "Albedo", "diffuse", "normals"}) {
    try {
      parseAovList(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const ParameterError& e) {
      EXPECT_NE(std::string(e.what()).find("AOV"), std::string::npos) << e.what();
    }
  }
}

TransportHeader twoRows() {
  TransportHeader h;
  h.camera.size = {2, 2};
  h.pixels = {0, 3};
  h.albedo = {0.5f, 0.5f, 0.5f, 1, 0, 0.25f};
  h.coverage = {1, 0.5f};
  return h;
}

TEST(AovList, LabelsAnOlderFileCannotGiveAreRefusedNamingWhatToRunAgain) {
  const TransportHeader h = twoRows();  // no normals, positions or objects
  EXPECT_EQ(availableAovs(h), (std::vector<Aov>{Aov::Albedo, Aov::Mask, Aov::Shading}));
  EXPECT_NO_THROW(requireAovs(h, {Aov::Albedo, Aov::Mask, Aov::Shading}, "m.h5", true));
  const auto message = [&](Aov aov, bool model) {
    try {
      requireAovs(h, {aov}, "old.h5", model);
    } catch (const UserError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message(Aov::Normal, true).find("old.h5: cannot give the 'normal' label"),
            std::string::npos);
  EXPECT_NE(message(Aov::Normal, true).find("compress"), std::string::npos);
  EXPECT_NE(message(Aov::Object, false).find("run precompute again"), std::string::npos);
  EXPECT_NE(message(Aov::Depth, false).find("position"), std::string::npos);
}

TEST(PixelLabels, BackgroundHoldsZeroAndNoObjectAndTheAlbedoIsPremultiplied) {
  TransportHeader h = twoRows();
  h.objectNames = {"a", "b"};
  h.objects = {1, 0};
  const std::vector<LabelLayer> layers =
      viewLabels(h, {Aov::Albedo, Aov::Mask, Aov::Object, Aov::Shading});
  ASSERT_EQ(layers.size(), 3u);  // shading is per frame
  EXPECT_EQ(layers[0].values,
            (std::vector<float>{0.5f, 0.5f, 0.5f, 0, 0, 0, 0, 0, 0, 0.5f, 0, 0.125f}));
  EXPECT_EQ(layers[1].values, (std::vector<float>{1, 0, 0, 0.5f}));
  EXPECT_EQ(layers[2].values, (std::vector<float>{1, -1, -1, 0}));
  // Shading: the frame less its background, over coverage x albedo; 0 where
  // the albedo is.
  const std::vector<float> frame{1, 2, 3, 9, 9, 9, 9, 9, 9, 0.5f, 7, 0.25f};
  const std::vector<float> background{0, 0, 0, 9, 9, 9, 9, 9, 9, 0.25f, 1, 0};
  std::vector<float> shading(12);
  frameShading(h, frame.data(), background.data(), 3, shading.data());
  EXPECT_EQ(shading, (std::vector<float>{2, 4, 6, 0, 0, 0, 0, 0, 0, 0.5f, 0, 2}));
}

TEST(Npy, TheHeaderIsNumpysVersionOneLayout) {
  test::TempDir dir;
  const std::string path = dir.file("a.npy");
  const std::vector<float> values{1, 2, 3, 4, 5, 6};
  writeNpy(path, path, {2, 3}, values.data());
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 10u);
  EXPECT_EQ(bytes.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  const size_t headerLength = static_cast<unsigned char>(bytes[8]) | (bytes[9] << 8);
  EXPECT_EQ((10 + headerLength) % 64, 0u);  // the data starts aligned
  const std::string header = bytes.substr(10, headerLength);
  EXPECT_EQ(header.back(), '\n');
  EXPECT_NE(header.find("'descr': '<f4'"), std::string::npos) << header;
  EXPECT_NE(header.find("'shape': (2, 3)"), std::string::npos) << header;
  ASSERT_EQ(bytes.size(), 10 + headerLength + 24);
  EXPECT_EQ(std::memcmp(bytes.data() + 10 + headerLength, values.data(), 24), 0);
  const std::int32_t ids[2] = {-1, 7};
  writeNpy(path, path, {2}, ids);
  std::ifstream again(path, std::ios::binary);
  const std::string idBytes((std::istreambuf_iterator<char>(again)),
                            std::istreambuf_iterator<char>());
  EXPECT_NE(idBytes.find("'descr': '<i4'"), std::string::npos);
  EXPECT_NE(idBytes.find("'shape': (2,)"), std::string::npos);  // a 1-tuple keeps its comma
}

}  // namespace
}  // namespace acpca
