#include "lighting/rotation.h"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <sstream>

#include "core/error.h"
#include "lighting/spec_parsing.h"

namespace acpca {

namespace {

double toRadians(double degrees) {
  return degrees * std::numbers::pi / 180.0;
}

std::string formatAngle(double degrees) {
  std::ostringstream out;
  out << degrees;
  return out.str();
}

double parseNumber(const std::string& text, const std::string& spec) {
  return parseFiniteNumber(text, "rotation", spec);
}

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, separator)) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.push_back("");
  return parts;
}

}  // namespace

std::string EnvRotation::label() const {
  if (pitch == 0 && roll == 0) return concat("y", formatAngle(yaw));
  return concat("y", formatAngle(yaw), "_p", formatAngle(pitch), "_r", formatAngle(roll));
}

Eigen::Matrix3d rotationMatrix(const EnvRotation& r) {
  using Eigen::AngleAxisd;
  return (AngleAxisd(toRadians(r.roll), Eigen::Vector3d::UnitZ()) *
          AngleAxisd(toRadians(r.pitch), Eigen::Vector3d::UnitX()) *
          AngleAxisd(toRadians(r.yaw), Eigen::Vector3d::UnitY()))
      .toRotationMatrix();
}

void validateRotation(const EnvRotation& r) {
  for (const auto& [name, value] :
       {std::pair<const char*, double>{"yaw", r.yaw}, {"pitch", r.pitch}, {"roll", r.roll}})
    requireFinite(value, name);
}

std::vector<EnvRotation> parseRotationSpec(const std::string& spec) {
  if (spec.find(':') != std::string::npos) {
    const auto parts = split(spec, ':');
    if (parts.size() != 3)
      throw ParameterError("rotation", spec, concat("expected ", kRotationSweepGrammar));
    const double a = parseNumber(parts[0], spec), b = parseNumber(parts[1], spec),
                 s = parseNumber(parts[2], spec);
    if (s <= 0) throw ParameterError("rotation", spec, "the step must be > 0");
    if (b <= a) throw ParameterError("rotation", spec, "the end must exceed the start");
    const double count = std::ceil((b - a) / s - 1e-9);
    if (count > 100000) throw ParameterError("rotation", spec, "more than 100000 steps");
    std::vector<EnvRotation> sweep;
    for (int i = 0; i < static_cast<int>(count); ++i) sweep.push_back({a + i * s, 0, 0});
    return sweep;
  }
  const auto parts = split(spec, ',');
  if (parts.size() != 1 && parts.size() != 3)
    throw ParameterError("rotation", spec,
                         concat("expected ", kRotationGrammar, " or ", kRotationSweepGrammar));
  EnvRotation r;
  r.yaw = parseNumber(parts[0], spec);
  if (parts.size() == 3) {
    r.pitch = parseNumber(parts[1], spec);
    r.roll = parseNumber(parts[2], spec);
  }
  return {r};
}

EnvRotation parseSingleRotation(const std::string& spec, const std::string& flag) {
  if (spec.empty()) return {};
  const auto parsed = parseRotationSpec(spec);
  if (parsed.size() != 1)
    throw UserError(concat(flag, " takes one rotation here, not a sweep (", spec, ")"));
  return parsed.front();
}

std::vector<EnvRotation> parseRotationSpecs(const std::vector<std::string>& specs) {
  std::vector<EnvRotation> all;
  for (const auto& spec : specs) {
    const auto parsed = parseRotationSpec(spec);
    all.insert(all.end(), parsed.begin(), parsed.end());
  }
  if (all.empty()) all.push_back({});
  return all;
}

}  // namespace acpca
