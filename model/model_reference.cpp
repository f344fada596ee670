#include "model/model_reference.h"

#include "core/error.h"
#include "transport/row_layout.h"

namespace acpca {

std::vector<std::vector<float>> relightModelReference(
    const Model& m, const std::vector<std::vector<double>>& lightings) {
  const int n = m.globalBases();
  std::vector<std::vector<float>> out;
  const Eigen::MatrixXd basis = m.globalBasis.cast<double>();
  for (const auto& lighting : lightings) {
    // L_g = V_g^T L (N x 3), in double.
    const Eigen::MatrixXd lg =
        basis.transpose() *
        lightingOnRows<double>(lighting, m.geometry.latticeSize(), m.geometry.channels);
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
