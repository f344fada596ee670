#include "cluster/model_file.h"

#include <algorithm>
#include <cmath>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/half.h"
#include "precompute/transport/hdf5_handles.h"
#include "precompute/transport/image_header.h"

namespace acpca {

namespace {

template <typename T>
void writeVector(hid_t f, const std::string& name, const std::vector<T>& v, hid_t type,
                 const std::string& ctx) {
  h5::writeTyped(f, name, {static_cast<hsize_t>(v.size())}, type, v.data(), ctx);
}

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

/// An upper bound on |relit value| per unit of the largest lattice light
/// value, from the triangle inequality on albedo_p * (u_p . W^T V_g^T L +
/// mu . V_g^T L): every value may be finite while their products overflow.
double relitBoundPerUnitLight(const Model& m) {
  const long long n = m.globalBases();
  double projection = 0;  // max_j sum_i |V_g(i, j)|: bounds |(V_g^T L)_j| / max|L|
  for (long long j = 0; j < n; ++j)
    projection = std::max(projection, double(m.globalBasis.col(j).cwiseAbs().sum()));
  double worstRow = 0;
  std::vector<double> basisNorm;
  for (int c = 0; c < m.clusters(); ++c) {
    basisNorm.assign(m.ranks[c], 0.0);
    for (int k = 0; k < m.ranks[c]; ++k)
      for (long long j = 0; j < n; ++j)
        basisNorm[k] += std::abs(m.bases[m.basisOffsets[c] + k * n + j]);
    double mean = 0;
    for (long long j = 0; j < n; ++j) mean += std::abs(m.means[c * n + j]);
    for (long long r = 0; r < m.rowOffsets[c + 1] - m.rowOffsets[c]; ++r) {
      double row = mean;
      for (int k = 0; k < m.ranks[c]; ++k) row += std::abs(m.coefficient(c, r, k)) * basisNorm[k];
      worstRow = std::max(worstRow, row);
    }
  }
  double albedo = 0;
  for (float a : m.geometry.albedo) albedo = std::max(albedo, double(a));
  return albedo * worstRow * projection;
}

}  // namespace

void writeModel(const Model& m, const std::string& path) {
  AtomicOutput output(path);
  {
    h5::Handle file = h5::createFile(output.tempPath());
    const hid_t f = file.get();
    const auto& g = m.geometry;
    const std::string& ctx = path;
    h5::writeAttribute(f, "format", std::string(kModelFormat), ctx);
    h5::writeAttribute(f, "version", static_cast<long long>(kModelVersion), ctx);
    h5::writeAttribute(f, "method", m.method, ctx);
    h5::writeAttribute(f, "settings", m.settings, ctx);
    writeImageHeader(f, g, false, ctx);
    h5::writeAttribute(f, "global_bases", static_cast<long long>(m.globalBases()), ctx);
    h5::writeAttribute(f, "clusters", static_cast<long long>(m.clusters()), ctx);
    h5::writeAttribute(f, "has_mean", static_cast<long long>(m.hasMean), ctx);
    h5::writeAttribute(f, "coeffs", std::string(coeffPrecisionName(m.precision)), ctx);
    h5::writeAttribute(f, "bases", std::string(coeffPrecisionName(m.basisPrecision)), ctx);
    h5::writeAttribute(f, "total_cost", m.totalCost(), ctx);
    h5::writeAttribute(f, "cost_per_pixel", m.costPerPixel(), ctx);
    h5::writeAttribute(f, "transport_error", m.transportError, ctx);
    h5::writeAttribute(f, "global_energy_kept", m.globalEnergyKept, ctx);
    h5::writeAttribute(f, "compress_seconds", m.compressSeconds, ctx);
    h5::writeAttribute(f, "peak_memory_bytes", m.peakMemoryBytes, ctx);
    // global_basis as [l, N] row-major, as numpy reads it.
    const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> vg = m.globalBasis;
    h5::writeDataset(f, "global_basis",
                     {static_cast<hsize_t>(vg.rows()), static_cast<hsize_t>(vg.cols())}, vg.data(),
                     ctx);
    writeVector(f, "cluster_rows", m.clusterRows, H5T_NATIVE_INT32, ctx);
    writeVector(f, "cluster_row_offsets", m.rowOffsets, H5T_NATIVE_INT64, ctx);
    writeVector(f, "cluster_rank", m.ranks, H5T_NATIVE_INT32, ctx);
    writeVector(f, "cluster_basis_offsets", m.basisOffsets, H5T_NATIVE_INT64, ctx);
    if (m.basisPrecision == CoeffPrecision::F16) {
      // The values are half-representable: the conversion is exact.
      const h5::Handle half = h5::halfType();
      for (const auto* values : {&m.bases, &m.means}) {
        std::vector<std::uint16_t> h(values->size());
        floatToHalf(values->data(), h.data(), h.size());
        writeVector(f, values == &m.bases ? "bases" : "means", h, half.get(), ctx);
      }
    } else {
      writeVector(f, "bases", m.bases, H5T_NATIVE_FLOAT, ctx);
      writeVector(f, "means", m.means, H5T_NATIVE_FLOAT, ctx);
    }
    writeVector(f, "coefficient_offsets", m.coefficientOffsets, H5T_NATIVE_INT64, ctx);
    writeVector(f, "coefficient_scale", m.coeffScale, H5T_NATIVE_FLOAT, ctx);
    if (m.precision == CoeffPrecision::F32)
      writeVector(f, "coefficients", m.coeffF32, H5T_NATIVE_FLOAT, ctx);
    if (m.precision == CoeffPrecision::F16) {
      const h5::Handle half = h5::halfType();
      writeVector(f, "coefficients", m.coeffF16, half.get(), ctx);
    }
    if (m.precision == CoeffPrecision::I8)
      writeVector(f, "coefficients", m.coeffI8, H5T_NATIVE_INT8, ctx);
    h5::writeAttribute(f, "complete", 1LL, ctx);  // last: marks the file whole
    h5::closeWrittenFile(file, path);
  }
  output.commit();
}

bool isModelFile(const std::string& path) {
  h5::silenceLibraryErrors();
  if (H5Fis_hdf5(path.c_str()) <= 0) return false;
  try {
    const h5::Handle file = h5::openFileReadOnly(path);
    return h5::hasAttribute(file.get(), "format") &&
           h5::readStringAttribute(file.get(), "format", path) == kModelFormat;
  } catch (const UserError&) {
    return false;
  }
}

Model readModel(const std::string& path) {
  const std::string& ctx = path;
  const h5::Handle file = h5::openFileReadOnly(path);
  const hid_t f = file.get();
  if (!h5::hasAttribute(f, "format") || h5::readStringAttribute(f, "format", ctx) != kModelFormat)
    throw UserError(concat(ctx, ": not an adaptive-cpca model file"));
  if (h5::readIntAttribute(f, "version", ctx) != kModelVersion)
    throw UserError(concat(ctx, ": unsupported model version"));
  if (!h5::hasAttribute(f, "complete") || h5::readIntAttribute(f, "complete", ctx) != 1)
    throw UserError(concat(ctx, ": the model file is incomplete"));
  Model m;
  m.geometry = readImageHeader(f, false, ctx);
  auto& g = m.geometry;
  m.method = h5::readStringAttribute(f, "method", ctx);
  m.settings = h5::readStringAttribute(f, "settings", ctx);
  const long long rows = g.rows();
  const long long n = h5::readIntAttribute(f, "global_bases", ctx);
  const long long clusters = h5::readIntAttribute(f, "clusters", ctx);
  const long long l = g.rowLength();
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
  m.compressSeconds = h5::readDoubleAttribute(f, "compress_seconds", ctx);
  m.peakMemoryBytes = h5::readIntAttribute(f, "peak_memory_bytes", ctx);

  if (h5::datasetShape(f, "global_basis", ctx) != std::vector<hsize_t>{hsize_t(l), hsize_t(n)})
    throw UserError(concat(ctx, ": dataset 'global_basis' has the wrong shape"));
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> vg(l, n);
  h5::readDataset(f, "global_basis", vg.data(), ctx);
  m.globalBasis = vg;
  m.clusterRows = readVector<std::int32_t>(f, "cluster_rows", H5T_NATIVE_INT32, rows, ctx);
  m.rowOffsets =
      readVector<std::int64_t>(f, "cluster_row_offsets", H5T_NATIVE_INT64, clusters + 1, ctx);
  m.ranks = readVector<std::int32_t>(f, "cluster_rank", H5T_NATIVE_INT32, clusters, ctx);
  m.basisOffsets =
      readVector<std::int64_t>(f, "cluster_basis_offsets", H5T_NATIVE_INT64, clusters + 1, ctx);
  m.coefficientOffsets =
      readVector<std::int64_t>(f, "coefficient_offsets", H5T_NATIVE_INT64, clusters + 1, ctx);
  // Every offset must agree with the ranks and sizes before the big arrays are read.
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
  g.validate(ctx);  // pixel indices in range and increasing, albedo and coverage sane
  std::vector<char> seen(rows, 0);
  for (auto r : m.clusterRows) {
    if (r < 0 || r >= rows || seen[r])
      throw UserError(concat(ctx, ": cluster rows are not a partition"));
    seen[r] = 1;
  }
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
  const auto finite = [&](const auto& values, const char* what) {
    for (float v : values)
      if (!std::isfinite(v)) throw UserError(concat(ctx, ": non-finite ", what));
  };
  finite(m.bases, "basis value");
  finite(m.means, "cluster mean");
  finite(m.coeffF32, "coefficient");
  finite(m.coeffScale, "coefficient scale");
  finite(Eigen::Map<const Eigen::VectorXf>(m.globalBasis.data(), m.globalBasis.size()),
         "global basis value");
  if (m.precision == CoeffPrecision::F16) {
    std::vector<float> decoded(m.coeffF16.size());
    halfToFloat(m.coeffF16.data(), decoded.data(), decoded.size());
    finite(decoded, "coefficient");
  }
  // Orthonormal bases and transport values below 1 keep real models many orders
  // below this; 1e20 still leaves lighting up to ~1e18 per
  // lattice direction before a relit value could overflow a float.
  if (!(relitBoundPerUnitLight(m) <= 1e20))
    throw UserError(concat(ctx, ": values out of range (relit values could overflow)"));
  return m;
}

}  // namespace acpca
