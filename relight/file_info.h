#pragma once
// What a transport or model file holds, as the JSON `info --json` prints and
// the Python module's `info` returns: one description for both.
#include <nlohmann/json.hpp>
#include <string>

#include "cluster/model.h"
#include "transport/transport_file.h"

namespace acpca {

/// "shared" (one row per pixel for R, G and B) or "rgb" (three side by side).
const char* rowLayoutName(int channels);
/// {"rank": clusters} of a model (JSON keys are strings).
nlohmann::json rankHistogramJson(const Model& model);
nlohmann::json describeModel(const Model& model, const std::string& path);
nlohmann::json describeTransport(const TransportReader& transport);
/// Either of the above, whichever the file is (UserError when neither).
nlohmann::json describeFile(const std::string& path);
/// The same for a reader, as a few lines of text (what `info` prints).
std::string describeInWords(const Model& model, const std::string& path);
std::string describeInWords(const TransportReader& transport, const std::string& path);

}  // namespace acpca
