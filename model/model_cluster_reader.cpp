#include "model/model_cluster_reader.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/half.h"
#include "model/model_arrays.h"
#include "model/model_values.h"
#include "transport/dataset_slices.h"
#include "transport/hdf5_handles.h"

namespace acpca {

struct ModelClusterReader::Datasets {
  h5::Handle file, half;  // first: closed last
  std::unique_ptr<DatasetSlices> bases, coefficients;
};

namespace {

/// Rows of V_g per block of the parallel read (a few hundred KB).
constexpr long long kGlobalBasisBlockRows = 64;

}  // namespace

ModelClusterReader::ModelClusterReader(const std::string& path)
    : path_(path), sets_(std::make_unique<Datasets>()) {
  const std::string& ctx = path;
  Datasets& d = *sets_;
  d.file = openModelFile(path);
  d.half = h5::halfType();
  const hid_t f = d.file.get();
  const ModelCounts counts = readModelLayout(f, ctx, model_);
  globalBases_ = static_cast<int>(counts.globalBases);
  const long long n = counts.globalBases, l = model_.geometry.rowLength();

  // V_g in blocks of rows on all cores, each block's column sums kept apart and
  // added in block order, so the bound is the same whatever the threads.
  const DatasetSlices basis(f, path, "global_basis", H5T_NATIVE_FLOAT, {hsize_t(l), hsize_t(n)},
                            ctx);
  globalBasis_.reset(new float[std::max(1LL, l * n)]);  // every value read below
  const long long blocks = n > 0 ? (l + kGlobalBasisBlockRows - 1) / kGlobalBasisBlockRows : 0;
  std::vector<std::vector<double>> columnSums(blocks);
  tbb::parallel_for(0LL, blocks, [&](long long b) {
    const long long first = b * kGlobalBasisBlockRows,
                    count = std::min(kGlobalBasisBlockRows, l - first);
    float* rows = globalBasis_.get() + first * n;
    basis.read(first, count, rows);
    std::vector<double>& sums = columnSums[b];
    sums.assign(n, 0.0);
    for (long long r = 0; r < count; ++r)
      for (long long j = 0; j < n; ++j) sums[j] += std::abs(double(rows[r * n + j]));
    // A sum of floats in double cannot overflow: it is finite exactly when its values are.
    for (long long j = 0; j < n; ++j)
      if (!std::isfinite(sums[j])) throw UserError(concat(ctx, ": non-finite global basis value"));
  });
  for (long long j = 0; j < n; ++j) {
    double column = 0;
    for (const auto& sums : columnSums) column += sums[j];
    projectionBound_ = std::max(projectionBound_, column);
  }

  const hid_t basisType =
      model_.basisPrecision == CoeffPrecision::F16 ? d.half.get() : H5T_NATIVE_FLOAT;
  d.bases = std::make_unique<DatasetSlices>(
      f, path, "bases", basisType, std::vector<hsize_t>{hsize_t(model_.basisOffsets.back())}, ctx);
  d.coefficients = std::make_unique<DatasetSlices>(
      f, path, "coefficients", coefficientType(model_.precision, d.half.get()),
      std::vector<hsize_t>{hsize_t(model_.coefficientOffsets.back())}, ctx);
  terms_.resize(model_.clusters());
}

ModelClusterReader::~ModelClusterReader() = default;

ClusterValues ModelClusterReader::valuesOf(int c) const {
  const Model& m = model_;
  const long long n = globalBases_;
  ClusterValues v;
  v.rank = m.ranks[c];
  v.rows = m.rowOffsets[c + 1] - m.rowOffsets[c];
  v.globalBases = globalBases_;
  v.precision = m.precision;
  v.mean = m.means.data() + c * n;
  v.scale = m.coeffScale.data() + (n > 0 ? m.basisOffsets[c] / n : 0);
  return v;
}

const float* ModelClusterReader::readBases(int c, ClusterScratch& scratch) const {
  const long long values = static_cast<long long>(model_.ranks[c]) * globalBases_;
  scratch.bases.resize(values);
  if (model_.basisPrecision == CoeffPrecision::F16) {
    scratch.halves.resize(values);
    sets_->bases->read(model_.basisOffsets[c], values, scratch.halves.data());
    halfToFloat(scratch.halves.data(), scratch.bases.data(), values);
  } else {
    sets_->bases->read(model_.basisOffsets[c], values, scratch.bases.data());
  }
  ClusterValues v = valuesOf(c);
  v.bases = scratch.bases.data();
  // The terms sum every basis value and mean: not finite exactly when one of
  // them is not, so the value by value check runs only then, for its message.
  terms_[c] = clusterBoundTerms(v);
  bool finite = std::isfinite(terms_[c].mean);
  for (double w : terms_[c].weight) finite = finite && std::isfinite(w);
  for (int k = 0; k < v.rank; ++k) finite = finite && std::isfinite(v.scale[k]);
  if (!finite) checkBasesFinite(v, path_);
  return v.bases;
}

const void* ModelClusterReader::readCoefficients(int c, long long first, long long rows,
                                                 ClusterScratch& scratch) const {
  ClusterValues v = valuesOf(c);
  ACPCA_CHECK(first >= 0 && rows >= 0 && first + rows <= v.rows, "rows of cluster ", c);
  const long long values = rows * v.rank;
  const long long bytes = values * storedBytes(v.precision);
  scratch.coefficients.resize((bytes + sizeof(float) - 1) / sizeof(float));
  sets_->coefficients->read(model_.coefficientOffsets[c] + first * v.rank, values,
                            scratch.coefficients.data());
  v.rows = rows;
  v.coefficients = scratch.coefficients.data();
  const double bound = rowsBound(v, terms_[c]);  // infinite when a coefficient is not finite
  if (!std::isfinite(bound)) checkCoefficientsFinite(v, path_);
  const std::lock_guard<std::mutex> hold(boundLock_);
  rowBound_ = std::max(rowBound_, bound);
  return v.coefficients;
}

void ModelClusterReader::checkRelitBound() const {
  // A cluster without rows adds nothing: its bound is its rows' (none).
  acpca::checkRelitBound(largestAlbedo(model_.geometry) * rowBound_ * projectionBound_, path_);
}

}  // namespace acpca
