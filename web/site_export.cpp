#include "web/site_export.h"

#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/half.h"
#include "lighting/builtin_maps.h"
#include "lighting/environment.h"
#include "model/model_file.h"
#include "web/page_assets.h"
#include "web/site_files.h"

namespace acpca {

namespace {

namespace fs = std::filesystem;

/// model.bin: arrays one after another, each at a multiple of 8 bytes so
/// that the page views it as a typed array in place; model.json names them.
class PackedArrays {
 public:
  template <typename T>
  void add(const std::string& name, const std::string& type, const std::vector<T>& values) {
    bytes_.resize((bytes_.size() + 7) / 8 * 8, 0);
    index_[name] = {{"type", type}, {"offset", bytes_.size()}, {"count", values.size()}};
    const auto* first = reinterpret_cast<const unsigned char*>(values.data());
    bytes_.insert(bytes_.end(), first, first + values.size() * sizeof(T));
  }
  const std::vector<unsigned char>& bytes() const { return bytes_; }
  const nlohmann::json& index() const { return index_; }

 private:
  std::vector<unsigned char> bytes_;
  nlohmann::json index_ = nlohmann::json::object();
};

/// The lattice texels some pixel sees: those where a row of V_g is not zero
/// in any channel. The page projects a lighting over these alone.
std::vector<std::int32_t> seenTexels(const Model& model) {
  const int l = model.geometry.latticeSize(), channels = model.geometry.channels;
  std::vector<std::int32_t> seen;
  for (int j = 0; j < l; ++j) {
    bool any = false;
    for (int c = 0; c < channels && !any; ++c)
      any = model.globalBasis.row(static_cast<Eigen::Index>(c) * l + j).any();
    if (any) seen.push_back(j);
  }
  return seen;
}

std::vector<std::uint16_t> asHalves(const float* values, size_t count) {
  std::vector<std::uint16_t> halves(count);
  floatToHalfIeee(values, halves.data(), count);
  return halves;
}

/// Adds the model's arrays at the active ranks, rows in cluster order.
void packModel(const Model& model, const std::vector<int>& ranks,
               const std::vector<std::int32_t>& seen, PackedArrays& arrays) {
  const int n = model.globalBases(), l = model.geometry.latticeSize();
  const int channels = model.geometry.channels;
  const size_t width = channels * seen.size();
  // V_g column by column over the seen texels (channel c's at c S + s).
  std::vector<float> basis(width * n);
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < channels; ++c)
      for (size_t s = 0; s < seen.size(); ++s)
        basis[k * width + c * seen.size() + s] =
            model.globalBasis(static_cast<Eigen::Index>(c) * l + seen[s], k);
  arrays.add("seen_texels", "i32", seen);
  arrays.add("global_basis", "f32", basis);
  std::vector<std::int32_t> rowsOf(model.clusters());
  std::vector<float> bases, scale, albedo, coverage;
  std::vector<std::int32_t> rowPixel;
  std::vector<float> coeffF32;
  std::vector<std::uint16_t> coeffF16;
  std::vector<std::int8_t> coeffI8;
  for (int c = 0; c < model.clusters(); ++c) {
    const ClusterValues v = model.clusterValues(c);
    const int r = ranks[c];
    rowsOf[c] = static_cast<std::int32_t>(v.rows);
    bases.insert(bases.end(), v.bases, v.bases + static_cast<size_t>(r) * n);
    scale.insert(scale.end(), v.scale, v.scale + r);
    for (long long row = 0; row < v.rows; ++row) {
      const long long at = row * v.rank;
      if (v.precision == CoeffPrecision::I8) {
        const auto* q = static_cast<const std::int8_t*>(v.coefficients) + at;
        coeffI8.insert(coeffI8.end(), q, q + r);
      } else if (v.precision == CoeffPrecision::F16) {
        const auto* h = static_cast<const std::uint16_t*>(v.coefficients) + at;
        coeffF16.insert(coeffF16.end(), h, h + r);
      } else {
        const auto* f = static_cast<const float*>(v.coefficients) + at;
        coeffF32.insert(coeffF32.end(), f, f + r);
      }
      const std::int32_t p = model.clusterRows[model.rowOffsets[c] + row];
      rowPixel.push_back(model.geometry.pixels[p]);
      for (int ch = 0; ch < 3; ++ch) albedo.push_back(model.geometry.albedo[3 * p + ch]);
      coverage.push_back(model.geometry.coverage[p]);
    }
  }
  std::vector<std::int32_t> active(ranks.begin(), ranks.end());
  arrays.add("cluster_rank", "i32", active);
  arrays.add("cluster_rows", "i32", rowsOf);
  const bool halfBases = model.basisPrecision == CoeffPrecision::F16;
  // Half bases hold half-representable values: converted back exactly.
  if (halfBases) {
    arrays.add("bases", "f16", asHalves(bases.data(), bases.size()));
    if (model.hasMean) arrays.add("means", "f16", asHalves(model.means.data(), model.means.size()));
  } else {
    arrays.add("bases", "f32", bases);
    if (model.hasMean) arrays.add("means", "f32", model.means);
  }
  arrays.add("coefficient_scale", "f32", scale);
  if (model.precision == CoeffPrecision::I8) arrays.add("coefficients", "i8", coeffI8);
  if (model.precision == CoeffPrecision::F16) arrays.add("coefficients", "f16", coeffF16);
  if (model.precision == CoeffPrecision::F32) arrays.add("coefficients", "f32", coeffF32);
  arrays.add("row_pixel", "i32", rowPixel);
  arrays.add("albedo", "f32", albedo);
  arrays.add("coverage", "f32", coverage);
}

nlohmann::json vec(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

/// The numbers the page's integration of the built-in maps and of map files
/// takes from lighting/builtin_maps.h, named once there.
nlohmann::json integrationConstants() {
  return {{"sky_sun",
           {{"theta", kSkySunTheta},
            {"phi", kSkySunPhi},
            {"size", kSkySunSize},
            {"radiance", kSkySunRadiance}}},
          {"sky_zenith", kSkyZenith},
          {"sky_horizon", kSkyHorizon},
          {"sky_ground", kSkyGround},
          {"sky_glow_colour", kSkyGlowColour},
          {"sky_glow_strength", kSkyGlowStrength},
          {"sky_glow_sharpness", kSkyGlowSharpness},
          {"sky_horizon_power", kSkyHorizonPower},
          {"sky_sub_cells", kSkySubCells},
          {"disc_rings_per_texel", kDiscRingsPerTexel},
          {"min_disc_rings", kMinDiscRings},
          {"max_disc_rings", kMaxDiscRings},
          {"map_sub_cells_per_texel", kMapSubCellsPerTexel},
          {"latlong_aspect_tolerance", kLatLongAspectTolerance},
          {"max_map_pixels", kMaxMapPixels}};
}

/// Each map's entry in the page's list; a lat-long file's pixels written
/// beside it as float32 RGB, as the CLI reads them (checked, ringing clamped).
nlohmann::json exportMaps(const std::vector<std::string>& specs, SiteWriter& site,
                          WebExportReport& report) {
  nlohmann::json maps = nlohmann::json::array();
  for (const std::string& spec : expandEnvironmentSpecs(specs)) {
    const std::unique_ptr<Environment> env = loadEnvironment(spec);
    if (isAnalyticEnvironment(spec)) {
      maps.push_back({{"name", env->name()}, {"spec", spec}});
      continue;
    }
    const LatLongPixels* pixels = env->latLong();
    if (!pixels)
      throw UserError(concat(spec,
                             ": the page integrates lat-long maps (2:1) only; write this cube "
                             "cross as a lat-long map first"));
    const std::string file = concat("maps/map-", maps.size(), ".bin");
    const size_t bytes = sizeof(float) * 3 * static_cast<size_t>(pixels->width) * pixels->height;
    site.write(file, pixels->rgb, bytes);
    report.mapBytes += static_cast<long long>(bytes);
    maps.push_back({{"name", env->name()},
                    {"spec", fs::path(spec).filename().string()},
                    {"width", pixels->width},
                    {"height", pixels->height},
                    {"file", file}});
  }
  return maps;
}

}  // namespace

WebExportReport exportWebPage(const WebExportOptions& options) {
  if (!isModelFile(options.model))
    throw UserError(concat(options.model,
                           ": not a model file; the page relights a model (compress or build "
                           "makes one)"));
  refuseForeignSiteFiles(options.out);
  const Model model = readModel(options.model);
  const TransportHeader& g = model.geometry;
  if (g.isLightSet())
    throw UserError(concat(options.model,
                           ": a captured light set has no camera or lattice for the page to "
                           "relight it under a map"));
  WebExportReport report;
  const std::vector<int> ranks = options.maxRank.activeRanks(model.ranks);
  const std::vector<std::int32_t> seen = seenTexels(model);
  report.seenTexels = static_cast<int>(seen.size());
  report.latticeTexels = g.latticeSize();
  PackedArrays arrays;
  packModel(model, ranks, seen, arrays);

  SiteWriter site(options.out);
  for (const PageAsset& asset : pageAssets()) site.write(asset.name, asset.bytes, asset.size);
  const nlohmann::json maps = exportMaps(
      options.envs.empty() ? std::vector<std::string>{"sky"} : options.envs, site, report);
  site.write("model.bin", arrays.bytes().data(), arrays.bytes().size());
  report.modelBytes = static_cast<long long>(arrays.bytes().size());
  const std::string name = fs::path(options.model).filename().string();
  const nlohmann::json manifest = {{"format", "adaptive-cpca web model"},
                                   {"version", 1},
                                   {"title", options.title.empty() ? name : options.title},
                                   {"source", name},
                                   {"method", model.method},
                                   {"max_rank", options.maxRank.text()},
                                   {"width", g.camera.size.width},
                                   {"height", g.camera.size.height},
                                   {"camera",
                                    {{"eye", vec(g.camera.eye)},
                                     {"target", vec(g.camera.target)},
                                     {"up", vec(g.camera.up)},
                                     {"fov_degrees", g.camera.fovDegrees}}},
                                   {"cubemap", g.cubemapResolution},
                                   {"channels", g.channels},
                                   {"global_bases", model.globalBases()},
                                   {"has_mean", model.hasMean},
                                   {"rows", g.rows()},
                                   {"arrays", arrays.index()},
                                   {"lighting", integrationConstants()},
                                   {"maps", maps}};
  site.write("model.json", manifest.dump(1) + "\n");
  site.finish();
  report.pageBytes = site.bytes();
  report.files = site.files();
  return report;
}

}  // namespace acpca
