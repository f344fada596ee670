#include "dataset/file_info.h"

#include <cstring>
#include <filesystem>
#include <numbers>
#include <sstream>

#include "core/text.h"
#include "dataset/pixel_labels.h"
#include "imageio/frame_metadata.h"
#include "model/model_file.h"

namespace acpca {

namespace {

nlohmann::json cameraJson(const Camera& c) {
  const auto vec3 = [](const Vec3& v) { return nlohmann::json{v.x(), v.y(), v.z()}; };
  return {
      {"eye", vec3(c.eye)}, {"target", vec3(c.target)}, {"up", vec3(c.up)}, {"fov", c.fovDegrees}};
}

std::string positionsInWords(const TransportHeader& h, const PixelDatasets& d,
                             const std::string& remedy) {
  if (h.isLightSet()) return "  positions    none (captured images hold no geometry)\n";
  return d.positions ? "  positions    each pixel's world position (local lights)\n"
                     : concat("  positions    none (written before positions were stored; ", remedy,
                              " for local lights)\n");
}

/// How the file lights lamps (relight/lamp_light.h).
std::string lampsInWords(const TransportHeader& h, const PixelDatasets& d,
                         const std::string& remedy) {
  if (h.isLightSet()) return "  lamps        none (captured images hold no geometry)\n";
  if (!d.lamps)
    return concat("  lamps        through the lattice (written before surfaces were stored; ",
                  remedy, " for exact lamps)\n");
  if (h.bounces > 0) return "  lamps        through the lattice (the rows hold bounced light)\n";
  return "  lamps        exact: shadow rays from each camera sample\n";
}

/// The scene's materials by geometry, as the file records them.
nlohmann::json materialsJson(const PixelDatasets& d) {
  nlohmann::json list = nlohmann::json::array();
  for (const Material& m : d.materials) {
    nlohmann::json j = {{"type", kMaterialTypeNames.name(m.type)}};
    if (m.type != Material::Type::Diffuse) j["specular"] = m.specular;
    if (m.type == Material::Type::Phong) j["exponent"] = m.exponent;
    if (m.type == Material::Type::Ggx) j["roughness_u"] = m.alphaU(), j["roughness_v"] = m.alphaV();
    if (m.type == Material::Type::AshikhminShirley) j["nu"] = m.nu, j["nv"] = m.nv;
    if (m.type == Material::Type::Ggx || m.type == Material::Type::AshikhminShirley)
      j["rotation"] = m.rotationDegrees;
    list.push_back(j);
  }
  return list;
}

std::string materialsInWords(const PixelDatasets& d) {
  if (d.materials.empty()) return "";
  std::string text;
  for (size_t k = 0; k < d.materials.size(); ++k)
    text += concat(k ? "; " : "", describeMaterial(d.materials[k]));
  return concat("  materials    ", text, "\n");
}

/// The AOVs the file can give, by name.
nlohmann::json labelsJson(const TransportHeader& h, const PixelDatasets& d) {
  nlohmann::json names = nlohmann::json::array();
  for (Aov aov : availableAovs(h, d)) names.push_back(kAovNames.name(aov));
  return names;
}

std::string labelsInWords(const TransportHeader& h, const PixelDatasets& d,
                          const std::string& remedy) {
  std::string names;
  for (const auto& name : labelsJson(h, d))
    names += (names.empty() ? "" : ", ") + name.get<std::string>();
  const bool all = availableAovs(h, d).size() == parseAovList("all").size();
  return concat("  labels       ", names,
                all              ? concat(" (", h.objectNames.size(), " object(s))")
                : h.isLightSet() ? std::string(" (captured images hold no geometry or albedo)")
                                 : concat(" (", remedy, " for the others)"),
                "\n");
}

/// The lighting domain: the lattice, or a captured light set.
std::string domainInWords(const TransportHeader& h, const std::string& ofBases = "") {
  if (!h.isLightSet())
    return concat("  lattice      6x", h.cubemapResolution, "x", h.cubemapResolution, " = ",
                  h.latticeSize(), " directions", ofBases, "\n");
  const double uncovered = h.lights.uncoveredSolidAngle();
  return concat("  lights       ", h.lights.describe(), ofBases, "\n", "  uncovered    ",
                formatted("%.4g", uncovered), " sr (",
                formatted("%.2f", 100 * uncovered / (4 * std::numbers::pi)),
                "% of the sphere): lighting from there does not reach the images\n");
}

nlohmann::json lightsJson(const TransportHeader& h) {
  if (!h.isLightSet()) return nullptr;
  return {{"count", h.lights.size()},
          {"cells", h.lights.cells == CellSource::Given ? "given" : "capped-voronoi"},
          {"cap_deg", h.lights.cells == CellSource::Given ? nlohmann::json(nullptr)
                                                          : nlohmann::json(h.lights.capDegrees)},
          {"uncovered_sr", h.lights.uncoveredSolidAngle()}};
}

}  // namespace

const char* rowLayoutName(int channels) {
  return channels == 3 ? "rgb" : "shared";
}

nlohmann::json rankHistogramJson(const std::vector<std::int32_t>& ranks) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [rank, count] : rankHistogram(ranks)) j[std::to_string(rank)] = count;
  return j;
}

nlohmann::json describeModel(const ModelSummary& m) {
  return {
      {"kind", "model"},
      {"camera", m.geometry.isLightSet() ? nlohmann::json(nullptr) : cameraJson(m.geometry.camera)},
      {"lights", lightsJson(m.geometry)},
      {"width", m.geometry.camera.size.width},
      {"height", m.geometry.camera.size.height},
      {"occupied_pixels", m.pixels.rows},
      {"cubemap", m.geometry.cubemapResolution},
      {"row_layout", rowLayoutName(m.geometry.channels)},
      {"global_bases", m.globalBases},
      {"clusters", m.clusters()},
      {"cost_per_pixel", m.costPerPixel()},
      {"total_cost", m.totalCost()},
      {"bytes", m.fileBytes},
      {"bytes_per_frame", m.frameBytes()},
      {"method", m.method},
      {"scene", m.geometry.scene},
      {"coeffs", coeffPrecisionName(m.precision)},
      {"bases", coeffPrecisionName(m.basisPrecision)},
      {"transport_error", m.transportError},
      {"rank_histogram", rankHistogramJson(m.ranks)},
      {"positions", m.pixels.positions},
      {"exact_lamps", m.pixels.lamps && m.geometry.bounces == 0},
      {"labels", labelsJson(m.geometry, m.pixels)},
      {"materials", materialsJson(m.pixels)},
      {"settings", nlohmann::json::parse(m.settings, nullptr, false)}};
}

nlohmann::json describeTransport(const TransportSummary& t) {
  const TransportHeader& h = t.header;
  const long long rows = t.pixels.rows;
  return {{"kind", "transport"},
          {"camera", h.isLightSet() ? nlohmann::json(nullptr) : cameraJson(h.camera)},
          {"lights", lightsJson(h)},
          {"width", h.camera.size.width},
          {"height", h.camera.size.height},
          {"occupied_pixels", rows},
          {"cubemap", h.cubemapResolution},
          {"directions", h.latticeSize()},
          {"global_bases", nullptr},
          {"clusters", nullptr},
          {"cost_per_pixel", h.latticeSize()},
          {"bytes", t.fileBytes},
          {"method", "dense"},
          {"scene", h.scene},
          {"precision", precisionName(h.precision)},
          {"spp", h.samplesPerPixel},
          {"texel_rays", h.texelRays},
          {"row_layout", rowLayoutName(h.channels)},
          {"bounces", h.bounces},
          {"indirect_samples", h.bounces > 0 ? nlohmann::json(h.indirectSamples) : nullptr},
          {"indirect_cache_cell", h.bounces > 0 ? nlohmann::json(h.indirectCacheCell) : nullptr},
          {"stored_values", rows * static_cast<long long>(h.rowLength())},
          {"positions", t.pixels.positions},
          {"exact_lamps", t.pixels.lamps && h.bounces == 0},
          {"labels", labelsJson(h, t.pixels)},
          {"materials", materialsJson(t.pixels)}};
}

namespace {

bool isFrameFile(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".exr" || extension == ".png";
}

std::string numberList(const nlohmann::json& values, size_t first, size_t count) {
  std::string text;
  for (size_t k = first; k < first + count && k < values.size(); ++k)
    text += concat(k > first ? " " : "", values[k].get<float>() + 0.0f);  // 6 digits, no -0
  return text;
}

}  // namespace

FileDescription describeFrame(const std::string& path) {
  const nlohmann::json m = readFrameMetadata(path);
  std::ostringstream out;
  if (!m.contains("env") && !m.contains("source")) {
    out << path << ": an image with no frame header (written before frames carried one, "
        << "or by another tool)\n";
    return {m, out.str()};
  }
  const auto text = [&](const char* key) {
    if (!m.contains(key) || m[key].is_null()) return std::string("none");
    return m[key].is_number() ? shortestNumberText(m[key].get<double>()) : m[key].dump();
  };
  const std::string env = m.value("env", "");
  out << path << ": frame " << text("frame") << " of " << m.value("source", "?") << " ("
      << m.value("method", "?") << "), adaptive-cpca " << m.value("version", "?") << "\n"
      << "  lighting     " << (env.empty() ? "no map" : env) << " at yaw " << text("yaw")
      << ", pitch " << text("pitch") << ", roll " << text("roll") << ", exposure "
      << text("exposure") << " EV\n";
  if (m.contains("cost_per_pixel"))
    out << "  cost         " << text("cost_per_pixel") << " multiply-adds per pixel\n";
  if (m.contains("lights") && !m["lights"].empty())
    out << "  lamps        " << m["lights"].dump() << "\n";
  if (m.contains("sources") && !m["sources"].empty())
    out << "  sources      " << m["sources"].size() << " split off and lit exactly\n";
  if (m.contains("env_sha256") && m["env_sha256"].is_string())
    out << "  map sha256   " << m["env_sha256"].get<std::string>() << "\n";
  out << "  colour       " << m.value("colorInteropID", "?")
      << (m.contains("cICP") ? ", PNG: sRGB-encoded, BT.709 primaries" : "")
      << (m.contains("chromaticities") ? ", Rec.709 primaries, D65 white" : "") << "\n";
  for (const char* matrix : {"worldToCamera", "worldToNDC"})
    if (m.contains(matrix))
      for (int r = 0; r < 4; ++r) {
        const std::string label = r ? "" : matrix;
        out << "  " << label << std::string(15 - label.size(), ' ')
            << numberList(m[matrix], 4 * r, 4) << "\n";
      }
  return {m, out.str()};
}

FileDescription describeFile(const std::string& path) {
  if (isFrameFile(path)) return describeFrame(path);
  if (isModelFile(path)) {
    const ModelSummary model = readModelSummary(path);
    return {describeModel(model), describeInWords(model, path)};
  }
  const TransportSummary transport = readTransportSummary(path);
  return {describeTransport(transport), describeInWords(transport, path)};
}

std::string describeInWords(const ModelSummary& m, const std::string& path) {
  std::ostringstream out;
  out << path << ": " << m.method << " model of scene '" << m.geometry.scene << "'\n"
      << "  image        " << m.geometry.camera.size.width << "x" << m.geometry.camera.size.height
      << ", " << m.pixels.rows << " occupied pixels\n"
      << domainInWords(m.geometry, concat(", N = ", m.globalBases, " global bases",
                                          m.geometry.channels == 3 ? " over R, G and B rows" : ""))
      << "  clusters     " << m.clusters() << (m.hasMean ? " (with means)" : "") << ", ranks "
      << rankSummary(m.ranks) << "\n"
      << "  cost         " << m.totalCost() << " multiply-adds per frame, " << m.costPerPixel()
      << " per pixel\n"
      << "  storage      " << coeffPrecisionName(m.precision) << " coefficients, "
      << coeffPrecisionName(m.basisPrecision) << " bases, " << formatBytes(m.frameBytes())
      << " read per frame, " << formatBytes(double(m.fileBytes)) << " on disk\n"
      << "  error        " << m.transportError << " relative to T (Frobenius)\n"
      << positionsInWords(m.geometry, m.pixels, "compress (or build) it again from a new transport")
      << lampsInWords(m.geometry, m.pixels, "compress (or build) it again from a new transport")
      << materialsInWords(m.pixels)
      << labelsInWords(m.geometry, m.pixels, "compress (or build) it again from a new transport");
  return out.str();
}

std::string describeInWords(const TransportSummary& t, const std::string& path) {
  const TransportHeader& h = t.header;
  const long long rows = t.pixels.rows;
  const long long storedValues = rows * static_cast<long long>(h.rowLength());
  std::ostringstream out;
  out << path << ": transport of scene '" << h.scene << "'\n"
      << "  image        " << h.camera.size.width << "x" << h.camera.size.height << ", " << rows
      << " occupied pixels (" << 100.0 * rows / h.camera.size.pixels() << "%)\n"
      << domainInWords(h)
      << (h.isLightSet() ? "  source       captured images (imported), no camera\n"
                         : concat("  sampling     ", h.samplesPerPixel, " sample(s) per pixel, ",
                                  h.texelRays, " ray(s) per texel\n"))
      << (h.isLightSet() ? "" : "  light        ")
      << (h.isLightSet()  ? std::string()
          : h.bounces > 0 ? concat("direct and up to ", h.bounces,
                                   " bounce(s): ", h.indirectSamples, " paths per traced sample, ",
                                   h.indirectCacheCell > 0
                                       ? concat("visibility cache cell ", h.indirectCacheCell,
                                                " of the scene's extent")
                                       : std::string("exact visibility at every vertex"),
                                   "\n")
                          : std::string("direct\n"))
      << "  rows         "
      << (h.channels == 3 ? "R, G and B side by side (3 x l values per pixel)"
                          : "one per pixel, shared by R, G and B")
      << "\n"
      << "  storage      " << precisionName(h.precision) << ", " << storedValues << " values, "
      << formatBytes(t.fileBytes) << " on disk\n"
      << "  relight cost " << h.latticeSize() << " multiply-adds of RGB triples per pixel (dense)\n"
      << positionsInWords(h, t.pixels, "precompute it again")
      << lampsInWords(h, t.pixels, "precompute it again") << materialsInWords(t.pixels)
      << labelsInWords(h, t.pixels, "precompute it again");
  return out.str();
}

}  // namespace acpca
