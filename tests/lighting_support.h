#pragma once
// The lightings the relight and eval suites judge the small plant by.
#include <vector>

#include "lighting/environment.h"
#include "lighting/lighting.h"

namespace acpca::test {

/// sky, a 4-degree sun and constant:1 on a 6 x R^2 lattice.
inline std::vector<LatticeLighting> plantLightings(int cubemap = 8) {
  const CubeLattice lattice(cubemap);
  std::vector<LatticeLighting> out;
  for (const char* env : {"sky", "sun:50,30,4,1000", "constant:1"})
    out.push_back(computeLighting(*loadEnvironment(env), lattice, {}));
  return out;
}

}  // namespace acpca::test
