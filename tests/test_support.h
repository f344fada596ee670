#pragma once
// Shared helpers for the test suites: temporary directories and transport files
// read back into memory.
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <string>
#include <vector>

#include "precompute/render/scene.h"
#include "precompute/render/transport_renderer.h"
#include "precompute/transport/error.h"
#include "precompute/transport/transport_file.h"

namespace acpca::test {

namespace fs = std::filesystem;

/// A fresh directory under the system temp dir, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    path_ = fs::temp_directory_path() /
            ("acpca-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

/// A transport precomputed and read back whole (small scenes only).
struct LoadedTransport {
  TransportHeader header;
  std::vector<float> rows;  // rows x l
  PrecomputeStats stats;
  int l = 0;
  const float* row(long long r) const { return rows.data() + r * l; }
};

inline LoadedTransport precomputeInMemory(const Scene& scene, const PrecomputeOptions& options) {
  TempDir dir;
  const std::string path = dir.file("t.h5");
  LoadedTransport t;
  t.stats = precomputeTransport(scene, path, options);
  const TransportReader reader(path);
  t.header = reader.header();
  t.l = reader.latticeSize();
  t.rows.resize(static_cast<size_t>(reader.rows()) * t.l);
  reader.readRows(0, reader.rows(), t.rows.data());
  return t;
}

/// The small plant the compression and relighting suites share: 40x40 pixels,
/// a 6x8x8 lattice, f32 rows, written to `path`.
inline void precomputeSmallPlant(const std::string& path) {
  Scene scene = makePlantScene();
  scene.camera.size = {40, 40};
  PrecomputeOptions o;
  o.cubemapResolution = 8;
  o.precision = Precision::F32;
  precomputeTransport(scene, path, o);
}

/// A suite whose tests share one small plant transport, `path()`, in `dir_`.
class SmallPlantSuite : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    precomputeSmallPlant(dir_->file("t.h5"));
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::string path() { return dir_->file("t.h5"); }
  static inline TempDir* dir_ = nullptr;
};

/// Index of the row of pixel (x, y), or -1 for background.
inline long long rowOfPixel(const TransportHeader& h, int x, int y) {
  const int p = y * h.camera.size.width + x;
  const auto it = std::lower_bound(h.pixels.begin(), h.pixels.end(), p);
  return (it != h.pixels.end() && *it == p) ? it - h.pixels.begin() : -1;
}

}  // namespace acpca::test
