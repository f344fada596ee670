#include "relight/dense_relight.h"

#include <Eigen/Core>

#include "core/error.h"
#include "transport/row_layout.h"
#include "transport/row_stream.h"

namespace acpca {

std::vector<std::vector<float>> denseRelight(const TransportReader& transport,
                                             const std::vector<LatticeLighting>& lightings) {
  const int l = transport.rowLength();
  const long long rows = transport.rows();
  const int maps = static_cast<int>(lightings.size());
  // L: (row length) x 3M, columns 3m..3m+2 hold map m as the rows meet it.
  Eigen::MatrixXf lighting(l, 3 * maps);
  for (int m = 0; m < maps; ++m)
    lighting.middleCols(3 * m, 3) =
        lightingOnRows(lightings[m], transport.latticeSize(), transport.header().channels);
  std::vector<std::vector<float>> result(maps, std::vector<float>(3 * rows));
  if (rows == 0 || maps == 0) return result;

  const auto& albedo = transport.header().albedo;
  streamRowBlocks(
      transport, rowsPerBlock(transport), [&](long long first, long long count, const float* rows) {
        using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
        const Eigen::MatrixXf product = Eigen::Map<const RowMatrix>(rows, count, l) * lighting;
        for (long long r = 0; r < count; ++r)
          for (int m = 0; m < maps; ++m)
            for (int c = 0; c < 3; ++c)
              result[m][3 * (first + r) + c] = albedo[3 * (first + r) + c] * product(r, 3 * m + c);
      });
  return result;
}

}  // namespace acpca
