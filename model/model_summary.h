#pragma once
// A model file read for what `info` reports: attributes, shapes and the
// clusters' ranks and sizes, none of its large arrays (per-pixel data, bases,
// coefficients); and the figures both it and a whole Model compute from
// those numbers.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "model/model.h"
#include "transport/file_summary.h"

namespace acpca {

/// sum over clusters of n_c (p_c + N) (eq. 17/19), a mean counted as one
/// more basis; cluster c's rows are rowOffsets[c] .. rowOffsets[c + 1).
double clustersCost(const std::vector<std::int32_t>& ranks,
                    const std::vector<std::int64_t>& rowOffsets, bool hasMean, int globalBases);
/// Bytes a relight reads per frame: cluster bases and means in their
/// precision, coefficients in theirs, the global basis in f32.
long long frameBytesOf(CoeffPrecision coefficients, CoeffPrecision bases, long long basisValues,
                       long long meanValues, long long coefficientValues,
                       long long globalBasisValues);
/// How many clusters have each rank; the ranks in one short line (as for a Model).
std::map<int, int> rankHistogram(const std::vector<std::int32_t>& ranks);
std::string rankSummary(const std::vector<std::int32_t>& ranks);

/// A model file's attributes, shapes and cluster ranks, its large arrays
/// (per-pixel data, bases, coefficients) left unread: what `info` reports,
/// read in milliseconds at any size.
struct ModelSummary {
  TransportHeader geometry;  ///< attributes only: its per-pixel arrays are empty
  PixelDatasets pixels;
  std::string method, settings;
  int globalBases = 0;
  bool hasMean = false;
  CoeffPrecision precision = CoeffPrecision::F32, basisPrecision = CoeffPrecision::F32;
  double transportError = 0;
  std::vector<std::int32_t> ranks;       ///< n_c
  std::vector<std::int64_t> rowOffsets;  ///< C + 1
  long long basisValues = 0, coefficientValues = 0;
  long long fileBytes = -1;

  int clusters() const { return static_cast<int>(ranks.size()); }
  /// As Model's, from the same numbers.
  double totalCost() const;
  double costPerPixel() const { return pixels.rows ? totalCost() / pixels.rows : 0; }
  long long frameBytes() const;
};

/// Checks the file as readModel does, but for the values of its arrays.
ModelSummary readModelSummary(const std::string& path);

}  // namespace acpca
