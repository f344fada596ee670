#include "model/model_arrays.h"

namespace acpca {

void readClusterOffsets(hid_t f, Model& m, long long rows, long long n, long long clusters,
                        const std::string& ctx) {
  m.rowOffsets =
      readVector<std::int64_t>(f, "cluster_row_offsets", H5T_NATIVE_INT64, clusters + 1, ctx);
  m.ranks = readVector<std::int32_t>(f, "cluster_rank", H5T_NATIVE_INT32, clusters, ctx);
  m.basisOffsets =
      readVector<std::int64_t>(f, "cluster_basis_offsets", H5T_NATIVE_INT64, clusters + 1, ctx);
  m.coefficientOffsets =
      readVector<std::int64_t>(f, "coefficient_offsets", H5T_NATIVE_INT64, clusters + 1, ctx);
  if (m.rowOffsets[0] != 0 || m.basisOffsets[0] != 0 || m.coefficientOffsets[0] != 0)
    throw UserError(concat(ctx, ": cluster offsets do not start at 0"));
  for (long long c = 0; c < clusters; ++c) {
    const long long p = m.rowOffsets[c + 1] - m.rowOffsets[c];
    if (p < 0 || p > rows || m.ranks[c] < 0 || m.ranks[c] > n ||
        m.basisOffsets[c + 1] - m.basisOffsets[c] != n * m.ranks[c] ||
        m.coefficientOffsets[c + 1] - m.coefficientOffsets[c] != p * m.ranks[c])
      throw UserError(concat(ctx, ": cluster ", c, " has inconsistent sizes"));
  }
  if (m.rowOffsets.back() != rows) throw UserError(concat(ctx, ": clusters do not cover the rows"));
}

void readClusterArrays(hid_t f, Model& m, long long rows, long long n, long long clusters,
                       const std::string& ctx) {
  m.clusterRows = readVector<std::int32_t>(f, "cluster_rows", H5T_NATIVE_INT32, rows, ctx);
  readClusterOffsets(f, m, rows, n, clusters, ctx);
  // HDF5 converts half datasets to float on read.
  m.bases = readVector<float>(f, "bases", H5T_NATIVE_FLOAT, m.basisOffsets.back(), ctx);
  m.means = readVector<float>(f, "means", H5T_NATIVE_FLOAT, clusters * n, ctx);
  m.coeffScale = readVector<float>(f, "coefficient_scale", H5T_NATIVE_FLOAT,
                                   n > 0 ? m.basisOffsets.back() / n : 0, ctx);
  const long long coefficients = m.coefficientOffsets.back();
  if (m.precision == CoeffPrecision::F32)
    m.coeffF32 = readVector<float>(f, "coefficients", H5T_NATIVE_FLOAT, coefficients, ctx);
  if (m.precision == CoeffPrecision::F16) {
    const h5::Handle half = h5::halfType();
    m.coeffF16 = readVector<std::uint16_t>(f, "coefficients", half.get(), coefficients, ctx);
  }
  if (m.precision == CoeffPrecision::I8)
    m.coeffI8 = readVector<std::int8_t>(f, "coefficients", H5T_NATIVE_INT8, coefficients, ctx);
}

}  // namespace acpca
