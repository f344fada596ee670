// Writes the Python package's _contract.py at build time: every constant the
// C++ libraries define that the pure-Python side of adaptive_cpca needs
// (file versions, the lattice, spec grammars, limits, the built-in maps and
// the sampling constants), read from the headers that define them, so that
// no number is copied by hand. Some grammars are built at run time (the light
// kinds'), so this is a program linked to the libraries, not a template.
// Usage: acpca_write_contract OUT.py
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "core/text.h"
#include "core/version.h"
#include "lighting/builtin_maps.h"
#include "lighting/cube_cross.h"
#include "lighting/environment.h"
#include "lighting/light_kinds.h"
#include "lighting/lighting_sampler.h"
#include "lighting/sh_lighting.h"
#include "model/model_file.h"
#include "relight/image_composer.h"
#include "transport/light_set.h"
#include "transport/transport_file.h"

namespace acpca {
namespace {

/// A Python literal for a double: the shortest text that reads back as it,
/// always a float.
std::string floatLiteral(double v) {
  std::string text = shortestNumberText(v);
  if (text.find_first_of(".en") == std::string::npos) text += ".0";
  return text;
}

std::string stringLiteral(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  out += '"';
  return out;
}

template <typename Items, typename Write>
std::string tupleLiteral(const Items& items, Write write) {
  std::string out = "(";
  for (const auto& item : items) {
    if (out.size() > 1) out += ", ";
    out += write(item);
  }
  out += std::size(items) == 1 ? ",)" : ")";  // (a,): one item is a tuple
  return out;
}

std::string rgbLiteral(const std::array<double, 3>& v) {
  return tupleLiteral(v, floatLiteral);
}

std::string vecLiteral(const Vec3& v) {
  return tupleLiteral(std::array<double, 3>{v.x(), v.y(), v.z()},
                      [](double x) { return std::to_string(static_cast<int>(x)); });
}

std::string hexLiteral(std::uint64_t v) {
  char text[24];
  std::snprintf(text, sizeof text, "0x%016llX", static_cast<unsigned long long>(v));
  return text;
}

class ContractWriter {
 public:
  void section(const char* comment) { out_ << "\n# " << comment << "\n"; }
  void constant(const char* name, const std::string& literal) {
    out_ << name << " = " << literal << "\n";
  }
  std::string text() const { return out_.str(); }

 private:
  std::ostringstream out_;
};

void writeVersions(ContractWriter& w) {
  w.section("core/version.h");
  w.constant("VERSION", stringLiteral(kVersion));
  w.section("model/model_file.h and transport/transport_file.h: the versions read");
  w.constant("MODEL_VERSION", std::to_string(kModelVersion));
  w.constant("OLDEST_MODEL_VERSION", std::to_string(kOldestModelVersion));
  w.constant("TRANSPORT_VERSION", std::to_string(kTransportVersion));
  w.constant("OLDEST_TRANSPORT_VERSION", std::to_string(kOldestTransportVersion));
}

void writeLattice(ContractWriter& w) {
  w.section("transport/cube_lattice.h: faces +X, -X, +Y, -Y, +Z, -Z");
  w.constant("CUBE_FACES", std::to_string(CubeLattice::kFaces));
  w.constant("MAX_CUBE_RESOLUTION", std::to_string(CubeLattice::kMaxResolution));
  w.section("transport/light_set.h: a light set's fine lattice and its parts");
  w.constant("CELL_LATTICE_STEP", std::to_string(kCellLatticeStep));
  w.constant("MIN_CELL_LATTICE", std::to_string(kMinCellLattice));
  w.constant("MAX_CELL_LATTICE", std::to_string(kMaxCellLattice));
  w.constant("CELL_SAMPLES_PER_FACE_SIDE", std::to_string(kCellSamplesPerFaceSide));
  w.section("lighting/cube_cross.h: (column, row, centre, right, down) per face");
  w.constant("CROSS_FACES", tupleLiteral(kCrossFaces, [](const CrossFace& f) {
               return tupleLiteral(
                   std::array{std::to_string(f.column), std::to_string(f.row), vecLiteral(f.centre),
                              vecLiteral(f.right), vecLiteral(f.down)},
                   [](const std::string& part) { return part; });
             }));
}

void writeSpecs(ContractWriter& w) {
  w.section(
      "lighting/environment.h and light_kinds.h: the specs (ENVIRONMENT_SPECS: prefix, grammar)");
  w.constant("ENVIRONMENT_GRAMMARS", stringLiteral(environmentGrammarList()));
  w.constant("ENVIRONMENT_SPECS", tupleLiteral(kEnvironmentGrammars, [](const auto& g) {
               return tupleLiteral(std::array{stringLiteral(g.prefix), stringLiteral(g.grammar)},
                                   [](const std::string& part) { return part; });
             }));
  w.constant("LIGHT_GRAMMARS", tupleLiteral(kLightGrammars, [](const LightGrammar& g) {
               return stringLiteral(g.grammar);
             }));
  w.constant("MAP_FILE_EXTENSIONS", tupleLiteral(kMapFileExtensions, [](std::string_view e) {
               return stringLiteral(std::string(e));
             }));
  w.constant("BACKGROUNDS", tupleLiteral(kBackgroundNames.entries(), [](const auto& entry) {
               return stringLiteral(entry.second);
             }));
}

void writeMaps(ContractWriter& w) {
  w.section("lighting/environment.h and builtin_maps.h: limits on maps");
  w.constant("MAX_NEGATIVE_SHARE", floatLiteral(kMaxNegativeShare));
  w.constant("SILENT_NEGATIVE_SHARE", floatLiteral(kSilentNegativeShare));
  w.constant("LATLONG_ASPECT_TOLERANCE", floatLiteral(kLatLongAspectTolerance));
  w.constant("MAX_MAP_PIXELS", std::to_string(kMaxMapPixels));
  w.constant("MAP_SUB_CELLS_PER_TEXEL", std::to_string(kMapSubCellsPerTexel));

  w.section("lighting/builtin_maps.h: the built-in sky and a disc's rings");
  w.constant("SKY_SUN",
             tupleLiteral(std::array{kSkySunTheta, kSkySunPhi, kSkySunSize}, floatLiteral));
  w.constant("SKY_SUN_RADIANCE", rgbLiteral(kSkySunRadiance));
  w.constant("SKY_ZENITH", rgbLiteral(kSkyZenith));
  w.constant("SKY_HORIZON", rgbLiteral(kSkyHorizon));
  w.constant("SKY_GROUND", rgbLiteral(kSkyGround));
  w.constant("SKY_GLOW_COLOUR", rgbLiteral(kSkyGlowColour));
  w.constant("SKY_GLOW_STRENGTH", floatLiteral(kSkyGlowStrength));
  w.constant("SKY_GLOW_SHARPNESS", floatLiteral(kSkyGlowSharpness));
  w.constant("SKY_HORIZON_POWER", std::to_string(kSkyHorizonPower));
  w.constant("SKY_SUB_CELLS", std::to_string(kSkySubCells));
  w.constant("DISC_RINGS_PER_TEXEL", std::to_string(kDiscRingsPerTexel));
  w.constant("MIN_DISC_RINGS", std::to_string(kMinDiscRings));
  w.constant("MAX_DISC_RINGS", std::to_string(kMaxDiscRings));
  w.section("lighting/sh_lighting.h: c0 .. c4 of realSh9");
  w.constant("SH9_NORMALISATIONS", tupleLiteral(kSh9Normalisations, floatLiteral));
}

void writeSampling(ContractWriter& w) {
  w.section("lighting/lighting_sampler.h: the --env-sample draws");
  w.constant("SPLITMIX_INCREMENT", hexLiteral(kSplitMixIncrement));
  w.constant("SPLITMIX_MIXES", tupleLiteral(kSplitMixMixes, [](const auto& mix) {
               return tupleLiteral(std::array{std::to_string(mix.first), hexLiteral(mix.second)},
                                   [](const std::string& part) { return part; });
             }));
  w.constant("SPLITMIX_LAST_SHIFT", std::to_string(kSplitMixLastShift));
  w.constant("UNIFORMS_PER_DRAW", std::to_string(kUniformsPerDraw));
  w.constant("DRAW_ROUNDING_STEPS", floatLiteral(kDrawRoundingSteps));
  w.constant("MAX_LIGHTING_SAMPLES", std::to_string(kMaxLightingSamples));
  w.constant("MAX_EXPOSURE_JITTER", floatLiteral(kMaxExposureJitter));
  w.constant("SAMPLED_ROTATIONS",
             tupleLiteral(kSampledRotationNames.entries(),
                          [](const auto& entry) { return stringLiteral(entry.second); }));
}

std::string contractText() {
  ContractWriter w;
  writeVersions(w);
  writeLattice(w);
  writeSpecs(w);
  writeMaps(w);
  writeSampling(w);
  return w.text();
}

}  // namespace
}  // namespace acpca

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: " << argv[0] << " OUT.py\n";
    return 2;
  }
  const std::filesystem::path out = argv[1], temporary = out.string() + ".tmp";
  {
    std::ofstream file(temporary);
    file << "\"\"\"The constants adaptive_cpca's C++ libraries define, for its pure-Python\n"
            "side: generated at build time by python/write_contract.cpp from the\n"
            "headers named above each group. Do not edit; rebuild.\"\"\"\n"
         << acpca::contractText();
    if (!file) {
      std::cerr << "could not write " << temporary << "\n";
      return 1;
    }
  }
  std::filesystem::rename(temporary, out);
  return 0;
}
