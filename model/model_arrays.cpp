#include "model/model_arrays.h"

#include <algorithm>

#include "model/model_file.h"
#include "transport/image_header.h"

namespace acpca {

h5::Handle openModelFile(const std::string& path) {
  const std::string& ctx = path;
  h5::Handle file = h5::openFileReadOnly(path);
  const hid_t f = file.get();
  if (!h5::hasAttribute(f, "format") || h5::readStringAttribute(f, "format", ctx) != kModelFormat)
    throw UserError(concat(ctx, ": not an adaptive-cpca model file"));
  const long long version = h5::readIntAttribute(f, "version", ctx);
  if (version < kOldestModelVersion || version > kModelVersion)
    throw UserError(concat(ctx, ": model format version ", version, "; this build reads ",
                           kOldestModelVersion, " to ", kModelVersion,
                           version < kOldestModelVersion ? ": compress (or build) it again"
                                                         : ": written by a newer adaptive-cpca"));
  if (!h5::hasAttribute(f, "complete") || h5::readIntAttribute(f, "complete", ctx) != 1)
    throw UserError(concat(ctx, ": the model file is incomplete"));
  return file;
}

ModelCounts readModelAttributes(hid_t f, const std::string& ctx, long long rows, long long l,
                                Model& m) {
  m.method = h5::readStringAttribute(f, "method", ctx);
  m.settings = h5::readStringAttribute(f, "settings", ctx);
  const long long n = h5::readIntAttribute(f, "global_bases", ctx);
  const long long clusters = h5::readIntAttribute(f, "clusters", ctx);
  if (n < 0 || n > l || clusters < 0 || clusters > std::max(rows, 1LL))
    throw UserError(concat(ctx, ": sizes in the header do not add up"));
  m.hasMean = h5::readIntAttribute(f, "has_mean", ctx) != 0;
  // Storage kinds, named as the file's attributes (not as the CLI options).
  const auto storage = [&](const char* attribute, bool allowI8) {
    const std::string text = h5::readStringAttribute(f, attribute, ctx);
    if (text == "f32") return CoeffPrecision::F32;
    if (text == "f16") return CoeffPrecision::F16;
    if (text == "i8" && allowI8) return CoeffPrecision::I8;
    throw UserError(concat(ctx, ": attribute '", attribute, "' is '", text, "'"));
  };
  m.precision = storage("coeffs", true);
  m.basisPrecision = h5::hasAttribute(f, "bases") ? storage("bases", false) : CoeffPrecision::F32;
  m.transportError = h5::readDoubleAttribute(f, "transport_error", ctx);
  m.globalEnergyKept = h5::readDoubleAttribute(f, "global_energy_kept", ctx);
  if (h5::datasetShape(f, "global_basis", ctx) != std::vector<hsize_t>{hsize_t(l), hsize_t(n)})
    throw UserError(concat(ctx, ": dataset 'global_basis' has the wrong shape"));
  return {n, clusters};
}

ModelCounts readModelLayout(hid_t f, const std::string& ctx, Model& m) {
  m.geometry = readImageHeader(f, false, ctx);
  TransportHeader& g = m.geometry;
  const long long rows = g.rows();
  const ModelCounts counts = readModelAttributes(f, ctx, rows, g.rowLength(), m);
  readClusterLayout(f, m, rows, counts.globalBases, counts.clusters, ctx);
  g.validate(ctx);  // pixel indices in range and increasing, albedo and coverage sane
  std::vector<char> seen(rows, 0);
  for (auto r : m.clusterRows) {
    if (r < 0 || r >= rows || seen[r])
      throw UserError(concat(ctx, ": cluster rows are not a partition"));
    seen[r] = 1;
  }
  return counts;
}

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

void readClusterLayout(hid_t f, Model& m, long long rows, long long n, long long clusters,
                       const std::string& ctx) {
  m.clusterRows = readVector<std::int32_t>(f, "cluster_rows", H5T_NATIVE_INT32, rows, ctx);
  readClusterOffsets(f, m, rows, n, clusters, ctx);
  // HDF5 converts half datasets to float on read.
  m.means = readVector<float>(f, "means", H5T_NATIVE_FLOAT, clusters * n, ctx);
  m.coeffScale = readVector<float>(f, "coefficient_scale", H5T_NATIVE_FLOAT,
                                   n > 0 ? m.basisOffsets.back() / n : 0, ctx);
}

void readClusterArrays(hid_t f, Model& m, long long rows, long long n, long long clusters,
                       const std::string& ctx) {
  readClusterLayout(f, m, rows, n, clusters, ctx);
  m.bases = readVector<float>(f, "bases", H5T_NATIVE_FLOAT, m.basisOffsets.back(), ctx);
  readCoefficients(f, m, ctx);
}

hid_t coefficientType(CoeffPrecision p, hid_t half) {
  return p == CoeffPrecision::F32   ? H5T_NATIVE_FLOAT
         : p == CoeffPrecision::F16 ? half
                                    : H5T_NATIVE_INT8;
}

void readCoefficients(hid_t f, Model& m, const std::string& ctx) {
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
