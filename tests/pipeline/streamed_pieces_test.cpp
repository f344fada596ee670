// The pieces of the streamed build: how the image is cut into tiles, and the
// rows RowSource renders on demand, which must be the rows precompute writes.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>

#include "pipeline/tile_files.h"
#include "pipeline/tile_plan.h"
#include "precompute/scene.h"
#include "precompute/transport_renderer.h"
#include "tests/test_support.h"

namespace acpca {
namespace {

TEST(TilePlan, EveryRowInOneTileInRowMajorOrderWithEdgeTilesCut) {
  const ImageSize size{10, 7};
  std::vector<std::int32_t> pixels;  // every pixel but a 4x4 block at (4, 0): its tile is empty
  for (int p = 0; p < size.pixels(); ++p)
    if (!(p % 10 >= 4 && p % 10 < 8 && p / 10 < 4)) pixels.push_back(p);
  const std::vector<Tile> tiles = planTiles(size, pixels, 4);
  ASSERT_EQ(tiles.size(), 5u) << "3 x 2 tiles, one empty";
  std::vector<int> seen(pixels.size(), 0);
  for (size_t t = 0; t < tiles.size(); ++t) {
    const Tile& tile = tiles[t];
    EXPECT_EQ(tile.width, tile.x0 == 8 ? 2 : 4);
    EXPECT_EQ(tile.height, tile.y0 == 4 ? 3 : 4);
    EXPECT_TRUE(std::is_sorted(tile.rows.begin(), tile.rows.end()));
    if (t > 0) {
      EXPECT_TRUE(tiles[t - 1].y0 < tile.y0 ||
                  (tiles[t - 1].y0 == tile.y0 && tiles[t - 1].x0 < tile.x0));
    }
    const std::vector<std::int32_t> local = tilePixels(tile, size, pixels);
    for (size_t i = 0; i < tile.rows.size(); ++i) {
      const int x = pixels[tile.rows[i]] % 10, y = pixels[tile.rows[i]] / 10;
      EXPECT_EQ(local[i], (y - tile.y0) * tile.width + (x - tile.x0));
      ++seen[tile.rows[i]];
    }
  }
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](int n) { return n == 1; }));
  EXPECT_THROW(planTiles(size, pixels, 0), ParameterError);
}

TEST(RowSource, RendersEachRowAsPrecomputeWritesIt) {
  // In any order and any subset, direct light and bounced light (whose
  // visibility cache must be the one precompute builds), rounded through half
  // as the f16 file stores the rows.
  test::TempDir dir;
  Scene scene = makeBuiltinScene("plant");
  scene.camera.size = {20, 18};
  for (int bounces : {0, 1}) {
    SCOPED_TRACE(bounces);
    PrecomputeOptions o;
    o.cubemapResolution = 4;
    o.samplesPerPixel = 2;
    o.bounces = bounces;
    o.indirectSamples = 4;
    precomputeTransport(scene, dir.file("t.h5"), o);
    const TransportReader file(dir.file("t.h5"));
    const RowSource source(scene, o);
    ASSERT_EQ(source.header().pixels, file.header().pixels);
    ASSERT_EQ(source.header().albedo, file.header().albedo);
    ASSERT_EQ(source.rowLength(), file.rowLength());
    std::vector<long long> rows(static_cast<size_t>(file.rows()));
    std::iota(rows.begin(), rows.end(), 0);
    std::shuffle(rows.begin(), rows.end(), std::mt19937(7));
    rows.resize(rows.size() / 2);
    std::vector<float> rendered(rows.size() * source.rowLength());
    const auto [shadowRays, pathRays] = source.render(rows, rendered.data());
    EXPECT_GT(shadowRays, 0);
    EXPECT_EQ(pathRays > 0, bounces > 0);
    std::vector<float> stored(static_cast<size_t>(file.rowLength()));
    long long nonzero = 0;
    for (size_t i = 0; i < rows.size(); ++i) {
      file.readRows(rows[i], 1, stored.data());
      for (int j = 0; j < file.rowLength(); ++j) {
        ASSERT_EQ(rendered[i * source.rowLength() + j], stored[j]) << "row " << rows[i];
        nonzero += stored[j] != 0;
      }
    }
    EXPECT_GT(nonzero, 0);
  }
}

TEST(TileFiles, AnUnreadableFileIsNamed) {
  test::TempDir dir;
  try {
    readBytes(dir.file("missing.h5"));
    ADD_FAILURE() << "read a missing file";
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("missing.h5"), std::string::npos) << e.what();
  }
  writeBytes(dir.file("a.bin"), {'x', 'y'});
  EXPECT_EQ(readBytes(dir.file("a.bin")), (std::vector<char>{'x', 'y'}));
  EXPECT_NE(fingerprint("ab", 2), fingerprint("ba", 2));
}

}  // namespace
}  // namespace acpca
