#pragma once
// Whether the lattice resolves a scene's specular lobes, and the rays per
// texel that would (docs/scenes.md, "Materials").
#include <string>
#include <vector>

#include "precompute/precompute_options.h"
#include "precompute/scene.h"

namespace acpca {

/// Occlusion rays per texel that resolve a Phong lobe of this exponent on a
/// 6 x R x R lattice (1 when texel centres already do).
int texelRaysForLobe(double exponent, int cubemapResolution);
/// Half the width at half maximum (radians) of a material's specular lobe over
/// light directions: Phong's, GGX's mirrored distribution or Ashikhmin-
/// Shirley's lobe (across the narrower axis when anisotropic); 0 without one.
double lobeHalfWidth(const Material& m);
/// One line per Phong or GGX material whose lobe the lattice under-samples: fewer than
/// two direction samples (2/R radians apart at a face's centre, over
/// sqrt(texel rays)) across its half-maximum width, so highlights alias. Each
/// names the --texel-rays that resolves the lobe.
std::vector<std::string> samplingWarnings(const Scene& scene, const PrecomputeOptions& options);

}  // namespace acpca
