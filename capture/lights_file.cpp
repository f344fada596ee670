#include "capture/lights_file.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/text.h"
#include "core/warning.h"
#include "transport/light_set.h"

namespace acpca {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string trimmed(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

double parseNumber(const std::string& text, const std::string& where, const std::string& what) {
  const std::string t = trimmed(text);
  double v = 0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || ec != std::errc() || end != t.data() + t.size() || !std::isfinite(v))
    throw UserError(concat(where, ": ", what, " '", t, "' is not a finite number"));
  return v;
}

/// A light's direction from what the file gave, checked.
Eigen::Vector3d unitDirection(const Eigen::Vector3d& v, const std::string& where) {
  const double n = v.norm();
  if (!(n > 0) || !std::isfinite(n))
    throw UserError(concat(where,
                           ": the light's direction is zero (it must point from the "
                           "subject toward the light)"));
  return v / n;
}

void checkIrradiance(const Eigen::Vector3d& e, const std::string& where) {
  if (!(e.array() > 0).all())
    throw UserError(concat(where, ": intensity must be > 0 in every channel"));
}

// ---- CSV ----

struct CsvColumns {
  int image = -1, x = -1, y = -1, z = -1, r = -1, g = -1, b = -1, solidAngle = -1;
  size_t count = 0;
};

CsvColumns csvColumns(const std::string& headerLine, const std::string& where) {
  CsvColumns c;
  const std::vector<std::string> names = splitText(headerLine, ',');
  c.count = names.size();
  std::set<std::string> seen;
  for (size_t i = 0; i < names.size(); ++i) {
    std::string name = trimmed(names[i]);
    std::transform(name.begin(), name.end(), name.begin(), ::tolower);
    if (!seen.insert(name).second)
      throw UserError(concat(where, ": column '", name, "' appears twice"));
    int* slot = name == "image"         ? &c.image
                : name == "x"           ? &c.x
                : name == "y"           ? &c.y
                : name == "z"           ? &c.z
                : name == "r"           ? &c.r
                : name == "g"           ? &c.g
                : name == "b"           ? &c.b
                : name == "solid_angle" ? &c.solidAngle
                                        : nullptr;
    if (!slot)
      throw UserError(concat(where, ": unknown column '", name,
                             "' (the header is image,x,y,z[,r,g,b][,solid_angle])"));
    *slot = static_cast<int>(i);
  }
  if (c.image < 0 || c.x < 0 || c.y < 0 || c.z < 0)
    throw UserError(concat(where, ": the header must name the columns image, x, y and z (got '",
                           trimmed(headerLine), "')"));
  const int colours = (c.r >= 0) + (c.g >= 0) + (c.b >= 0);
  if (colours != 0 && colours != 3)
    throw UserError(concat(where, ": give all of r, g and b, or none"));
  return c;
}

std::vector<LightEntry> parseCsv(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  std::string line;
  int lineNumber = 0;
  std::optional<CsvColumns> columns;
  std::vector<LightEntry> lights;
  while (std::getline(in, line)) {
    ++lineNumber;
    const std::string t = trimmed(line);
    if (t.empty() || t[0] == '#') continue;
    const std::string where = concat(path, " line ", lineNumber);
    if (!columns) {
      columns = csvColumns(t, where);
      continue;
    }
    const std::vector<std::string> cells = splitText(t, ',');
    if (cells.size() != columns->count)
      throw UserError(
          concat(where, ": ", cells.size(), " values, the header names ", columns->count));
    const auto number = [&](int column, const char* what) {
      return parseNumber(cells[column], where, what);
    };
    LightEntry e;
    e.where = where;
    e.image = trimmed(cells[columns->image]);
    if (e.image.empty()) throw UserError(concat(where, ": the image name is empty"));
    e.direction = unitDirection(
        {number(columns->x, "x"), number(columns->y, "y"), number(columns->z, "z")}, where);
    if (columns->r >= 0) {
      e.irradiance = {number(columns->r, "r"), number(columns->g, "g"), number(columns->b, "b")};
      checkIrradiance(e.irradiance, where);
    }
    if (columns->solidAngle >= 0) e.solidAngle = number(columns->solidAngle, "solid_angle");
    lights.push_back(std::move(e));
  }
  if (!columns) throw UserError(concat(path, ": no header line (image,x,y,z[,r,g,b])"));
  return lights;
}

// ---- JSON ----

Eigen::Vector3d jsonVector(const json& v, const std::string& where) {
  if (!v.is_array() || v.size() != 3)
    throw UserError(concat(where, ": expected 3 numbers [x, y, z]"));
  Eigen::Vector3d out;
  for (int i = 0; i < 3; ++i) {
    if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
      throw UserError(concat(where, ": expected 3 finite numbers"));
    out[i] = v[i].get<double>();
  }
  return out;
}

LightEntry jsonLight(const json& item, const std::string& where,
                     const std::optional<Eigen::Vector3d>& center) {
  if (!item.is_object()) throw UserError(concat(where, ": expected an object"));
  for (const auto& kv : item.items())
    if (kv.key() != "image" && kv.key() != "direction" && kv.key() != "position" &&
        kv.key() != "intensity" && kv.key() != "solid_angle")
      throw UserError(concat(where, ": unknown key '", kv.key(),
                             "' (image, direction or position, intensity, solid_angle)"));
  LightEntry e;
  e.where = where;
  if (!item.contains("image") || !item["image"].is_string() ||
      item["image"].get<std::string>().empty())
    throw UserError(concat(where, ": 'image' must name the light's image"));
  e.image = item["image"].get<std::string>();
  const bool hasDirection = item.contains("direction"), hasPosition = item.contains("position");
  if (hasDirection == hasPosition)
    throw UserError(concat(where, ": give either 'direction' or 'position'"));
  if (hasDirection) {
    e.direction = unitDirection(jsonVector(item["direction"], where + ".direction"), where);
  } else {
    if (!center)
      throw UserError(concat(where,
                             ": a 'position' needs the subject's \"center\" at the top "
                             "level of the file"));
    e.direction = unitDirection(jsonVector(item["position"], where + ".position") - *center, where);
  }
  if (item.contains("intensity")) {
    const json& v = item["intensity"];
    if (v.is_number() && std::isfinite(v.get<double>()))
      e.irradiance = Eigen::Vector3d::Constant(v.get<double>());
    else
      e.irradiance = jsonVector(v, where + ".intensity");
    checkIrradiance(e.irradiance, where);
  }
  if (item.contains("solid_angle")) {
    const json& v = item["solid_angle"];
    if (!v.is_number() || !std::isfinite(v.get<double>()))
      throw UserError(concat(where, ".solid_angle: expected a finite number"));
    e.solidAngle = v.get<double>();
  }
  return e;
}

std::vector<LightEntry> parseJson(const std::string& text, const std::string& path) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {
    throw UserError(concat(path, ": not valid JSON: ", e.what()));
  }
  if (!root.is_object()) throw UserError(concat(path, ": expected an object {\"lights\": [...]}"));
  for (const auto& kv : root.items())
    if (kv.key() != "lights" && kv.key() != "center")
      throw UserError(concat(path, ": unknown key '", kv.key(), "' (lights, center)"));
  std::optional<Eigen::Vector3d> center;
  if (root.contains("center")) center = jsonVector(root["center"], path + ": center");
  if (!root.contains("lights") || !root["lights"].is_array())
    throw UserError(concat(path, ": 'lights' must be a list of lights"));
  std::vector<LightEntry> lights;
  const json& list = root["lights"];
  for (size_t i = 0; i < list.size(); ++i)
    lights.push_back(jsonLight(list[i], concat(path, ": lights[", i, "]"), center));
  return lights;
}

/// Solid angles for all lights or none; no direction twice; not too many.
void checkLights(const std::vector<LightEntry>& lights, const std::string& path) {
  if (lights.empty()) throw UserError(concat(path, ": the file lists no lights"));
  requireLightCount(lights.size(), path);
  if (lights.size() > static_cast<size_t>(kMaxLights))
    throw UserError(concat(path, ": ", lights.size(), " lights, more than the ", kMaxLights,
                           " a light set may hold"));
  const bool given = lights.front().solidAngle >= 0;
  for (const LightEntry& e : lights) {
    if ((e.solidAngle >= 0) != given)
      throw UserError(concat(e.where, ": give every light's solid_angle, or none"));
    if (given && !(e.solidAngle > 0 && e.solidAngle <= 4 * std::numbers::pi))
      throw UserError(concat(e.where, ": solid_angle ", e.solidAngle, " is not in (0, 4 pi]"));
  }
  std::vector<Vec3> directions;
  for (const LightEntry& e : lights) directions.push_back(e.direction);
  const auto [first, second] = findSameDirection(directions);
  if (second >= 0)
    throw UserError(concat(lights[second].where, ": the same direction as ", lights[first].where,
                           " (two lights cannot stand in one place)"));
}

}  // namespace

void requireLightCount(size_t lights, const std::string& where) {
  if (lights < 2)
    throw UserError(concat(where, ": ", lights,
                           " light(s); a light set needs at least 2 (one "
                           "light's cell is the whole sphere, so every relight would be its "
                           "image scaled)"));
}

LightsFile parseLightsFile(const std::string& text, const std::string& path) {
  LightsFile file;
  file.path = path;
  const auto first = text.find_first_not_of(" \t\r\n");
  const bool isJson = first != std::string::npos && text[first] == '{';
  file.lights = isJson ? parseJson(text, path) : parseCsv(text, path);
  checkLights(file.lights, path);
  const fs::path folder = fs::path(path).parent_path();
  for (LightEntry& e : file.lights) e.imagePath = (folder / e.image).lexically_normal().string();
  return file;
}

void warnOfUnlistedImages(const LightsFile& file) {
  std::set<fs::path> listed, folders;
  std::set<std::string> kinds;
  for (const LightEntry& e : file.lights) {
    const fs::path p = fs::path(e.imagePath).lexically_normal();
    listed.insert(p);
    folders.insert(p.parent_path());
    kinds.insert(p.extension().string());
  }
  long long unlisted = 0;
  for (const fs::path& folder : folders) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(folder.empty() ? "." : folder, ec))
      if (entry.is_regular_file() && kinds.count(entry.path().extension().string()) &&
          !listed.count((folder / entry.path().filename()).lexically_normal()))
        ++unlisted;
  }
  if (unlisted > 0)
    warn(concat(file.path, " lists ", file.lights.size(), " images; ", unlisted,
                " more of their kind lie beside them unlisted"));
}

LightsFile readLightsFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw UserError(concat(path, ": cannot open the lights file"));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw UserError(concat(path, ": cannot read the lights file"));
  return parseLightsFile(text.str(), path);
}

}  // namespace acpca
