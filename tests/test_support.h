#pragma once
// Shared helpers for the test suites: temporary directories and the transport
// fixtures the build makes with the real CLI (tests/CMakeLists.txt), so that the
// cluster, relight and eval suites need no renderer.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/error.h"
#include "tests/temp_dir.h"
#include "transport/transport_file.h"

namespace acpca::test {

/// A transport fixture made at build time: "small-plant" (the plant at 40x40,
/// a 6x8x8 lattice, f32 rows), "grid2d" (40x30, 6x8x8, f16) or
/// "bounced-plant" (24x24, 6x8x8, f32, one bounce: R, G and B rows).
inline std::string fixture(const std::string& name) {
  return std::string(ACPCA_FIXTURE_DIR) + "/" + name + ".h5";
}

/// A suite whose tests share the small plant transport, `path()`.
class SmallPlantSuite : public ::testing::Test {
 protected:
  static std::string path() { return fixture("small-plant"); }
};

/// A whole file's bytes (empty when it cannot be read).
inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Writes `text` as the whole file.
inline void writeFile(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

/// Index of the row of pixel (x, y), or -1 for background.
inline long long rowOfPixel(const TransportHeader& h, int x, int y) {
  const int p = y * h.camera.size.width + x;
  const auto it = std::lower_bound(h.pixels.begin(), h.pixels.end(), p);
  return (it != h.pixels.end() && *it == p) ? it - h.pixels.begin() : -1;
}

}  // namespace acpca::test
