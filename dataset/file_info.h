#pragma once
// What a transport or model file holds, as the JSON `info --json` prints and
// the Python module's `info` returns, and in words: one description for both,
// read from the file's attributes and shapes alone (never its arrays), so a
// 1024x1024 model is described in milliseconds.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "model/model_summary.h"
#include "transport/file_summary.h"

namespace acpca {

/// "shared" (one row per pixel for R, G and B) or "rgb" (three side by side).
const char* rowLayoutName(int channels);
/// {"rank": clusters} of a model's cluster ranks (JSON keys are strings).
nlohmann::json rankHistogramJson(const std::vector<std::int32_t>& ranks);
nlohmann::json describeModel(const ModelSummary& model);
nlohmann::json describeTransport(const TransportSummary& transport);
std::string describeInWords(const ModelSummary& model, const std::string& path);
std::string describeInWords(const TransportSummary& transport, const std::string& path);

/// A file's description both ways.
struct FileDescription {
  nlohmann::json json;
  std::string words;  ///< a few lines: what `info` prints
};
/// A frame's header (imageio/frame_metadata.h): its lighting, source, colour
/// space and camera, as `info FRAME` prints them.
FileDescription describeFrame(const std::string& path);
/// Whichever the file is: a frame (.exr or .png), a model or a transport
/// (UserError when none).
FileDescription describeFile(const std::string& path);

}  // namespace acpca
