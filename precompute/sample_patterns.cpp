#include "precompute/sample_patterns.h"

#include <cmath>

namespace acpca {

TexelDirections makeTexelDirections(const CubeLattice& lattice, int raysPerTexel) {
  TexelDirections t;
  t.raysPerTexel = raysPerTexel;
  const size_t n = static_cast<size_t>(lattice.size()) * raysPerTexel;
  t.x.resize(n), t.y.resize(n), t.z.resize(n), t.weight.resize(n);
  const double step = 2.0 / lattice.resolution();
  for (int j = 0; j < lattice.size(); ++j) {
    const TexelCoord c = lattice.texelCoord(j);
    double total = 0;
    for (int k = 0; k < raysPerTexel; ++k) {
      Vec3 d;
      double density = 1;
      if (raysPerTexel == 1) {
        d = lattice.direction(j);
      } else {
        // R2 points in the texel, shifted per texel (Cranley-Patterson) so that
        // neighbouring texels do not share a pattern.
        const double shiftS = std::fmod(j * 0.6180339887498949, 1.0);
        const double shiftT = std::fmod(j * 0.4142135623730950, 1.0);
        const double u = std::fmod(shiftS + k * 0.7548776662466927, 1.0);
        const double v = std::fmod(shiftT + k * 0.5698402909980532, 1.0);
        const double sc = -1 + (c.col + u) * step, tc = -1 + (c.row + v) * step;
        const Vec3 p = CubeLattice::faceDirection(c.face, sc, tc);
        density = 1 / std::pow(p.squaredNorm(), 1.5);  // d(omega)/d(area) on the face
        d = p.normalized();
      }
      const size_t q = static_cast<size_t>(j) * raysPerTexel + k;
      t.x[q] = float(d.x()), t.y[q] = float(d.y()), t.z[q] = float(d.z());
      t.weight[q] = float(density);
      total += density;
    }
    for (int k = 0; k < raysPerTexel; ++k)
      t.weight[static_cast<size_t>(j) * raysPerTexel + k] /= float(total);
  }
  return t;
}

bool samplesAgree(const GBuffer& g, int x, int y) {
  const PixelSample& centre = g.at(x, y, 0);
  if (centre.material < 0) return false;
  for (int s = 1; s < g.samplesPerPixel; ++s) {
    const PixelSample& ps = g.at(x, y, s);
    if (ps.material != centre.material) return false;
    if (ps.normal.dot(centre.normal) < 0.99f) return false;
    // An anisotropic lobe turns with the tangent (either sign is the same lobe).
    if (g.anisotropic[centre.material] && std::abs(ps.tangent.dot(centre.tangent)) < 0.99f)
      return false;
    const Eigen::Vector3f step = ps.origin - centre.origin;
    if (std::abs(step.dot(centre.geometricNormal)) > 0.1f * step.norm()) return false;
  }
  return true;
}

void sampleWeights(const GBuffer& g, int x, int y, Antialiasing mode, std::vector<float>& weights) {
  weights.assign(g.samplesPerPixel, 0.0f);
  if (mode == Antialiasing::Adaptive && samplesAgree(g, x, y)) {
    weights[0] = 1;
    return;
  }
  float total = 0;
  int hits = 0;
  for (int s = 0; s < g.samplesPerPixel; ++s) {
    const PixelSample& ps = g.at(x, y, s);
    if (ps.material < 0) continue;
    weights[s] = luminance(ps.albedo);
    total += weights[s];
    ++hits;
  }
  for (int s = 0; s < g.samplesPerPixel; ++s) {
    if (g.at(x, y, s).material < 0) continue;
    weights[s] = total > 0 ? weights[s] / total : 1.0f / hits;
  }
}

}  // namespace acpca
