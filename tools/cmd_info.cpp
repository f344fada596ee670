// `adaptive-cpca info`: what a transport (or model) file holds.
#include <iostream>

#include "precompute/transport/transport_file.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct InfoArgs {
  std::string file, jsonPath;
};

void run(const InfoArgs& a) {
  const TransportReader t(a.file);
  const auto& h = t.header();
  const long long storedValues = t.rows() * static_cast<long long>(t.latticeSize());
  const nlohmann::json j = {{"kind", "transport"},
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
