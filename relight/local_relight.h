#pragma once
// Relighting under local lights (docs/lighting.md, "Local lights"): each
// pixel sees the lights from its own world position as a sparse lattice
// lighting (lighting/local_light.h), which meets the pixel's transport row: T
// itself (the dense ground truth) or the model's reconstruction of it,
// u_p . (W_c^T V_g^T e_j) per texel j the pixel's lights touch, formed once per
// cluster and texel. Both are linear in the lights, so a frame under an
// environment and lights is the sum of the two relights.
#include <string>
#include <vector>

#include "lighting/local_light.h"
#include "relight/local_columns.h"
#include "relight/model_relighter.h"
#include "transport/transport_file.h"

namespace acpca {

/// Refuses lights that cannot be relit from this file: a file without pixel
/// positions (UserError naming `path` and what to run again; `model` picks the
/// advice), a light that encloses or touches a pixel's position (ParameterError
/// "light" with the count and the first pixel: the transport there would need
/// the light inside the surface).
void requireLocalLightsApply(const TransportHeader& header, const std::string& path, bool model,
                             const std::vector<LocalLight>& lights);

/// Per occupied row RGB (rows x 3, albedo applied) under the lights alone,
/// from T (call requireLocalLightsApply first, once): one pass over the file,
/// parallel over blocks of rows; the same values for any thread count.
std::vector<float> denseLocalRelight(const TransportReader& transport,
                                     const std::vector<LocalLight>& lights);

/// How far apart, in texels of direction, the pixels of one cluster may see
/// a light and still share its direction taps (found once, at their mean
/// position); each pixel keeps the irradiance at its own position.
inline constexpr double kAnchorSpreadTexels = 0.5;

/// The same from a model at the relighter's rank limit (call
/// requireLocalLightsApply first). Per cluster and light its pixels are
/// grouped in cubes that the light sees within `anchorSpread` texels (0: a
/// group per pixel, the model's reconstruction of T lit exactly as T is);
/// each group's direction taps meet the columns of the cluster's
/// reconstruction, W_c^T V_g^T e_j, formed once per cluster and texel; each
/// pixel adds, per light, the irradiance at its position times its
/// coefficients against its group's transport: rank + 1 multiply-adds per
/// light and row. `kept` (made for this relighter's model) keeps the columns
/// for the next frames, which then form only the columns of texels new to
/// a cluster; without it they are formed afresh. Either way the same image.
std::vector<float> modelLocalRelight(const ModelRelighter& relighter,
                                     const std::vector<LocalLight>& lights,
                                     double anchorSpread = kAnchorSpreadTexels,
                                     LocalLightColumns* kept = nullptr);

}  // namespace acpca
