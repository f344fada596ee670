#include "model/model_file.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/half.h"
#include "model/cost_model.h"
#include "model/model_arrays.h"
#include "model/model_summary.h"
#include "model/model_values.h"
#include "transport/hdf5_handles.h"
#include "transport/image_header.h"

namespace acpca {

namespace {

template <typename T>
void writeVector(hid_t f, const std::string& name, const std::vector<T>& v, hid_t type,
                 const std::string& ctx) {
  h5::writeTyped(f, name, {static_cast<hsize_t>(v.size())}, type, v.data(), ctx);
}

}  // namespace

struct ModelFileWriter::Datasets {
  explicit Datasets(const std::string& path) : output(path) {}
  AtomicOutput output;
  h5::Handle file, half;
  h5::PiecewiseDataset rows, rowOffsets, ranks, basisOffsets, bases, means, coefficientOffsets,
      scale, coefficients;
};

ModelSizes ModelSizes::of(const Model& m) {
  return {m.clusters(), static_cast<long long>(m.clusterRows.size()),
          static_cast<long long>(m.bases.size()), m.coefficientOffsets.back()};
}

ModelSizes& ModelSizes::operator+=(const ModelSizes& o) {
  clusters += o.clusters, rows += o.rows, basisValues += o.basisValues,
      coefficients += o.coefficients;
  return *this;
}

ModelFileWriter::ModelFileWriter(const std::string& path, const Model& head,
                                 const ModelSizes& sizes, ModelFileKind kind)
    : path_(path),
      globalBases_(head.globalBases()),
      hasMean_(head.hasMean),
      precision_(head.precision),
      basisPrecision_(head.basisPrecision),
      data_(std::make_unique<Datasets>(path)) {
  Datasets& d = *data_;
  d.file = h5::createFile(d.output.tempPath(), path);
  d.half = h5::halfType();
  const hid_t f = d.file.get();
  const std::string& ctx = path;
  const bool whole = kind == ModelFileKind::Whole;
  h5::writeAttribute(f, "format", std::string(whole ? kModelFormat : kClustersFormat), ctx);
  h5::writeAttribute(f, "version", static_cast<long long>(kModelVersion), ctx);
  h5::writeAttribute(f, "method", head.method, ctx);
  h5::writeAttribute(f, "settings", head.settings, ctx);
  if (whole) writeImageHeader(f, head.geometry, ctx);
  h5::writeAttribute(f, "global_bases", static_cast<long long>(globalBases_), ctx);
  h5::writeAttribute(f, "has_mean", static_cast<long long>(hasMean_), ctx);
  h5::writeAttribute(f, "coeffs", std::string(coeffPrecisionName(precision_)), ctx);
  h5::writeAttribute(f, "bases", std::string(coeffPrecisionName(basisPrecision_)), ctx);
  if (whole) {
    // global_basis as [l, N] row-major, as numpy reads it.
    const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> vg =
        head.globalBasis;
    h5::writeDataset(f, "global_basis",
                     {static_cast<hsize_t>(vg.rows()), static_cast<hsize_t>(vg.cols())}, vg.data(),
                     ctx);
  }
  const hid_t basisType = basisPrecision_ == CoeffPrecision::F16 ? d.half.get() : H5T_NATIVE_FLOAT;
  const hid_t coefficientType = precision_ == CoeffPrecision::F16  ? d.half.get()
                                : precision_ == CoeffPrecision::I8 ? H5T_NATIVE_INT8
                                                                   : H5T_NATIVE_FLOAT;
  const auto size = [](long long n) { return static_cast<hsize_t>(n); };
  const long long c = sizes.clusters, n = globalBases_;
  d.rows = h5::PiecewiseDataset(f, "cluster_rows", H5T_NATIVE_INT32, size(sizes.rows), ctx);
  d.rowOffsets = h5::PiecewiseDataset(f, "cluster_row_offsets", H5T_NATIVE_INT64, size(c + 1), ctx);
  d.ranks = h5::PiecewiseDataset(f, "cluster_rank", H5T_NATIVE_INT32, size(c), ctx);
  d.basisOffsets =
      h5::PiecewiseDataset(f, "cluster_basis_offsets", H5T_NATIVE_INT64, size(c + 1), ctx);
  d.bases = h5::PiecewiseDataset(f, "bases", basisType, size(sizes.basisValues), ctx);
  d.means = h5::PiecewiseDataset(f, "means", basisType, size(c * n), ctx);
  d.coefficientOffsets =
      h5::PiecewiseDataset(f, "coefficient_offsets", H5T_NATIVE_INT64, size(c + 1), ctx);
  d.scale = h5::PiecewiseDataset(f, "coefficient_scale", H5T_NATIVE_FLOAT,
                                 size(n > 0 ? sizes.basisValues / n : 0), ctx);
  d.coefficients =
      h5::PiecewiseDataset(f, "coefficients", coefficientType, size(sizes.coefficients), ctx);
  const std::int64_t zero = 0;
  for (auto* offsets : {&d.rowOffsets, &d.basisOffsets, &d.coefficientOffsets})
    offsets->append(H5T_NATIVE_INT64, &zero, 1);
}

ModelFileWriter::~ModelFileWriter() = default;

void ModelFileWriter::append(const Model& m) {
  Datasets& d = *data_;
  const long long clusters = m.clusters(), n = globalBases_;
  ACPCA_CHECK(
      m.precision == precision_ && m.basisPrecision == basisPrecision_ && m.hasMean == hasMean_,
      "clusters appended in another precision");
  ACPCA_CHECK(m.means.size() == static_cast<size_t>(clusters * n), "means of ", clusters,
              " clusters of ", n, " global bases");
  const auto shifted = [](const std::vector<std::int64_t>& offsets, std::int64_t by) {
    std::vector<std::int64_t> out(offsets.begin() + 1, offsets.end());
    for (auto& o : out) o += by;
    return out;
  };
  const std::vector<std::int64_t> rowOffsets = shifted(m.rowOffsets, rows_),
                                  basisOffsets = shifted(m.basisOffsets, d.bases.written()),
                                  coefficientOffsets =
                                      shifted(m.coefficientOffsets, d.coefficients.written());
  d.rows.append(H5T_NATIVE_INT32, m.clusterRows.data(), m.clusterRows.size());
  d.rowOffsets.append(H5T_NATIVE_INT64, rowOffsets.data(), rowOffsets.size());
  d.ranks.append(H5T_NATIVE_INT32, m.ranks.data(), m.ranks.size());
  d.basisOffsets.append(H5T_NATIVE_INT64, basisOffsets.data(), basisOffsets.size());
  if (basisPrecision_ == CoeffPrecision::F16) {
    // The values are half-representable: the conversion is exact.
    for (const auto* values : {&m.bases, &m.means}) {
      std::vector<std::uint16_t> h(values->size());
      floatToHalf(values->data(), h.data(), h.size());
      (values == &m.bases ? d.bases : d.means).append(d.half.get(), h.data(), h.size());
    }
  } else {
    d.bases.append(H5T_NATIVE_FLOAT, m.bases.data(), m.bases.size());
    d.means.append(H5T_NATIVE_FLOAT, m.means.data(), m.means.size());
  }
  d.coefficientOffsets.append(H5T_NATIVE_INT64, coefficientOffsets.data(),
                              coefficientOffsets.size());
  d.scale.append(H5T_NATIVE_FLOAT, m.coeffScale.data(), m.coeffScale.size());
  if (precision_ == CoeffPrecision::F32)
    d.coefficients.append(H5T_NATIVE_FLOAT, m.coeffF32.data(), m.coeffF32.size());
  if (precision_ == CoeffPrecision::F16)
    d.coefficients.append(d.half.get(), m.coeffF16.data(), m.coeffF16.size());
  if (precision_ == CoeffPrecision::I8)
    d.coefficients.append(H5T_NATIVE_INT8, m.coeffI8.data(), m.coeffI8.size());
  for (long long c = 0; c < clusters; ++c)  // as Model::totalCost sums it
    totalCost_ += clusterCost(m.ranks[c] + (hasMean_ ? 1 : 0),
                              m.rowOffsets[c + 1] - m.rowOffsets[c], globalBases_);
  clusters_ += clusters;
  rows_ += m.rowOffsets.empty() ? 0 : m.rowOffsets.back();
}

void ModelFileWriter::writeArray(const std::string& name, const std::vector<float>& values) {
  h5::writeDataset(data_->file.get(), name, {static_cast<hsize_t>(values.size())}, values.data(),
                   path_);
}

void ModelFileWriter::finish(const Model& summary, const std::map<std::string, double>& extra) {
  Datasets& d = *data_;
  const hid_t f = d.file.get();
  const std::string& ctx = path_;
  h5::writeAttribute(f, "clusters", clusters_, ctx);
  h5::writeAttribute(f, "total_cost", totalCost_, ctx);
  h5::writeAttribute(f, "cost_per_pixel", rows_ ? totalCost_ / rows_ : 0.0, ctx);
  h5::writeAttribute(f, "transport_error", summary.transportError, ctx);
  h5::writeAttribute(f, "global_energy_kept", summary.globalEnergyKept, ctx);
  for (const auto& [name, value] : extra) h5::writeAttribute(f, name, value, ctx);
  h5::writeAttribute(f, "complete", 1LL, ctx);  // last: marks the file whole
  for (auto* set : {&d.rows, &d.rowOffsets, &d.ranks, &d.basisOffsets, &d.bases, &d.means,
                    &d.coefficientOffsets, &d.scale, &d.coefficients}) {
    ACPCA_CHECK(set->written() == set->size(), path_, ": ", set->written(), " of ", set->size(),
                " values appended");
    *set = h5::PiecewiseDataset();
  }
  d.half.reset();
  h5::closeWrittenFile(d.file, path_);
  d.output.commit();
}

void writeModel(const Model& m, const std::string& path) {
  ModelFileWriter writer(path, m, ModelSizes::of(m));
  writer.append(m);
  writer.finish(m);
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

ModelSummary readModelSummary(const std::string& path) {
  const h5::Handle file = openModelFile(path);
  const hid_t f = file.get();
  ModelSummary s;
  Model m;  // its attributes and cluster offsets only
  m.geometry = readImageHeaderAttributes(f, false, path, s.pixels);
  const auto [n, clusters] = readModelAttributes(f, path, s.pixels.rows, m.geometry.rowLength(), m);
  readClusterOffsets(f, m, s.pixels.rows, n, clusters, path);
  s.geometry = std::move(m.geometry);
  s.method = std::move(m.method);
  s.settings = std::move(m.settings);
  s.globalBases = static_cast<int>(n);
  s.hasMean = m.hasMean;
  s.precision = m.precision;
  s.basisPrecision = m.basisPrecision;
  s.transportError = m.transportError;
  s.ranks = std::move(m.ranks);
  s.rowOffsets = std::move(m.rowOffsets);
  s.basisValues = m.basisOffsets.back();
  s.coefficientValues = m.coefficientOffsets.back();
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  s.fileBytes = ec ? -1 : static_cast<long long>(bytes);
  return s;
}

double ModelSummary::totalCost() const {
  return clustersCost(ranks, rowOffsets, hasMean, globalBases);
}

long long ModelSummary::frameBytes() const {
  return frameBytesOf(precision, basisPrecision, basisValues,
                      hasMean ? static_cast<long long>(clusters()) * globalBases : 0,
                      coefficientValues,
                      geometry.rowLength() * static_cast<long long>(globalBases));
}

Model readModel(const std::string& path) {
  const std::string& ctx = path;
  const h5::Handle file = openModelFile(path);
  const hid_t f = file.get();
  Model m;
  const auto [n, clusters] = readModelLayout(f, ctx, m);
  Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> vg(m.geometry.rowLength(),
                                                                           n);
  h5::readDataset(f, "global_basis", vg.data(), ctx);
  m.globalBasis = vg;
  m.bases = readVector<float>(f, "bases", H5T_NATIVE_FLOAT, m.basisOffsets.back(), ctx);
  readCoefficients(f, m, ctx);
  checkModelValues(m, ctx);
  return m;
}

}  // namespace acpca
