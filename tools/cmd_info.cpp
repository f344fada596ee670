// `adaptive-cpca info`: what a transport (or model) file holds.
#include <filesystem>
#include <iostream>

#include "cluster/model_file.h"
#include "precompute/transport/transport_file.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct InfoArgs {
  std::string file, jsonPath;
};

void runModel(const InfoArgs& a) {
  const Model m = readModel(a.file);
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(a.file, ec);
  const nlohmann::json j = {{"kind", "model"},
                            {"width", m.geometry.camera.size.width},
                            {"height", m.geometry.camera.size.height},
                            {"occupied_pixels", m.rows()},
                            {"cubemap", m.geometry.cubemapResolution},
                            {"global_bases", m.globalBases()},
                            {"clusters", m.clusters()},
                            {"cost_per_pixel", m.costPerPixel()},
                            {"total_cost", m.totalCost()},
                            {"bytes", ec ? -1 : static_cast<long long>(bytes)},
                            {"bytes_per_frame", m.frameBytes()},
                            {"method", m.method},
                            {"coeffs", coeffPrecisionName(m.precision)},
                            {"bases", coeffPrecisionName(m.basisPrecision)},
                            {"transport_error", m.transportError},
                            {"rank_histogram", rankHistogramJson(m)},
                            {"settings", nlohmann::json::parse(m.settings, nullptr, false)}};
  if (!a.jsonPath.empty()) {
    writeJson(a.jsonPath, j);
    if (a.jsonPath == "-") return;
  }
  std::cout << a.file << ": " << m.method << " model of scene '" << m.geometry.scene << "'\n"
            << "  image        " << m.geometry.camera.size.width << "x"
            << m.geometry.camera.size.height << ", " << m.rows() << " occupied pixels\n"
            << "  lattice      6x" << m.geometry.cubemapResolution << "x"
            << m.geometry.cubemapResolution << ", N = " << m.globalBases() << " global bases\n"
            << "  clusters     " << m.clusters() << (m.hasMean ? " (with means)" : "") << ", ranks "
            << rankSummary(m) << "\n"
            << "  cost         " << m.totalCost() << " multiply-adds per frame, "
            << m.costPerPixel() << " per pixel\n"
            << "  storage      " << coeffPrecisionName(m.precision) << " coefficients, "
            << coeffPrecisionName(m.basisPrecision) << " bases, " << formatBytes(m.frameBytes())
            << " read per frame, " << formatBytes(double(bytes)) << " on disk\n"
            << "  error        " << m.transportError << " relative to T (Frobenius)\n";
}

void run(const InfoArgs& a) {
  if (isModelFile(a.file)) return runModel(a);
  const TransportReader t(a.file);
  const auto& h = t.header();
  const long long storedValues = t.rows() * static_cast<long long>(t.latticeSize());
  const auto vec3 = [](const Vec3& v) { return nlohmann::json{v.x(), v.y(), v.z()}; };
  const nlohmann::json j = {{"kind", "transport"},
                            {"camera",
                             {{"eye", vec3(h.camera.eye)},
                              {"target", vec3(h.camera.target)},
                              {"up", vec3(h.camera.up)},
                              {"fov", h.camera.fovDegrees}}},
                            {"width", h.camera.size.width},
                            {"height", h.camera.size.height},
                            {"occupied_pixels", t.rows()},
                            {"cubemap", h.cubemapResolution},
                            {"directions", t.latticeSize()},
                            {"global_bases", nullptr},
                            {"clusters", nullptr},
                            {"cost_per_pixel", t.latticeSize()},
                            {"bytes", t.fileBytes()},
                            {"method", "dense"},
                            {"scene", h.scene},
                            {"precision", precisionName(h.precision)},
                            {"spp", h.samplesPerPixel},
                            {"texel_rays", h.texelRays},
                            {"stored_values", storedValues}};
  if (!a.jsonPath.empty()) {
    writeJson(a.jsonPath, j);
    if (a.jsonPath == "-") return;
  }
  std::cout << a.file << ": transport of scene '" << h.scene << "'\n"
            << "  image        " << h.camera.size.width << "x" << h.camera.size.height << ", "
            << t.rows() << " occupied pixels (" << 100.0 * t.rows() / h.camera.size.pixels()
            << "%)\n"
            << "  lattice      6x" << h.cubemapResolution << "x" << h.cubemapResolution << " = "
            << t.latticeSize() << " directions\n"
            << "  sampling     " << h.samplesPerPixel << " sample(s) per pixel, " << h.texelRays
            << " ray(s) per texel\n"
            << "  storage      " << precisionName(h.precision) << ", " << storedValues
            << " values, " << formatBytes(t.fileBytes()) << " on disk\n"
            << "  relight cost " << t.latticeSize() << " multiply-adds per pixel (dense)\n";
}

}  // namespace

void registerInfo(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  auto* sub = app.add_subcommand("info", "Describe a transport or model file");
  sub->add_option("file", args->file, "Transport or model file")->required();
  sub->add_option("--json", args->jsonPath, "Write the description as JSON to FILE (- for stdout)");
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
