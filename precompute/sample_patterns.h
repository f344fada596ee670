#pragma once
// Where the precompute samples (internal to the renderer): the shadow-ray
// directions within each lattice texel, and which camera samples of a pixel
// are traced, with what weight in its row.
#include <vector>

#include "precompute/embree_scene.h"
#include "precompute/precompute_options.h"
#include "transport/cube_lattice.h"

namespace acpca {

/// The shadow-ray directions of every texel: its centre when one ray per texel,
/// else `raysPerTexel` stratified points weighted by their solid-angle density
/// so that they average over the texel's area.
struct TexelDirections {
  int raysPerTexel = 1;
  std::vector<float> x, y, z, weight;  // texel j, ray k at j * raysPerTexel + k
};

TexelDirections makeTexelDirections(const CubeLattice& lattice, int raysPerTexel);

/// Whether a pixel's covered samples see one smooth piece of surface: all
/// covered, one object, normals within ~8 degrees and the points on one tangent
/// plane (no depth step). Only then can its centre sample stand for the rest.
bool samplesAgree(const GBuffer& g, int x, int y);

/// The weights of a pixel's samples in its row (0: not traced). Every covered
/// sample is traced with its share of the summed luminance of their albedos
/// (uniform when all are black), so that mean albedo x row is exact when the
/// albedos share a hue (docs/scenes.md, "Anti-aliasing"); with Adaptive, a
/// pixel whose samples agree traces its centre alone, with weight 1.
void sampleWeights(const GBuffer& g, int x, int y, Antialiasing mode, std::vector<float>& weights);

}  // namespace acpca
