#pragma once
// Everything a transport pass over a scene needs, and the header of the file
// it writes. Inside the library only.
#include <memory>

#include "precompute/embree_scene.h"
#include "precompute/image_row_renderer.h"
#include "precompute/indirect_light.h"
#include "precompute/precompute_options.h"
#include "precompute/shadow_rays.h"

namespace acpca {

/// ParameterError on the first option out of its range.
void validatePrecomputeOptions(const PrecomputeOptions& options);

/// The threads an arena of `threads` (0: all cores) runs.
int arenaThreads(int threads);

/// The lattice, the Embree scene, the G-buffer, the shadow rays, the indirect
/// light (with bounces) and the row renderer, built once inside the caller's arena.
struct TransportPass {
  TransportPass(const Scene& scene, const PrecomputeOptions& options);

  int channels() const { return indirect ? indirect->settings().channels : 1; }

  const CubeLattice lattice;
  const EmbreeScene embree;
  const GBuffer gbuffer;
  const TexelDirections dirs;
  const ShadowRays shadows;
  const std::unique_ptr<IndirectLight> indirect;
  const ImageRowRenderer renderer;
};

/// The header of the scene's transport: the image geometry, per occupied
/// pixel (row-major order) its albedo (mean over hit samples), coverage,
/// normal, position and object, and the lamp geometry: each traced sample
/// with its weight in the row, and the surfaces.
TransportHeader transportHeader(const Scene& scene, const PrecomputeOptions& options,
                                const TransportPass& pass);

}  // namespace acpca
