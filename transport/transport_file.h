#pragma once
// The transport file: an HDF5 file holding, for every occupied pixel, its row of
// T over the cube lattice (docs/design.md section 3), plus the image geometry, camera,
// per-pixel albedo, coverage and normal. Layout: docs/formats.md.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/atomic_file.h"
#include "core/enum_names.h"
#include "transport/camera.h"
#include "transport/hdf5_handles.h"
#include "transport/lamp_geometry.h"
#include "transport/light_set.h"

namespace acpca {

enum class Precision { F16, F32 };
inline constexpr EnumNames<Precision, 2> kPrecisionNames{
    "precision", {{{Precision::F16, "f16"}, {Precision::F32, "f32"}}}};
Precision parsePrecision(const std::string& text);  // "f16" | "f32"
const char* precisionName(Precision p);

inline constexpr const char* kTransportFormat = "adaptive-cpca transport";
/// Version 2 added the per-pixel `position`, version 3 the per-pixel `object`
/// and the scene's object names, version 4 the light set of captured
/// transports, version 5 the lamp samples and surfaces (transport/
/// lamp_geometry.h; docs/formats.md), version 6 their tangents and
/// anisotropic materials; earlier files are read without them.
inline constexpr int kTransportVersion = 6;
inline constexpr int kOldestTransportVersion = 1;

/// Everything about a transport except its rows.
struct TransportHeader {
  Camera camera;               ///< camera.size is the image size; the rest unset for a light set
  int cubemapResolution = 32;  ///< 0 for a light set
  /// The lighting domain of a captured transport (empty: the cube lattice).
  LightSet lights;
  int samplesPerPixel = 1;
  int texelRays = 1;
  Precision precision = Precision::F16;
  std::string scene;
  /// Rows per pixel layout: 1, one row shared by R, G and B (the light reaching
  /// the pixel has the colour of the lighting); 3, the R, G and B rows side by
  /// side (light that bounced off coloured surfaces carries their colour).
  int channels = 1;
  /// How the transport was made: bounces of indirect light (0: direct only),
  /// paths per pixel sample, and the visibility cache's cell (relative to the
  /// scene's extent; 0: exact shadow rays at every path vertex).
  int bounces = 0;
  int indirectSamples = 0;
  double indirectCacheCell = 0;

  std::vector<std::int32_t> pixels;  ///< linear index y*W+x of each row, increasing
  std::vector<float> albedo;         ///< 3 per row, linear RGB
  std::vector<float> coverage;       ///< 1 per row: fraction of pixel samples that hit
  std::vector<float> normals;        ///< 3 per row: shading normal (first hit sample)
  /// 3 per row: the world point the first hit sample's shadow rays start from
  /// (local lights are seen from there); empty in files made before version 2.
  std::vector<float> positions;
  /// 1 per row: which of objectNames the first hit sample met; empty in
  /// files made before transport version 3 and model version 5.
  std::vector<std::int32_t> objects;
  std::vector<std::string> objectNames;  ///< the scene's objects, in id order
  /// What a point or spot lamp's exact direct light needs (empty before
  /// transport version 5 and model version 7, and for light sets).
  LampGeometry lamps;

  bool hasPositions() const { return rows() == 0 || !positions.empty(); }
  /// Models made before version 5 hold no normals (transports always do).
  bool hasNormals() const { return rows() == 0 || !normals.empty(); }
  bool hasObjects() const { return rows() == 0 || !objects.empty(); }

  long long rows() const { return static_cast<long long>(pixels.size()); }
  /// Imported images over a light set: no camera, no geometry per pixel.
  bool isLightSet() const { return !lights.empty(); }
  /// Columns of the lighting domain: cube-lattice texels, or lights.
  int latticeSize() const {
    return isLightSet() ? lights.size() : 6 * cubemapResolution * cubemapResolution;
  }
  /// Values per row: channels x latticeSize, channel c's at [c l, (c + 1) l).
  int rowLength() const { return channels * latticeSize(); }
  /// Throws UserError when sizes or values do not agree (context names the file).
  void validate(const std::string& context) const;
};

/// Each column's direction and solid angle: the lattice's texels, or a light
/// set's lights and their cells.
struct ColumnGeometry {
  std::vector<Vec3> directions;
  std::vector<double> solidAngles;
};
ColumnGeometry columnGeometry(const TransportHeader& header);

/// Writes a transport file row block by row block, in increasing row order.
/// The file appears under its final name only after finish().
class TransportWriter {
 public:
  TransportWriter(const std::string& path, const TransportHeader& header);
  ~TransportWriter();
  /// rows: count x rowLength floats, row-major; firstRow must follow the last block.
  void writeRows(long long firstRow, long long count, const float* rows);
  /// Marks the file complete and moves it into place.
  void finish();
  long long bytesWritten() const { return bytesWritten_; }

 private:
  AtomicOutput output_;
  TransportHeader header_;
  h5::Handle file_, rows_, halfType_;
  long long nextRow_ = 0;
  long long bytesWritten_ = 0;
  std::vector<std::uint16_t> halfBuffer_;
};

/// Opens and validates a complete transport file; rows are read on demand.
class TransportReader {
 public:
  explicit TransportReader(const std::string& path);
  const std::string& path() const { return path_; }
  const TransportHeader& header() const { return header_; }
  long long rows() const { return header_.rows(); }
  int latticeSize() const { return header_.latticeSize(); }
  int rowLength() const { return header_.rowLength(); }
  /// Reads rows [first, first + count) as floats into out (count x rowLength).
  /// Not thread-safe: call from one thread at a time.
  void readRows(long long first, long long count, float* out) const;
  /// Size of the file on disk.
  long long fileBytes() const;

 private:
  std::string path_;
  TransportHeader header_;
  h5::Handle file_, rows_;
  mutable std::vector<std::uint16_t> halfBuffer_;
};

}  // namespace acpca
