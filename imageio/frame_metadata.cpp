#include "imageio/frame_metadata.h"

#include <OpenEXR/openexr.h>

#include <cmath>
#include <cstring>
#include <fstream>

#include "core/error.h"

namespace acpca {

namespace {

void appendBigEndian(std::vector<unsigned char>& out, std::uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8)
    out.push_back(static_cast<unsigned char>(v >> shift));
}

nlohmann::json matrixJson(const std::array<float, 16>& m) {
  return nlohmann::json(std::vector<float>(m.begin(), m.end()));
}

std::uint32_t bigEndian(const unsigned char* b) {
  return (std::uint32_t(b[0]) << 24) | (std::uint32_t(b[1]) << 16) | (std::uint32_t(b[2]) << 8) |
         b[3];
}

/// A field's value read back from its attribute text: JSON lists and objects
/// were written as their text.
nlohmann::json fieldOfText(const std::string& text) {
  if (!text.empty() && (text.front() == '[' || text.front() == '{')) {
    nlohmann::json parsed = nlohmann::json::parse(text, nullptr, false);
    if (!parsed.is_discarded()) return parsed;
  }
  return text;
}

nlohmann::json readExrMetadata(const std::string& path) {
  exr_context_t context = nullptr;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = [](exr_const_context_t, exr_result_t, const char*) {};
  if (exr_start_read(&context, path.c_str(), &init) != EXR_ERR_SUCCESS) {
    exr_finish(&context);
    throw UserError(concat(path, ": not an OpenEXR file that can be read"));
  }
  nlohmann::json json = nlohmann::json::object();
  int32_t count = 0;
  exr_get_attribute_count(context, 0, &count);
  const std::string prefix = kFrameFieldPrefix;
  for (int32_t k = 0; k < count; ++k) {
    const exr_attribute_t* a = nullptr;
    if (exr_get_attribute_by_index(context, 0, EXR_ATTR_LIST_FILE_ORDER, k, &a) || !a) continue;
    const std::string name = a->name;
    const bool field = name.rfind(prefix, 0) == 0;
    const std::string key = field ? name.substr(prefix.size()) : name;
    if (a->type == EXR_ATTR_CHROMATICITIES && name == "chromaticities") {
      const exr_attr_chromaticities_t& c = *a->chromaticities;
      json[key] = {c.red_x,  c.red_y,  c.green_x, c.green_y,
                   c.blue_x, c.blue_y, c.white_x, c.white_y};
    } else if (a->type == EXR_ATTR_M44F && (name == "worldToCamera" || name == "worldToNDC")) {
      json[key] = std::vector<float>(a->m44f->m, a->m44f->m + 16);
    } else if (a->type == EXR_ATTR_STRING && (field || name == "colorInteropID")) {
      const std::string text(a->string->str, static_cast<size_t>(a->string->length));
      json[key] = field ? fieldOfText(text) : nlohmann::json(text);
    } else if (field && a->type == EXR_ATTR_DOUBLE) {
      json[key] = a->d;
    } else if (field && a->type == EXR_ATTR_FLOAT_VECTOR) {
      json[key] =
          std::vector<float>(a->floatvector->arr, a->floatvector->arr + a->floatvector->length);
    }
  }
  exr_finish(&context);
  return json;
}

nlohmann::json readPngMetadata(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), {}};
  const auto* b = reinterpret_cast<const unsigned char*>(bytes.data());
  if (bytes.size() < 8 || bytes.compare(1, 3, "PNG") != 0)
    throw UserError(concat(path, ": not a PNG file"));
  nlohmann::json json = nlohmann::json::object();
  for (size_t at = 8; at + 12 <= bytes.size();) {
    const size_t length = bigEndian(b + at);
    const std::string type = bytes.substr(at + 4, 4);
    if (at + 12 + length > bytes.size()) throw UserError(concat(path, ": a chunk is cut short"));
    const std::string data = bytes.substr(at + 8, length);
    if (type == "cICP" && length == 4) {
      json["cICP"] = {b[at + 8], b[at + 9], b[at + 10], b[at + 11]};
    } else if (type == "sRGB" && length == 1) {
      json["sRGB"] = b[at + 8];
    } else if (type == "iTXt" && data.rfind(std::string(kPngFieldKeyword) + '\0', 0) == 0) {
      // keyword NUL, flag, method, language NUL, translated keyword NUL, text.
      size_t text = data.find('\0') + 3;
      text = data.find('\0', text) + 1;
      text = data.find('\0', text) + 1;
      if (data[data.find('\0') + 1] != 0)
        throw UserError(concat(path, ": its ", kPngFieldKeyword, " text is compressed"));
      const nlohmann::json fields = nlohmann::json::parse(data.substr(text), nullptr, false);
      if (fields.is_discarded() || !fields.is_object())
        throw UserError(concat(path, ": its ", kPngFieldKeyword, " text is not a JSON object"));
      json.update(fields);
    } else if (type == "IEND") {
      break;
    }
    at += 12 + length;
  }
  return json;
}

}  // namespace

nlohmann::json readFrameMetadata(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[4] = {};
  if (!in.read(magic, 4)) throw UserError(concat(path, ": cannot read it as an image"));
  if (std::memcmp(magic, "\x76\x2f\x31\x01", 4) == 0) return readExrMetadata(path);
  if (std::memcmp(magic, "\x89PNG", 4) == 0) return readPngMetadata(path);
  throw UserError(concat(path, ": neither OpenEXR nor PNG (only they carry a frame's header)"));
}

void FrameMetadata::setCamera(const Eigen::Matrix4d& toCamera, const Eigen::Matrix4d& toNdc) {
  const auto rowByRow = [](const Eigen::Matrix4d& matrix) {
    std::array<float, 16> values;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) values[4 * r + c] = static_cast<float>(matrix(r, c));
    return values;
  };
  worldToCamera = rowByRow(toCamera);
  worldToNdc = rowByRow(toNdc);
}

nlohmann::json frameMetadataJson(const FrameMetadata& metadata) {
  nlohmann::json json = metadata.fields;
  json["colorInteropID"] = metadata.colorInteropId();
  if (metadata.worldToCamera) json["worldToCamera"] = matrixJson(*metadata.worldToCamera);
  if (metadata.worldToNdc) json["worldToNDC"] = matrixJson(*metadata.worldToNdc);
  return json;
}

std::vector<PngChunk> srgbFrameChunks(const FrameMetadata& metadata) {
  std::vector<PngChunk> chunks;
  // cICP (PNG, third edition): BT.709 primaries (1), sRGB transfer (13), RGB (0), full range (1).
  chunks.push_back({{'c', 'I', 'C', 'P'}, {1, 13, 0, 1}});
  chunks.push_back({{'s', 'R', 'G', 'B'}, {0}});  // perceptual intent
  PngChunk gamma{{'g', 'A', 'M', 'A'}, {}};
  appendBigEndian(gamma.data, 45455);  // 1 / 2.2, x 100000, as PNG 11.3.3.4 pairs with sRGB
  chunks.push_back(gamma);
  PngChunk primaries{{'c', 'H', 'R', 'M'}, {}};
  const auto& c = kRec709Chromaticities;
  for (int k : {6, 7, 0, 1, 2, 3, 4, 5})  // white, red, green, blue
    appendBigEndian(primaries.data, static_cast<std::uint32_t>(std::lround(c[k] * 100000.0)));
  chunks.push_back(primaries);
  // iTXt: keyword, NUL, not compressed (0, 0), no language, NUL, no translated keyword, NUL, text.
  PngChunk text{{'i', 'T', 'X', 't'}, {}};
  const std::string keyword = kPngFieldKeyword, json = frameMetadataJson(metadata).dump();
  text.data.assign(keyword.begin(), keyword.end());
  text.data.insert(text.data.end(), {0, 0, 0, 0, 0});
  text.data.insert(text.data.end(), json.begin(), json.end());
  chunks.push_back(text);
  return chunks;
}

}  // namespace acpca
