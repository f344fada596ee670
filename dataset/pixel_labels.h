#pragma once
// Per-pixel labels (AOVs) of a view, from what transport and model files keep
// for each pixel, and each frame's shading. What every label holds, and at
// silhouette pixels: docs/datasets.md.
#include <cstdint>
#include <string>
#include <vector>

#include "core/enum_names.h"
#include "transport/file_summary.h"
#include "transport/transport_file.h"

namespace acpca {

enum class Aov { Albedo, Normal, Tangent, Depth, Position, Mask, Object, Shading };
inline constexpr EnumNames<Aov, 8> kAovNames{"AOV",
                                             {{{Aov::Albedo, "albedo"},
                                               {Aov::Normal, "normal"},
                                               {Aov::Tangent, "tangent"},
                                               {Aov::Depth, "depth"},
                                               {Aov::Position, "position"},
                                               {Aov::Mask, "mask"},
                                               {Aov::Object, "object"},
                                               {Aov::Shading, "shading"}}}};

/// A comma-separated list of AOV names and presets ("all"; "intrinsic":
/// albedo, shading, mask; "geometry": normal, tangent, depth, position, mask,
/// object),
/// each AOV once, in kAovNames' order. Empty text: none. ParameterError
/// ("AOV") naming what is not an AOV.
std::vector<Aov> parseAovList(const std::string& text);

/// The AOVs a file's per-pixel data can give: all but what older files lack
/// (normals before model version 5, positions before transport version 2 and
/// model version 4, objects before transport 3 and model 5, tangents before
/// transport 6 and model 8).
std::vector<Aov> availableAovs(const TransportHeader& header);
/// The same for a header read without its arrays (what the datasets hold).
std::vector<Aov> availableAovs(const TransportHeader& attributes, const PixelDatasets& datasets);

/// Throws UserError naming `path`, the AOV, and what to run again, for an
/// AOV the file cannot give. `model`: path is a model file.
void requireAovs(const TransportHeader& header, const std::vector<Aov>& aovs,
                 const std::string& path, bool model);

/// One per-view label: its AOV, its EXR channel names, and its values
/// (width x height x channels, row 0 at the top).
struct LabelLayer {
  Aov aov;
  std::vector<std::string> channels;
  std::vector<float> values;
};

/// The per-view labels among `aovs`, in their order (shading, which changes
/// with the lighting, is left out: see frameShading).
std::vector<LabelLayer> viewLabels(const TransportHeader& header, const std::vector<Aov>& aovs);

enum class LabelFormat { Exr, Npy, Both };
inline constexpr EnumNames<LabelFormat, 3> kLabelFormatNames{
    "label format",
    {{{LabelFormat::Exr, "exr"}, {LabelFormat::Npy, "npy"}, {LabelFormat::Both, "both"}}}};

/// Writes a view's labels: STEM.exr (float, every layer's channels, the
/// object names in the header attribute "objects") and/or STEM_AOV.npy per
/// layer (float32 H x W [x C]; object: int32 H x W), and with the mask
/// STEM_mask.png (8-bit, round(255 A): what image loaders read as a mask).
/// Every file appears under its name only once all are written. Returns the
/// paths written.
std::vector<std::string> writeViewLabels(const std::vector<LabelLayer>& layers,
                                         const TransportHeader& header, const std::string& stem,
                                         LabelFormat format);

/// A frame's shading, relit / albedo (3 floats per pixel): at each covered
/// pixel, (frame - background) / (coverage x albedo), per channel, where the
/// frame and its background part hold `channels` floats per pixel (3, or 4
/// with alpha). 0 where the albedo is 0, and at background pixels; negative
/// values are raised to 0 unless `keepNegative` (docs/design.md, section 6).
void frameShading(const TransportHeader& header, const float* frame, const float* background,
                  int channels, float* shading, bool keepNegative = false);

}  // namespace acpca
