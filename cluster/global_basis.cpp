#include "cluster/global_basis.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <random>

#include "cluster/symmetric_eigen.h"
#include "core/error.h"
#include "transport/row_stream.h"

namespace acpca {

namespace {

/// `count` distinct row indices out of `total`, sorted (Floyd's algorithm; the
/// raw mt19937_64 stream is specified by the standard, so are the indices).
std::vector<long long> sampleRows(long long total, long long count, std::mt19937_64& rng) {
  count = std::min(count, total);
  std::vector<long long> chosen;
  std::vector<char> taken(static_cast<size_t>(total), 0);
  for (long long j = total - count; j < total; ++j) {
    const long long t = static_cast<long long>(rng() % static_cast<unsigned long long>(j + 1));
    const long long pick = taken[t] ? j : t;
    taken[pick] = 1;
    chosen.push_back(pick);
  }
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

/// Gram matrix A^T A of the rows in double, lower triangle filled, summed over a
/// fixed number of row ranges in a fixed order (deterministic for any threads).
Eigen::MatrixXd gramMatrix(const Eigen::MatrixXd& rows) {
  constexpr int kParts = 4;
  const Eigen::Index n = rows.cols(), p = rows.rows();
  std::vector<Eigen::MatrixXd> parts(kParts, Eigen::MatrixXd::Zero(n, n));
  tbb::parallel_for(0, kParts, [&](int k) {
    const Eigen::Index begin = p * k / kParts, end = p * (k + 1) / kParts;
    if (end > begin)
      parts[k].selfadjointView<Eigen::Lower>().rankUpdate(
          rows.middleRows(begin, end - begin).transpose());
  });
  Eigen::MatrixXd gram = parts[0];
  for (int k = 1; k < kParts; ++k) gram += parts[k];
  return gram;
}

/// Sum of |r V|^2 over the rows r, read on the active directions (V has a row
/// per active direction): in parallel blocks of rows, summed in block order.
double projectedEnergy(const Eigen::MatrixXd& rows, const std::vector<int>& active,
                       const Eigen::Ref<const Eigen::MatrixXd>& vectors) {
  constexpr Eigen::Index kBlock = 256;
  const Eigen::Index blocks = (rows.rows() + kBlock - 1) / kBlock;
  std::vector<double> energy(static_cast<size_t>(blocks), 0.0);
  tbb::parallel_for(Eigen::Index(0), blocks, [&](Eigen::Index b) {
    const Eigen::Index first = b * kBlock, count = std::min(kBlock, rows.rows() - first);
    const Eigen::MatrixXd compact = rows.middleRows(first, count)(Eigen::all, active);
    energy[static_cast<size_t>(b)] = (compact * vectors).squaredNorm();
  });
  double sum = 0;
  for (double e : energy) sum += e;
  return sum;
}

}  // namespace

BasisSample chooseBasisSample(long long total, const GlobalBasisOptions& options) {
  if (options.sampleRows < 1) throw UserError("the global-basis sample needs at least one row");
  std::mt19937_64 rng(options.seed);
  BasisSample s;
  s.rows = sampleRows(total, options.sampleRows, rng);
  s.heldOut = sampleRows(total, std::min<long long>(4096, total), rng);
  return s;
}

GlobalBasis basisFromSample(const Eigen::MatrixXd& sample, const Eigen::MatrixXd& heldOut,
                            const GlobalBasisOptions& options) {
  if (!(options.energy > 0 && options.energy <= 1))
    throw ParameterError("global energy", options.energy, "is outside (0, 1]");
  const Eigen::Index l = sample.cols();
  GlobalBasis result;
  result.basis = Eigen::MatrixXf::Zero(l, 0);
  result.sampledRows = static_cast<int>(sample.rows());
  // The basis lives on the directions the sample sees: a direction no sampled
  // row sees adds a zero row and column to the Gram matrix, nothing else.
  for (Eigen::Index j = 0; j < l; ++j)
    if ((sample.col(j).array() != 0).any()) result.active.push_back(static_cast<int>(j));
  const std::vector<int>& active = result.active;
  result.activeDirections = static_cast<int>(active.size());
  if (active.empty()) return result;
  const Eigen::MatrixXd compact = sample(Eigen::all, active);

  const Eigen::MatrixXd gram = gramMatrix(compact);
  const double energy = compact.squaredNorm();
  const SymmetricEigen eig = symmetricEigenAlone(gram, true);
  const int n = rankForEnergy(eig.values, energy, options.energy);
  result.basis = Eigen::MatrixXf::Zero(l, n);
  for (size_t k = 0; k < active.size(); ++k)
    result.basis.row(active[k]) = eig.vectors.row(k).head(n).cast<float>();
  result.sampleEnergyKept = energy > 0 ? eig.values.head(n).sum() / energy : 1.0;
  const double heldEnergy = heldOut.squaredNorm();
  result.heldOutEnergyKept =
      heldEnergy > 0 ? projectedEnergy(heldOut, active, eig.vectors.leftCols(n)) / heldEnergy : 1.0;
  return result;
}

namespace {

/// The listed rows (sorted, distinct) as a rows x l matrix in double; each run
/// of consecutive rows is one read, so only these rows leave the file.
Eigen::MatrixXd readListedRows(const TransportReader& transport,
                               const std::vector<long long>& list) {
  const int l = transport.rowLength();
  Eigen::MatrixXd rows(static_cast<Eigen::Index>(list.size()), l);
  std::vector<float> run;
  for (size_t i = 0; i < list.size();) {
    size_t j = i + 1;
    while (j < list.size() && list[j] == list[j - 1] + 1) ++j;
    run.resize((j - i) * static_cast<size_t>(l));
    transport.readRows(list[i], static_cast<long long>(j - i), run.data());
    rows.middleRows(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j - i)) =
        Eigen::Map<const RowMatrixF>(run.data(), static_cast<Eigen::Index>(j - i), l)
            .cast<double>();
    i = j;
  }
  return rows;
}

}  // namespace

GlobalBasis computeGlobalBasis(const TransportReader& transport,
                               const GlobalBasisOptions& options) {
  if (!(options.energy > 0 && options.energy <= 1))
    throw ParameterError("global energy", options.energy, "is outside (0, 1]");
  const int l = transport.rowLength();
  if (transport.rows() == 0) {
    GlobalBasis empty;
    empty.basis = Eigen::MatrixXf::Zero(l, 0);
    return empty;
  }
  // Two independent samples: one to build the basis, one to check it. Only
  // they are read, so T itself is read once, by the projection.
  const BasisSample chosen = chooseBasisSample(transport.rows(), options);
  return basisFromSample(readListedRows(transport, chosen.rows),
                         readListedRows(transport, chosen.heldOut), options);
}

/// Rows are zero below their own horizon, and the lattice orders a face by
/// rows of texels, so about half of a floor pixel's row is zero in whole runs
/// (the down face, the lower halves of the side faces). The product skips runs
/// that are zero in every row of a group: rows with the same zero runs are
/// grouped, and each group meets only the basis rows of its non-zero runs.
class BasisProjector::ZeroRunProduct {
 public:
  /// Runs are half faces of the lattice: a side face's lower half is below
  /// an upward normal's horizon (12 runs per channel, at most 64 in a row).
  ZeroRunProduct(const GlobalBasis& globalBasis, int latticeSize, int rowLength) {
    const std::vector<int>& active = globalBasis.active;
    runLength_ = std::max({1, latticeSize / 12, (rowLength + 63) / 64});
    runOf_.resize(active.size());
    for (size_t k = 0; k < active.size(); ++k) runOf_[k] = active[k] / runLength_;
    basis_.resize(static_cast<Eigen::Index>(active.size()), globalBasis.globalBases());
    for (size_t k = 0; k < active.size(); ++k) basis_.row(k) = globalBasis.basis.row(active[k]);
  }

  const RowMatrixF& basis() const { return basis_; }

  /// out = t * basis, t holding the active directions of a block's rows.
  void multiply(const RowMatrixF& t, Eigen::Ref<RowMatrixF> out) const {
    const Eigen::Index count = t.rows(), a = t.cols();
    std::vector<std::uint64_t> runs(count, 0);
    for (Eigen::Index r = 0; r < count; ++r)
      for (Eigen::Index k = 0; k < a; ++k)
        if (t(r, k) != 0) runs[r] |= std::uint64_t{1} << runOf_[k];
    std::vector<int> order(count);
    for (Eigen::Index r = 0; r < count; ++r) order[r] = static_cast<int>(r);
    std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return runs[x] < runs[y]; });
    // Groups of consecutive sorted rows: at least kMinRows (a GEMM that pays
    // for gathering its basis rows), then only rows adding no non-zero run.
    constexpr Eigen::Index kMinRows = 256;
    for (Eigen::Index begin = 0; begin < count;) {
      std::uint64_t used = runs[order[begin]];
      Eigen::Index end = begin + 1;
      while (end < count && (end - begin < kMinRows || (runs[order[end]] & ~used) == 0))
        used |= runs[order[end++]];
      multiplyGroup(t, {order.begin() + begin, order.begin() + end}, used, out);
      begin = end;
    }
  }

 private:
  void multiplyGroup(const RowMatrixF& t, const std::vector<int>& rows, std::uint64_t used,
                     Eigen::Ref<RowMatrixF> out) const {
    std::vector<int> columns;
    for (size_t k = 0; k < runOf_.size(); ++k)
      if (used >> runOf_[k] & 1) columns.push_back(static_cast<int>(k));
    const auto n = static_cast<Eigen::Index>(rows.size());
    if (columns.empty()) {
      for (int r : rows) out.row(r).setZero();
      return;
    }
    RowMatrixF tg(n, static_cast<Eigen::Index>(columns.size()));
    for (Eigen::Index i = 0; i < n; ++i)
      for (size_t c = 0; c < columns.size(); ++c) tg(i, c) = t(rows[i], columns[c]);
    RowMatrixF product;
    if (columns.size() == runOf_.size()) {
      product.noalias() = tg * basis_;
    } else {
      RowMatrixF bg(static_cast<Eigen::Index>(columns.size()), basis_.cols());
      for (size_t c = 0; c < columns.size(); ++c) bg.row(c) = basis_.row(columns[c]);
      product.noalias() = tg * bg;
    }
    for (Eigen::Index i = 0; i < n; ++i) out.row(rows[i]) = product.row(i);
  }

  int runLength_ = 256;
  std::vector<int> runOf_;  ///< run of each active direction
  RowMatrixF basis_;        ///< active directions x N
};

BasisProjector::BasisProjector(const GlobalBasis& basis, int latticeSize, int rowLength)
    : product_(std::make_unique<ZeroRunProduct>(basis, latticeSize, rowLength)),
      active_(basis.active),
      rowLength_(rowLength),
      // What the basis misses, per row, is |t|^2 - |g|^2 in double. The float
      // product g = t V_g is good to about 1e-5 of |t|^2 per row, with signs
      // that average out over rows, so the difference is exact enough while
      // the basis drops much more than that. Near a complete basis the
      // difference would be rounding noise, so there the residual
      // t - V_g V_g^T t is formed itself (a second product as large as the
      // first). Per row the difference may carry rounding noise of either
      // sign; only sums are used.
      formResidual_(1 - basis.heldOutEnergyKept < 1e-4) {
  ACPCA_CHECK(basis.basis.rows() == rowLength, "basis has ", basis.basis.rows(), " rows for ",
              rowLength, " directions");
}

BasisProjector::~BasisProjector() = default;

void BasisProjector::project(const float* block, long long count, GlobalProjection& g,
                             long long first) const {
  const int l = rowLength_, a = static_cast<int>(active_.size());
  const RowMatrixF& basis = product_->basis();
  RowMatrixF t(count, a);  // the rows on the basis's directions
  for (long long r = 0; r < count; ++r)
    for (int k = 0; k < a; ++k) t(r, k) = block[r * l + active_[k]];
  auto coefficients = g.coefficients.middleRows(first, count);
  product_->multiply(t, coefficients);
  RowMatrixF residual;
  if (formResidual_) {
    residual = t;
    residual.noalias() -= coefficients * basis.transpose();
  }
  for (long long r = 0; r < count; ++r) {
    // Over the whole row: directions the sample never saw may still carry energy.
    const double energy =
        Eigen::Map<const Eigen::VectorXf>(block + r * l, l).cast<double>().squaredNorm();
    g.rowEnergy[first + r] = energy;
    g.residualEnergy[first + r] =
        formResidual_ ? energy - t.row(r).cast<double>().squaredNorm() +
                            residual.row(r).cast<double>().squaredNorm()
                      : std::max(0.0, energy - coefficients.row(r).cast<double>().squaredNorm());
  }
}

GlobalProjection BasisProjector::project(const float* rows, long long count) const {
  GlobalProjection g;
  g.coefficients.resize(count, product_->basis().cols());
  g.rowEnergy.resize(count);
  g.residualEnergy.resize(count);
  project(rows, count, g, 0);
  return g;
}

GlobalProjection projectOntoBasis(const TransportReader& transport,
                                  const GlobalBasis& globalBasis) {
  const BasisProjector projector(globalBasis, transport.latticeSize(), transport.rowLength());
  const long long total = transport.rows();
  GlobalProjection g;
  g.coefficients.resize(total, globalBasis.globalBases());
  g.rowEnergy.resize(total);
  g.residualEnergy.resize(total);
  // Blocks of a few thousand rows, so that rows sharing zero runs form groups.
  streamRowBlocks(transport, rowsPerBlock(transport, 48ll << 20),
                  [&](long long first, long long count, const float* block) {
                    projector.project(block, count, g, first);
                  });
  return g;
}

}  // namespace acpca
