#pragma once
// The cluster arrays model files and the streamed build's tile-cluster files
// share (docs/formats.md, "Model file"): read with their sizes checked.
// Inside the library only.
#include <string>
#include <vector>

#include "core/error.h"
#include "model/model.h"
#include "transport/hdf5_handles.h"

namespace acpca {

/// The model file at `path`, its format, version and completeness checked.
h5::Handle openModelFile(const std::string& path);

struct ModelCounts {
  long long globalBases, clusters;
};

/// The model's own attributes (past the image header) into m, and the
/// global basis's shape; N and C checked against the rows and row length.
ModelCounts readModelAttributes(hid_t f, const std::string& ctx, long long rows, long long l,
                                Model& m);

/// A model file's header, attributes, cluster rows (a partition of the rows,
/// checked), offsets, means and steps, but not its global basis, bases or
/// coefficients (left empty: the caller reads those its own way).
ModelCounts readModelLayout(hid_t f, const std::string& ctx, Model& m);

/// Marks a file of model clusters (one tile of a streamed build).
inline constexpr const char* kClustersFormat = "adaptive-cpca model clusters";

/// A 1-D dataset of exactly `expected` values; UserError naming ctx otherwise.
template <typename T>
std::vector<T> readVector(hid_t f, const std::string& name, hid_t type, hsize_t expected,
                          const std::string& ctx) {
  const auto shape = h5::datasetShape(f, name, ctx);
  if (shape.size() != 1 || shape[0] != expected)
    throw UserError(concat(ctx, ": dataset '", name, "' has the wrong size"));
  std::vector<T> v(expected);
  h5::readTyped(f, name, type, v.data(), ctx);
  return v;
}

/// The cluster offsets and ranks of a model file (small: C + 1 values each),
/// checked against each other and the rows, without the large arrays.
void readClusterOffsets(hid_t f, Model& m, long long rows, long long n, long long clusters,
                        const std::string& ctx);

/// The cluster rows, offsets, means and steps of a model file (rows of its
/// clusters in all, n global bases): offsets checked against the ranks and
/// sizes first.
void readClusterLayout(hid_t f, Model& m, long long rows, long long n, long long clusters,
                       const std::string& ctx);

/// The same and the bases and coefficients.
void readClusterArrays(hid_t f, Model& m, long long rows, long long n, long long clusters,
                       const std::string& ctx);

/// The coefficients, in the model's precision (after readClusterLayout).
void readCoefficients(hid_t f, Model& m, const std::string& ctx);

/// The coefficients' memory type for a precision (half: `half`).
hid_t coefficientType(CoeffPrecision p, hid_t half);

}  // namespace acpca
