#include "cluster/dimensionality.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

#include "cluster/symmetric_eigen.h"

namespace acpca {

PatchRows readSquarePatch(const TransportReader& transport, int cx, int cy, int side) {
  const TransportHeader& h = transport.header();
  const int width = h.camera.size.width, height = h.camera.size.height, l = transport.rowLength();
  const int x0 = std::max(0, cx - side / 2), x1 = std::min(width, cx - side / 2 + side);
  const int y0 = std::max(0, cy - side / 2), y1 = std::min(height, cy - side / 2 + side);
  PatchRows patch;
  for (int y = y0; y < y1; ++y) {
    // Rows are sorted by pixel index, so one image row of the patch is one run of rows.
    const auto first = std::lower_bound(h.pixels.begin(), h.pixels.end(), y * width + x0);
    const auto last = std::lower_bound(first, h.pixels.end(), y * width + x1);
    const long long count = last - first;
    if (count == 0) continue;
    patch.values.resize(static_cast<size_t>(patch.rows + count) * l);
    transport.readRows(first - h.pixels.begin(), count, patch.values.data() + patch.rows * l);
    patch.rows += count;
  }
  return patch;
}

int patchDimensionality(const PatchRows& patch, int latticeSize, double energy) {
  if (patch.rows == 0) return 0;
  const Eigen::Map<const Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> t(
      patch.values.data(), patch.rows, latticeSize);
  const Eigen::MatrixXd rows = t.cast<double>();
  Eigen::MatrixXd gram;
  if (patch.rows <= latticeSize)
    gram = rows * rows.transpose();
  else
    gram = rows.transpose() * rows;
  const double total = gram.trace();
  if (!(total > 0)) return 0;
  return rankForEnergy(symmetricEigen(gram, false).values, total, energy);
}

PowerLaw fitPowerLaw(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (size_t i = 0; i < x.size() && i < y.size(); ++i) {
    if (!(x[i] > 0 && y[i] > 0)) continue;
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
    ++n;
  }
  PowerLaw fit;
  fit.points = n;
  const double denominator = n * sxx - sx * sx;
  if (n < 2 || !(denominator > 1e-12 * std::max(1.0, n * sxx))) {
    fit.slope = fit.scale = NAN;
    return fit;
  }
  fit.slope = (n * sxy - sx * sy) / denominator;
  fit.scale = std::exp((sy - fit.slope * sx) / n);
  return fit;
}

double muFromSlope(double slope, int r) {
  return std::pow(double(r), -slope);
}

}  // namespace acpca
