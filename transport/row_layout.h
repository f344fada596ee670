#pragma once
// How a lighting meets a row: with one row per pixel every channel of the
// lighting multiplies the same row; with R, G and B rows side by side (light
// that bounced off coloured surfaces), channel c multiplies the c-th third.
#include <Eigen/Core>
#include <vector>

#include "core/error.h"

namespace acpca {

/// The lighting (3 values per texel, radiance x solid angle) as a
/// (channels x l) x 3 matrix L_rows, so that a pixel's RGB is albedo times
/// row . L_rows for every row layout: column c holds channel c where the row
/// holds channel c's values, and zero elsewhere.
template <typename Scalar = float>
Eigen::Matrix<Scalar, Eigen::Dynamic, 3> lightingOnRows(const std::vector<double>& lighting,
                                                        int latticeSize, int channels) {
  ACPCA_CHECK(static_cast<long long>(lighting.size()) == 3LL * latticeSize, "lighting has ",
              lighting.size(), " values for a lattice of ", latticeSize);
  ACPCA_CHECK(channels == 1 || channels == 3, channels, " channels");
  Eigen::Matrix<Scalar, Eigen::Dynamic, 3> out = Eigen::Matrix<Scalar, Eigen::Dynamic, 3>::Zero(
      static_cast<Eigen::Index>(channels) * latticeSize, 3);
  for (int j = 0; j < latticeSize; ++j)
    for (int c = 0; c < 3; ++c)
      out((channels == 1 ? 0 : c) * latticeSize + j, c) = static_cast<Scalar>(lighting[3 * j + c]);
  return out;
}

}  // namespace acpca
