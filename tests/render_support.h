#pragma once
// Helpers for the suites that render (render, extreme): a scene precomputed
// and read back whole.
#include "precompute/scene.h"
#include "precompute/transport_renderer.h"
#include "tests/test_support.h"

namespace acpca::test {

/// A transport precomputed and read back whole (small scenes only).
struct LoadedTransport {
  TransportHeader header;
  std::vector<float> rows;  // rows x l
  PrecomputeStats stats;
  int l = 0;           ///< values per row: channels x directions
  int directions = 0;  ///< lattice texels
  /// Channel c's part of row r (channel 0's when one row serves R, G and B).
  const float* part(long long r, int c) const {
    return row(r) + (header.channels == 3 ? c * directions : 0);
  }
  const float* row(long long r) const { return rows.data() + r * l; }
};

inline LoadedTransport precomputeInMemory(const Scene& scene, const PrecomputeOptions& options) {
  TempDir dir;
  const std::string path = dir.file("t.h5");
  LoadedTransport t;
  t.stats = precomputeTransport(scene, path, options);
  const TransportReader reader(path);
  t.header = reader.header();
  t.l = reader.rowLength();
  t.directions = reader.latticeSize();
  t.rows.resize(static_cast<size_t>(reader.rows()) * t.l);
  reader.readRows(0, reader.rows(), t.rows.data());
  return t;
}

/// A floor of `material` through the origin, seen from straight above (+Y),
/// filling a size x size image.
inline Scene floorScene(int size, const Material& material) {
  Scene s{"floor", {}, {}, {}, {}, {}};
  s.camera.eye = {0, 5, 0};
  s.camera.target = {0, 0, 0};
  s.camera.up = {0, 0, -1};
  s.camera.fovDegrees = 20;
  s.camera.size = {size, size};
  s.meshes.push_back(makeQuad({0, 0, 0}, {0, 1, 0}, 100, material, "floor"));
  return s;
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

}  // namespace acpca::test
