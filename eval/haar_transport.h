#pragma once
// The wavelet baseline of Ng et al. 2003: each transport row and each frame's
// lighting in an orthonormal 2D Haar basis per cube face. Per frame the lighting
// keeps only its k largest coefficients (a non-linear approximation); the relit
// pixel is the dot product of its wavelet-domain row with those k terms, read
// from a sparse column-major layout so that a frame touches only k columns.
#include <cstdint>
#include <vector>

#include "lighting/environment.h"
#include "transport/transport_file.h"

namespace acpca {

/// In place, the orthonormal 2D Haar transform of an R x R face (R a power of
/// two), row-major: the non-standard decomposition, level by level.
void haarForward2d(float* face, int resolution);
/// The inverse of haarForward2d.
void haarInverse2d(float* face, int resolution);

class HaarTransport {
 public:
  /// Reads T once. Coefficients whose magnitude is below 2^-bits of their row's
  /// largest are dropped (they would quantize to zero at `bits` bits, as Ng's 6);
  /// the others are kept in half precision. bits <= 0 keeps every non-zero.
  HaarTransport(const TransportReader& transport, int bits = 6);

  /// Relights with the `terms` largest wavelet coefficients of the lighting
  /// (by RGB magnitude); rgb: 3 floats per row, albedo applied.
  void relight(const LatticeLighting& lighting, int terms, float* rgb);
  std::vector<float> relight(const LatticeLighting& lighting, int terms);

  long long rows() const { return rows_; }
  /// Kept coefficients over all rows x lattice entries (Ng reports 12% for a plant).
  double fillRatio() const;
  /// Bytes of the sparse transport (values, row indices, column starts, albedo).
  long long bytes() const;
  /// Multiply-adds per pixel and channel of the last relight: entries of the chosen columns / rows.
  double lastCostPerPixel() const { return lastCost_; }

 private:
  /// Rows are split into blocks, each with its own columns, so threads write
  /// disjoint pixels and sum in a fixed order.
  struct RowBlock {
    long long firstRow = 0;
    std::vector<std::int64_t> columnStart;  ///< latticeSize + 1
    std::vector<std::uint16_t> row;         ///< row within the block
    std::vector<std::uint16_t> value;       ///< half
  };
  int resolution_ = 0, latticeSize_ = 0, rowLength_ = 0, channels_ = 1;
  long long rows_ = 0;
  std::vector<RowBlock> blocks_;
  std::vector<float> albedo_;
  double lastCost_ = 0;
  std::vector<float> light_;  ///< per frame: 3 x latticeSize, wavelet domain
};

}  // namespace acpca
