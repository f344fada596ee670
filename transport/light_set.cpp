#include "transport/light_set.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"

namespace acpca {

namespace {

constexpr double kDegree = std::numbers::pi / 180;

/// Index of the light nearest to d (largest cosine, ties to the lower index)
/// and its cosine; directions as coordinate arrays so the loop vectorises.
struct Nearest {
  int light = -1;
  double cosine = -2;
};

/// The lights as coordinate arrays, searched for the nearest to a direction.
class NearestLight {
 public:
  explicit NearestLight(const std::vector<Vec3>& directions) {
    for (const Vec3& d : directions) {
      x_.push_back(d.x());
      y_.push_back(d.y());
      z_.push_back(d.z());
    }
  }
  /// The nearest of all lights.
  Nearest operator()(const Vec3& d) const {
    Nearest best;
    for (size_t k = 0; k < x_.size(); ++k) consider(static_cast<int>(k), d, best);
    return best;
  }
  /// The nearest of `candidates` (increasing indices: ties go as above).
  Nearest among(const std::vector<int>& candidates, const Vec3& d) const {
    Nearest best;
    for (int k : candidates) consider(k, d, best);
    return best;
  }
  /// Lights within `cosine` of d (dot product at least it), in index order.
  void within(const Vec3& d, double cosine, std::vector<int>& out) const {
    out.clear();
    for (size_t k = 0; k < x_.size(); ++k)
      if (x_[k] * d.x() + y_[k] * d.y() + z_[k] * d.z() >= cosine)
        out.push_back(static_cast<int>(k));
  }

 private:
  void consider(int k, const Vec3& d, Nearest& best) const {
    const double c = x_[k] * d.x() + y_[k] * d.y() + z_[k] * d.z();
    if (c > best.cosine) best = {k, c};
  }
  std::vector<double> x_, y_, z_;
};

/// Angle from a texel's centre direction to its farthest corner.
double texelRadius(const CubeLattice& lattice, int texel) {
  const TexelCoord t = lattice.texelCoord(texel);
  const double step = 2.0 / lattice.resolution();
  const double s0 = -1 + t.col * step, t0 = -1 + t.row * step;
  double radius = 0;
  for (double s : {s0, s0 + step})
    for (double u : {t0, t0 + step}) {
      const Vec3 corner = CubeLattice::faceDirection(t.face, s, u).normalized();
      radius =
          std::max(radius, std::acos(std::clamp(corner.dot(lattice.direction(texel)), -1.0, 1.0)));
    }
  return radius;
}

}  // namespace

double LightSet::uncoveredSolidAngle() const {
  double covered = 0;
  for (double w : solidAngles) covered += w;
  return std::max(0.0, 4 * std::numbers::pi - covered);
}

std::string LightSet::describe() const {
  const std::string cellText =
      cells == CellSource::Given
          ? "cells given in the lights file"
          : concat("spherical Voronoi cells capped at ", capDegrees, " degrees");
  return concat(size(), size() == 1 ? " light, " : " lights, ", cellText);
}

void LightSet::validate(const std::string& context) const {
  const size_t n = directions.size();
  if (n == 0) throw UserError(concat(context, ": the light set holds no lights"));
  if (solidAngles.size() != n || irradiance.size() != n)
    throw UserError(concat(context,
                           ": the light set's directions, solid angles and irradiances "
                           "differ in count"));
  double total = 0;
  for (size_t k = 0; k < n; ++k) {
    if (!directions[k].allFinite() || std::abs(directions[k].norm() - 1) > 1e-6)
      throw UserError(concat(context, ": light ", k, "'s direction is not a unit vector"));
    if (!(solidAngles[k] >= 0 && solidAngles[k] <= 4 * std::numbers::pi))
      throw UserError(concat(context, ": light ", k, "'s cell solid angle ", solidAngles[k],
                             " is not in [0, 4 pi]"));
    if (!irradiance[k].allFinite() || !(irradiance[k].array() > 0).all())
      throw UserError(concat(context, ": light ", k, "'s irradiance is not positive"));
    total += solidAngles[k];
  }
  if (total > 4 * std::numbers::pi * (1 + 1e-6))
    throw UserError(concat(context, ": the cells' solid angles sum to ", total,
                           " sr, more than the sphere's 4 pi"));
  if (cells == CellSource::CappedVoronoi && !(capDegrees > 0 && capDegrees <= 180))
    throw UserError(concat(context, ": cell cap ", capDegrees, " degrees is not in (0, 180]"));
}

std::pair<int, int> findSameDirection(const std::vector<Vec3>& directions) {
  // Sorted by x, two directions within kSameDirection differ by at most that in x.
  std::vector<int> order(directions.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return directions[a].x() < directions[b].x(); });
  std::pair<int, int> first{-1, -1};
  for (size_t i = 0; i < order.size(); ++i)
    for (size_t j = i + 1; j < order.size(); ++j) {
      const Vec3 &a = directions[order[i]], &b = directions[order[j]];
      if (b.x() - a.x() > kSameDirection) break;
      if ((a - b).norm() > kSameDirection) continue;
      const std::pair<int, int> pair{std::min(order[i], order[j]), std::max(order[i], order[j])};
      if (first.second < 0 || pair.second < first.second ||
          (pair.second == first.second && pair.first < first.first))
        first = pair;
    }
  return first;
}

double defaultCellCapDegrees(const std::vector<Vec3>& directions) {
  if (directions.size() < 2) return 180;
  double worst = 1;  // the smallest nearest-neighbour cosine
  for (size_t k = 0; k < directions.size(); ++k) {
    double nearest = -1;
    for (size_t m = 0; m < directions.size(); ++m)
      if (m != k) nearest = std::max(nearest, directions[k].dot(directions[m]));
    worst = std::min(worst, nearest);
  }
  return std::acos(std::clamp(worst, -1.0, 1.0)) / kDegree;
}

int cellLatticeResolution(int lights) {
  // 90 / R degrees a texel <= (114.6 / sqrt(n)) / 4: R >= pi sqrt(n).
  const int r = static_cast<int>(std::ceil(std::numbers::pi * std::sqrt(std::max(1, lights))));
  return std::clamp((r + kCellLatticeStep - 1) / kCellLatticeStep * kCellLatticeStep,
                    kMinCellLattice, kMaxCellLattice);
}

LightCells::LightCells(const std::vector<Vec3>& directions, double capDegrees,
                       int latticeResolution, int sub)
    : lattice_(latticeResolution > 0 ? latticeResolution
                                     : cellLatticeResolution(static_cast<int>(directions.size()))),
      cells_(static_cast<int>(directions.size())) {
  if (sub <= 0)
    sub =
        std::max(1, (kCellSamplesPerFaceSide + lattice_.resolution() - 1) / lattice_.resolution());
  ACPCA_CHECK(cells_ >= 1, "cells ", cells_);
  const double capCosine =
      capDegrees <= 0 || capDegrees >= 180 ? -2 : std::cos(capDegrees * kDegree);
  const NearestLight nearest(directions);
  const int texels = lattice_.size(), r = lattice_.resolution();
  std::vector<std::vector<Share>> perTexel(texels);
  tbb::parallel_for(0, texels, [&](int j) {
    // Only lights within the nearest one's angle plus the texel's diameter
    // can be nearest to a point of the texel: search those.
    const Vec3& centre = lattice_.direction(j);
    const double reach =
        std::acos(std::clamp(nearest(centre).cosine, -1.0, 1.0)) + 2 * texelRadius(lattice_, j);
    std::vector<int> candidates;
    nearest.within(centre, reach >= std::numbers::pi ? -2 : std::cos(reach) - 1e-12, candidates);
    const TexelCoord t = lattice_.texelCoord(j);
    const double step = 2.0 / r, part = step / sub;
    const double s0 = -1 + t.col * step, t0 = -1 + t.row * step;
    std::vector<Share>& shares = perTexel[j];
    for (int a = 0; a < sub; ++a)
      for (int b = 0; b < sub; ++b) {
        const double s = s0 + b * part, u = t0 + a * part;
        const Vec3 d = CubeLattice::faceDirection(t.face, s + 0.5 * part, u + 0.5 * part);
        const Nearest n = nearest.among(candidates, d.normalized());
        if (n.cosine < capCosine) continue;
        const double w =
            CubeLattice::rectangleSolidAngle(s, u, s + part, u + part) / lattice_.solidAngle(j);
        auto it = std::find_if(shares.begin(), shares.end(),
                               [&](const Share& x) { return x.cell == n.light; });
        if (it == shares.end())
          shares.push_back({n.light, w});
        else
          it->fraction += w;
      }
  });
  start_.assign(texels + 1, 0);
  for (int j = 0; j < texels; ++j) start_[j + 1] = start_[j] + static_cast<int>(perTexel[j].size());
  shares_.reserve(start_.back());
  for (const auto& shares : perTexel) shares_.insert(shares_.end(), shares.begin(), shares.end());
}

std::vector<double> LightCells::solidAngles() const {
  std::vector<double> out(cells_, 0.0);
  gather(lattice_.solidAngles(), 1, out);
  return out;
}

void LightCells::gather(const std::vector<double>& texelValues, int stride,
                        std::vector<double>& out) const {
  ACPCA_CHECK(texelValues.size() == static_cast<size_t>(lattice_.size()) * stride &&
                  out.size() == static_cast<size_t>(cells_) * stride,
              "values ", texelValues.size(), ", out ", out.size(), ", stride ", stride);
  for (int j = 0; j < lattice_.size(); ++j)
    for (const Share* s = begin(j); s != end(j); ++s)
      for (int c = 0; c < stride; ++c)
        out[static_cast<size_t>(s->cell) * stride + c] += s->fraction * texelValues[j * stride + c];
}

}  // namespace acpca
