#pragma once
// The physics suites judge transport rows by relighting them: the grey value
// (mean over RGB, albedo applied) of every row under one lighting.
#include <vector>

#include "lighting/environment.h"
#include "lighting/lighting.h"
#include "tests/render_support.h"

namespace acpca::test {

inline std::vector<double> greyRows(const LoadedTransport& t, const Environment& env,
                                    const EnvRotation& rotation = {}) {
  const CubeLattice lattice(t.header.cubemapResolution);
  const LatticeLighting L = computeLighting(env, lattice, rotation);
  std::vector<double> out(t.header.rows());
  for (long long r = 0; r < t.header.rows(); ++r) {
    double sum = 0;
    for (int c = 0; c < 3; ++c) {
      double dot = 0;
      const float* part = t.part(r, c);
      for (int j = 0; j < t.directions; ++j) dot += double(part[j]) * L[3 * j + c];
      sum += t.header.albedo[3 * r + c] * dot;
    }
    out[r] = sum / 3;
  }
  return out;
}

}  // namespace acpca::test
