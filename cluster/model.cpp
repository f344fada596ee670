#include "cluster/model.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <filesystem>
#include <queue>

#include "cluster/cost_model.h"
#include "cluster/pca.h"
#include "cluster/symmetric_eigen.h"
#include "precompute/transport/atomic_file.h"
#include "precompute/transport/error.h"
#include "precompute/transport/half.h"
#include "precompute/transport/hdf5_handles.h"

namespace acpca {

CoeffPrecision parseBasisPrecision(const std::string& text) {
  if (text == "f32") return CoeffPrecision::F32;
  if (text == "f16") return CoeffPrecision::F16;
  throw UserError(concat("--bases '", text, "' is not one of f32, f16"));
}

CoeffPrecision parseCoeffPrecision(const std::string& text) {
  if (text == "f32") return CoeffPrecision::F32;
  if (text == "f16") return CoeffPrecision::F16;
  if (text == "i8") return CoeffPrecision::I8;
  throw UserError(concat("--coeffs '", text, "' is not one of f32, f16, i8"));
}

const char* coeffPrecisionName(CoeffPrecision p) {
  return p == CoeffPrecision::F32 ? "f32" : p == CoeffPrecision::F16 ? "f16" : "i8";
}

double Model::totalCost() const {
  double cost = 0;
  for (int c = 0; c < clusters(); ++c)
    cost +=
        clusterCost(ranks[c] + (hasMean ? 1 : 0), rowOffsets[c + 1] - rowOffsets[c], globalBases());
  return cost;
}

float Model::coefficient(int c, long long r, int k) const {
  const long long i = coefficientOffsets[c] + r * ranks[c] + k;
  switch (precision) {
    case CoeffPrecision::F32:
      return coeffF32[i];
    case CoeffPrecision::F16: {
      float v;
      halfToFloat(&coeffF16[i], &v, 1);
      return v;
    }
    default:
      return coeffI8[i] * coeffScale[firstBasisIndex(c) + k];
  }
}

std::vector<int> Model::clusterOfRow() const {
  std::vector<int> out(static_cast<size_t>(rows()), -1);
  for (int c = 0; c < clusters(); ++c)
    for (auto r = rowOffsets[c]; r < rowOffsets[c + 1]; ++r) out[clusterRows[r]] = c;
  return out;
}

long long Model::frameBytes() const {
  const long long coefficientBytes = precision == CoeffPrecision::F32   ? 4
                                     : precision == CoeffPrecision::F16 ? 2
                                                                        : 1;
  const long long basisBytes = basisPrecision == CoeffPrecision::F16 ? 2 : 4;
  return static_cast<long long>(bases.size()) * basisBytes +
         (hasMean ? static_cast<long long>(means.size()) * basisBytes : 0) +
         coefficientOffsets.back() * coefficientBytes +
         static_cast<long long>(globalBasis.size()) * 4;
}

namespace {

struct ClusterFit {
  PcaResult pca;
  Eigen::MatrixXf coefficients;  // p x n
};

/// PCA of a cluster too large to copy in double (global PCA at 1024x1024 has
/// 716k rows of N ~ 2000): the N x N Gram matrix is summed over a fixed split
/// of the rows (so the sum does not depend on the thread count), each block
/// widened to double, and the coefficients are computed block by block.
ClusterFit fitLargeCluster(const RowMatrixF& g, const std::vector<int>& rows, double tolerance,
                           bool subtractMean) {
  const int n = static_cast<int>(g.cols());
  const long long p = static_cast<long long>(rows.size());
  constexpr int kParts = 8;
  constexpr long long kBlock = 2048;
  std::vector<Eigen::MatrixXd> grams(kParts, Eigen::MatrixXd::Zero(n, n));
  std::vector<Eigen::RowVectorXd> sums(kParts, Eigen::RowVectorXd::Zero(n));
  tbb::parallel_for(0, kParts, [&](int part) {
    const long long first = p * part / kParts, last = p * (part + 1) / kParts;
    Eigen::MatrixXd block;
    for (long long b = first; b < last; b += kBlock) {
      const long long count = std::min(kBlock, last - b);
      block.resize(count, n);
      for (long long i = 0; i < count; ++i) block.row(i) = g.row(rows[b + i]).cast<double>();
      grams[part].selfadjointView<Eigen::Lower>().rankUpdate(block.transpose());
      sums[part] += block.colwise().sum();
    }
  });
  Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(n, n);
  Eigen::RowVectorXd sum = Eigen::RowVectorXd::Zero(n);
  for (int part = 0; part < kParts; ++part) gram += grams[part], sum += sums[part];
  gram = gram.selfadjointView<Eigen::Lower>();
  ClusterFit fit;
  PcaResult& pca = fit.pca;
  pca.mean = subtractMean ? Eigen::RowVectorXd(sum / double(p)) : Eigen::RowVectorXd::Zero(n);
  gram -= double(p) * pca.mean.transpose() * pca.mean;  // centre: sum (g - mu)(g - mu)^T
  pca.totalEnergy = std::max(0.0, gram.trace());
  const SymmetricEigen eig = symmetricEigen(gram, true);
  pca.eigenvalues = eig.values;
  pca.rank = pca.totalEnergy > 0 ? rankForEnergy(eig.values, pca.totalEnergy, tolerance) : 0;
  pca.residualEnergy = std::max(0.0, pca.totalEnergy - eig.values.head(pca.rank).sum());
  pca.basis = eig.vectors.leftCols(pca.rank);
  const Eigen::MatrixXf basis = pca.basis.cast<float>();
  const Eigen::RowVectorXf mean = pca.mean.cast<float>();
  fit.coefficients.resize(p, pca.rank);
  tbb::parallel_for(0LL, (p + kBlock - 1) / kBlock, [&](long long b) {
    const long long first = b * kBlock, count = std::min(kBlock, p - first);
    Eigen::MatrixXf block(count, n);
    for (long long i = 0; i < count; ++i) block.row(i) = g.row(rows[first + i]) - mean;
    fit.coefficients.middleRows(first, count).noalias() = block * basis;
  });
  return fit;
}

/// Rounds every value to the nearest half (kept as float).
void roundToHalf(std::vector<float>& values) {
  std::vector<std::uint16_t> h(values.size());
  floatToHalf(values.data(), h.data(), values.size());
  halfToFloat(h.data(), values.data(), values.size());
}

/// sum over rows of |g_p - mu_c - W_c u_p|^2 with the stored (quantized)
/// values: the cluster part of the transport error, exact for any precision.
double reconstructionError(const Model& m, const RowMatrixF& g) {
  const int n = m.globalBases();
  std::vector<double> perCluster(m.clusters(), 0.0);
  tbb::parallel_for(0, m.clusters(), [&](int c) {
    const long long p = m.rowOffsets[c + 1] - m.rowOffsets[c];
    const int rank = m.ranks[c];
    const Eigen::Map<const Eigen::MatrixXf> w(m.bases.data() + m.basisOffsets[c], n, rank);
    const Eigen::Map<const Eigen::RowVectorXf> mean(m.means.data() + static_cast<size_t>(c) * n, n);
    constexpr long long kBlock = 1024;
    Eigen::MatrixXf rows, u;
    for (long long first = 0; first < p; first += kBlock) {
      const long long count = std::min(kBlock, p - first);
      rows.resize(count, n);
      u.resize(count, rank);
      for (long long i = 0; i < count; ++i) {
        rows.row(i) = g.row(m.clusterRows[m.rowOffsets[c] + first + i]) - mean;
        for (int k = 0; k < rank; ++k) u(i, k) = m.coefficient(c, first + i, k);
      }
      rows.noalias() -= u * w.transpose();
      perCluster[c] += rows.cast<double>().squaredNorm();
    }
  });
  double sum = 0;
  for (double e : perCluster) sum += e;  // fixed order
  return sum;
}

}  // namespace

Model buildModel(const TransportHeader& geometry, const GlobalBasis& basis,
                 const GlobalProjection& projection, const Partition& partition,
                 const ModelOptions& options) {
  const int n = basis.globalBases();
  Model m;
  m.geometry = geometry;
  m.globalBasis = basis.basis;
  m.hasMean = options.mean;
  ACPCA_CHECK(options.basisPrecision != CoeffPrecision::I8, "bases are f32 or f16");
  m.basisPrecision = options.basisPrecision;
  const int clusters = static_cast<int>(partition.size());

  std::vector<ClusterFit> fits(clusters);
  const double tolerance = options.allocateRanks ? 1.0 : options.tolerance;
  const auto large = [&](int c) {
    return static_cast<long long>(partition[c].size()) * n > options.largeClusterValues;
  };
  for (int c = 0; c < clusters; ++c)  // one at a time: each is parallel inside
    if (large(c))
      fits[c] = fitLargeCluster(projection.coefficients, partition[c], tolerance, options.mean);
  tbb::parallel_for(0, clusters, [&](int c) {
    if (large(c)) return;
    Eigen::MatrixXd rows(partition[c].size(), n);
    for (size_t i = 0; i < partition[c].size(); ++i)
      rows.row(i) = projection.coefficients.row(partition[c][i]).cast<double>();
    fits[c].pca = pcaToTolerance(rows, tolerance, options.mean, true);
    fits[c].coefficients = ((rows.rowwise() - fits[c].pca.mean) * fits[c].pca.basis).cast<float>();
  });
  if (options.allocateRanks) {
    std::vector<Eigen::VectorXd> spectra;
    std::vector<long long> sizes;
    double energy = 0;
    for (const auto& f : fits) {
      spectra.push_back(f.pca.eigenvalues);
      sizes.push_back(f.coefficients.rows());
      energy += f.pca.totalEnergy;
    }
    const std::vector<int> ranks =
        allocateRanks(spectra, sizes, n, (1 - options.tolerance) * energy);
    for (int c = 0; c < clusters; ++c) {  // keep the leading ranks[c] bases
      ClusterFit& f = fits[c];
      const int r = std::min(ranks[c], f.pca.rank);
      f.pca.residualEnergy = std::max(0.0, f.pca.totalEnergy - f.pca.eigenvalues.head(r).sum());
      f.pca.rank = r;
      f.pca.basis = f.pca.basis.leftCols(r).eval();
      f.coefficients = f.coefficients.leftCols(r).eval();
    }
  }

  m.rowOffsets.push_back(0);
  m.basisOffsets.push_back(0);
  m.coefficientOffsets.push_back(0);
  m.means.assign(static_cast<size_t>(clusters) * n, 0.0f);
  double clusterResidual = 0, quantizationError = 0;
  for (int c = 0; c < clusters; ++c) {
    ClusterFit& f = fits[c];
    const int rank = f.pca.rank;
    m.clusterRows.insert(m.clusterRows.end(), partition[c].begin(), partition[c].end());
    m.rowOffsets.push_back(m.clusterRows.size());
    m.ranks.push_back(rank);
    const Eigen::MatrixXf b = f.pca.basis.cast<float>();
    m.bases.insert(m.bases.end(), b.data(), b.data() + b.size());
    m.basisOffsets.push_back(m.bases.size());
    for (int k = 0; k < n; ++k) m.means[static_cast<size_t>(c) * n + k] = float(f.pca.mean[k]);
    clusterResidual += f.pca.residualEnergy;
    // Row-major p x n coefficients, stored as asked once all are in.
    const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> u = f.coefficients;
    const size_t count = u.size();
    m.coeffF32.insert(m.coeffF32.end(), u.data(), u.data() + count);
    m.coefficientOffsets.push_back(m.coefficientOffsets.back() + static_cast<long long>(count));
    f = ClusterFit();  // release as we go: one cluster may hold most of the model
  }
  m.precision = CoeffPrecision::F32;
  quantizationError = storeCoefficients(m, options.precision);
  if (m.basisPrecision == CoeffPrecision::F16) {
    roundToHalf(m.bases);
    roundToHalf(m.means);
    clusterResidual = reconstructionError(m, projection.coefficients);
    quantizationError = 0;  // included
  }
  const double total = projection.transportEnergy();
  const double globalResidual = projection.residualEnergy.sum();
  m.globalEnergyKept = total > 0 ? 1 - globalResidual / total : 1;
  m.transportError =
      total > 0
          ? std::sqrt(std::max(0.0, globalResidual + clusterResidual + quantizationError) / total)
          : 0;
  return m;
}

double storeCoefficients(Model& m, CoeffPrecision precision) {
  ACPCA_CHECK(m.precision == CoeffPrecision::F32 && m.coeffF16.empty() && m.coeffI8.empty(),
              "coefficients are already stored as ", coeffPrecisionName(m.precision));
  m.precision = precision;
  m.coeffScale.assign(m.clusters() ? m.firstBasisIndex(m.clusters()) : 0, 1.0f);
  if (precision == CoeffPrecision::F32) return 0;
  // Orthonormal bases: the coefficient error is the row error, so this is exact.
  double error = 0;
  const std::vector<float> exact = std::move(m.coeffF32);
  m.coeffF32.clear();
  if (precision == CoeffPrecision::F16) {
    m.coeffF16.resize(exact.size());
    floatToHalf(exact.data(), m.coeffF16.data(), exact.size());
    std::vector<float> back(exact.size());
    halfToFloat(m.coeffF16.data(), back.data(), back.size());
    for (size_t i = 0; i < exact.size(); ++i) error += std::pow(double(back[i]) - exact[i], 2);
    return error;
  }
  m.coeffI8.resize(exact.size());
  for (int c = 0; c < m.clusters(); ++c) {
    const int rank = m.ranks[c];
    const long long rows = m.rowOffsets[c + 1] - m.rowOffsets[c];
    const long long first = m.coefficientOffsets[c];
    for (int k = 0; k < rank; ++k) {
      float maxAbs = 0;
      for (long long r = 0; r < rows; ++r)
        maxAbs = std::max(maxAbs, std::abs(exact[first + r * rank + k]));
      const float scale = maxAbs > 0 ? maxAbs / 127.0f : 1.0f;
      for (long long r = 0; r < rows; ++r) {
        const long long i = first + r * rank + k;
        const float q = std::clamp(std::round(exact[i] / scale), -127.0f, 127.0f);
        m.coeffI8[i] = static_cast<std::int8_t>(q);
        error += std::pow(double(q) * scale - exact[i], 2);
      }
      m.coeffScale[m.firstBasisIndex(c) + k] = scale;
    }
  }
  return error;
}

std::vector<int> allocateRanks(const std::vector<Eigen::VectorXd>& spectra,
                               const std::vector<long long>& clusterSizes, int globalBases,
                               double budget) {
  const size_t c = spectra.size();
  std::vector<int> ranks(c, 0);
  double dropped = 0;
  for (const auto& s : spectra) dropped += s.sum();
  // Max-heap on the value of each cluster's next basis; ties broken by index
  // so the result is deterministic.
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry> next;
  const auto push = [&](int i) {
    if (ranks[i] < spectra[i].size() && spectra[i][ranks[i]] > 0)
      next.push({spectra[i][ranks[i]] / (double(clusterSizes[i]) + globalBases), -i});
  };
  for (size_t i = 0; i < c; ++i) push(static_cast<int>(i));
  while (dropped > budget && !next.empty()) {
    const int i = -next.top().second;
    next.pop();
    dropped -= spectra[i][ranks[i]];
    ++ranks[i];
    push(i);
  }
  return ranks;
}

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
    h5::writeAttribute(f, "width", static_cast<long long>(g.camera.size.width), ctx);
    h5::writeAttribute(f, "height", static_cast<long long>(g.camera.size.height), ctx);
    h5::writeAttribute(f, "cubemap", static_cast<long long>(g.cubemapResolution), ctx);
    h5::writeAttribute(f, "scene", g.scene, ctx);
    h5::writeAttribute(f, "camera_eye",
                       std::vector<double>{g.camera.eye.x(), g.camera.eye.y(), g.camera.eye.z()},
                       ctx);
    h5::writeAttribute(
        f, "camera_target",
        std::vector<double>{g.camera.target.x(), g.camera.target.y(), g.camera.target.z()}, ctx);
    h5::writeAttribute(f, "camera_up",
                       std::vector<double>{g.camera.up.x(), g.camera.up.y(), g.camera.up.z()}, ctx);
    h5::writeAttribute(f, "camera_fov_deg", g.camera.fovDegrees, ctx);
    h5::writeAttribute(f, "occupied_pixels", g.rows(), ctx);
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
    const hsize_t rows = g.rows();
    h5::writeDataset(f, "pixels", {rows}, g.pixels.data(), ctx);
    h5::writeDataset(f, "albedo", {rows, 3}, g.albedo.data(), ctx);
    h5::writeDataset(f, "coverage", {rows}, g.coverage.data(), ctx);
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
  auto& g = m.geometry;
  m.method = h5::readStringAttribute(f, "method", ctx);
  m.settings = h5::readStringAttribute(f, "settings", ctx);
  g.scene = h5::readStringAttribute(f, "scene", ctx);
  const long long width = h5::readIntAttribute(f, "width", ctx),
                  height = h5::readIntAttribute(f, "height", ctx);
  if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide)
    throw UserError(concat(ctx, ": image size out of range"));
  g.camera.size = {static_cast<int>(width), static_cast<int>(height)};
  const long long cubemap = h5::readIntAttribute(f, "cubemap", ctx);
  if (cubemap < 1 || cubemap > 256)
    throw UserError(concat(ctx, ": cube-map resolution out of range"));
  g.cubemapResolution = static_cast<int>(cubemap);
  const auto vec3 = [&](const char* name) {
    const auto v = h5::readDoubleArrayAttribute(f, name, ctx);
    if (v.size() != 3) throw UserError(concat(ctx, ": attribute ", name, " needs 3 numbers"));
    return Vec3(v[0], v[1], v[2]);
  };
  g.camera.eye = vec3("camera_eye");
  g.camera.target = vec3("camera_target");
  g.camera.up = vec3("camera_up");
  g.camera.fovDegrees = h5::readDoubleAttribute(f, "camera_fov_deg", ctx);
  const long long rows = h5::readIntAttribute(f, "occupied_pixels", ctx);
  const long long n = h5::readIntAttribute(f, "global_bases", ctx);
  const long long clusters = h5::readIntAttribute(f, "clusters", ctx);
  const long long l = 6 * cubemap * cubemap;
  if (rows < 0 || rows > g.camera.size.pixels() || n < 0 || n > l || clusters < 0 ||
      clusters > std::max(rows, 1LL))
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

  g.pixels = readVector<std::int32_t>(f, "pixels", H5T_NATIVE_INT32, rows, ctx);
  if (h5::datasetShape(f, "albedo", ctx) != std::vector<hsize_t>{hsize_t(rows), 3})
    throw UserError(concat(ctx, ": dataset 'albedo' has the wrong shape"));
  g.albedo.resize(3 * rows);
  h5::readDataset(f, "albedo", g.albedo.data(), ctx);
  g.coverage = readVector<float>(f, "coverage", H5T_NATIVE_FLOAT, rows, ctx);
  g.normals.assign(3 * rows, 0.0f);
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
  return m;
}

std::vector<std::vector<float>> relightModelReference(
    const Model& m, const std::vector<std::vector<double>>& lightings) {
  const int n = m.globalBases();
  const long long l = m.globalBasis.rows();
  std::vector<std::vector<float>> out;
  for (const auto& lighting : lightings) {
    ACPCA_CHECK(static_cast<long long>(lighting.size()) == 3 * l, "lighting size ",
                lighting.size());
    // L_g = V_g^T L (N x 3), in double.
    Eigen::MatrixXd lg = Eigen::MatrixXd::Zero(n, 3);
    for (long long j = 0; j < l; ++j)
      for (int k = 0; k < n; ++k)
        for (int c = 0; c < 3; ++c) lg(k, c) += double(m.globalBasis(j, k)) * lighting[3 * j + c];
    std::vector<float> rgb(3 * m.rows(), 0.0f);
    for (int cl = 0; cl < m.clusters(); ++cl) {
      const int rank = m.ranks[cl];
      const Eigen::Map<const Eigen::MatrixXf> w(m.bases.data() + m.basisOffsets[cl], n, rank);
      const Eigen::MatrixXd li = w.cast<double>().transpose() * lg;  // n_c x 3
      Eigen::RowVector3d meanTerm = Eigen::RowVector3d::Zero();
      if (m.hasMean)
        for (int k = 0; k < n; ++k)
          meanTerm += double(m.means[static_cast<size_t>(cl) * n + k]) * lg.row(k);
      for (long long r = 0; r < m.rowOffsets[cl + 1] - m.rowOffsets[cl]; ++r) {
        const int row = m.clusterRows[m.rowOffsets[cl] + r];
        Eigen::RowVector3d b = meanTerm;
        for (int k = 0; k < rank; ++k) b += double(m.coefficient(cl, r, k)) * li.row(k);
        for (int c = 0; c < 3; ++c) rgb[3 * row + c] = float(m.geometry.albedo[3 * row + c] * b[c]);
      }
    }
    out.push_back(std::move(rgb));
  }
  return out;
}

}  // namespace acpca
