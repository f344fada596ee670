#pragma once
// What a frame's file says of itself (docs/formats.md, "Frame metadata"): the
// colour space of its values, the camera that saw it and the lighting that lit
// it, as EXR attributes and PNG chunks. Nothing in it changes from run to run.
#include <Eigen/Core>
#include <array>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace acpca {

/// Rec.709 primaries and D65 white (x, y of red, green, blue, white), as
/// OpenEXR's `chromaticities` holds them.
inline constexpr std::array<float, 8> kRec709Chromaticities{0.64f, 0.33f, 0.30f,   0.60f,
                                                            0.15f, 0.06f, 0.3127f, 0.3290f};
/// A frame's own fields are EXR attributes of this prefix.
inline constexpr const char* kFrameFieldPrefix = "acpca:";
/// The keyword of a PNG's iTXt chunk that holds them.
inline constexpr const char* kPngFieldKeyword = "acpca";

struct FrameMetadata {
  /// Scene-referred linear Rec.709 radiance, or values that are no colour
  /// (labels: normals, depth, object ids).
  enum class Values { Radiance, Data };
  Values values = Values::Radiance;
  /// OpenEXR's worldToCamera and worldToNDC: points are row vectors (p M),
  /// the matrix row by row.
  std::optional<std::array<float, 16>> worldToCamera, worldToNdc;
  /// The frame's fields (lighting, source, tool): EXR attributes named
  /// kFrameFieldPrefix + key (text a string, a number a double, lists of
  /// numbers at any depth a float vector of them in order, null nothing,
  /// anything else its JSON text); in a PNG, one iTXt chunk of JSON (frameMetadataJson).
  nlohmann::json fields = nlohmann::json::object();

  /// Sets worldToCamera and worldToNdc from the camera's matrices (row vectors).
  void setCamera(const Eigen::Matrix4d& toCamera, const Eigen::Matrix4d& toNdc);
  /// OpenEXR's colorInteropID: "lin_rec709_scene" or "data".
  const char* colorInteropId() const {
    return values == Values::Radiance ? "lin_rec709_scene" : "data";
  }
};

/// The fields with the camera ("worldToCamera", "worldToNDC": 16 numbers row
/// by row) and "colorInteropID": what a PNG's iTXt chunk holds.
nlohmann::json frameMetadataJson(const FrameMetadata& metadata);

/// What a frame file (EXR or PNG) says of itself, as frameMetadataJson gives
/// it, with "chromaticities" (8 numbers) of an EXR and "cICP" (4 numbers) and
/// "sRGB" (its rendering intent) of a PNG; an EXR's lists of numbers come
/// back flat. Empty for a file that says nothing; UserError naming `path`
/// for one that cannot be read.
nlohmann::json readFrameMetadata(const std::string& path);

/// A PNG chunk: its type and data (length and CRC are the encoder's).
struct PngChunk {
  std::array<char, 4> type;
  std::vector<unsigned char> data;
};
/// The chunks of a frame encoded as 8- or 16-bit sRGB: cICP (BT.709
/// primaries, the sRGB transfer function, full range), sRGB, and gAMA and
/// cHRM for readers that know neither, then an iTXt of frameMetadataJson.
std::vector<PngChunk> srgbFrameChunks(const FrameMetadata& metadata);

}  // namespace acpca
