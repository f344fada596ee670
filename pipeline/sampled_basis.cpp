#include "pipeline/sampled_basis.h"

#include <cstring>
#include <vector>

#include "core/error.h"
#include "core/ranks.h"

namespace acpca {

namespace {

/// Values appended to / read from a byte message in order.
struct Bytes {
  std::vector<char> data;
  size_t at = 0;
  template <typename T>
  void put(const T* values, size_t count) {
    const auto* p = reinterpret_cast<const char*>(values);
    data.insert(data.end(), p, p + count * sizeof(T));
  }
  template <typename T>
  void get(T* values, size_t count) {
    ACPCA_CHECK(at + count * sizeof(T) <= data.size(), "message shorter than its contents");
    std::memcpy(values, data.data() + at, count * sizeof(T));
    at += count * sizeof(T);
  }
};

}  // namespace

GlobalBasis fitBasis(const RowSource& source, const GlobalBasisOptions& options,
                     std::pair<long long, long long>& rays) {
  const BasisSample sample = chooseBasisSample(source.header().rows(), options);
  const int l = source.rowLength();
  const auto renderRows = [&](const std::vector<long long>& rows) {
    std::vector<float> values(rows.size() * static_cast<size_t>(l));
    const auto [shadow, paths] = source.render(rows, values.data());
    rays.first += shadow, rays.second += paths;
    return Eigen::Map<const RowMatrixF>(values.data(), static_cast<Eigen::Index>(rows.size()), l)
        .cast<double>()
        .eval();
  };
  const Eigen::MatrixXd held = renderRows(sample.heldOut);
  const Eigen::MatrixXd rows = renderRows(sample.rows);
  return basisFromSample(rows, held, options);
}

void shareBasis(GlobalBasis& basis) {
  Bytes b;
  if (ranks::rank() == 0) {
    const long long sizes[4] = {basis.basis.rows(), basis.basis.cols(),
                                static_cast<long long>(basis.active.size()),
                                (static_cast<long long>(basis.activeDirections) << 32) |
                                    static_cast<unsigned>(basis.sampledRows)};
    const double kept[2] = {basis.sampleEnergyKept, basis.heldOutEnergyKept};
    b.put(sizes, 4), b.put(kept, 2), b.put(basis.active.data(), basis.active.size());
    b.put(basis.basis.data(), static_cast<size_t>(basis.basis.size()));
  }
  ranks::broadcast(b.data);
  if (ranks::rank() == 0) return;
  long long sizes[4];
  double kept[2];
  b.get(sizes, 4), b.get(kept, 2);
  basis.active.resize(static_cast<size_t>(sizes[2]));
  b.get(basis.active.data(), basis.active.size());
  basis.basis.resize(sizes[0], sizes[1]);
  b.get(basis.basis.data(), static_cast<size_t>(basis.basis.size()));
  basis.activeDirections = static_cast<int>(sizes[3] >> 32);
  basis.sampledRows = static_cast<int>(sizes[3] & 0xffffffff);
  basis.sampleEnergyKept = kept[0], basis.heldOutEnergyKept = kept[1];
}

}  // namespace acpca
