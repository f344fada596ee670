// `adaptive-cpca info`: what a transport (or model) file holds.
#include <filesystem>
#include <iostream>

#include "cluster/model_file.h"
#include "relight/file_info.h"
#include "tools/cli_common.h"
#include "tools/commands.h"
#include "transport/transport_file.h"

namespace acpca::cli {

namespace {

struct InfoArgs {
  std::string file, jsonPath;
};

void runModel(const InfoArgs& a) {
  const Model m = readModel(a.file);
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(a.file, ec);
  const nlohmann::json j = describeModel(m, a.file);
  if (!a.jsonPath.empty()) {
    writeJson(a.jsonPath, j);
    if (a.jsonPath == "-") return;
  }
  std::cout << a.file << ": " << m.method << " model of scene '" << m.geometry.scene << "'\n"
            << "  image        " << m.geometry.camera.size.width << "x"
            << m.geometry.camera.size.height << ", " << m.rows() << " occupied pixels\n"
            << "  lattice      6x" << m.geometry.cubemapResolution << "x"
            << m.geometry.cubemapResolution << ", N = " << m.globalBases() << " global bases"
            << (m.geometry.channels == 3 ? " over R, G and B rows" : "") << "\n"
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
  refuseOutputsOverInputs({a.file}, {a.jsonPath});
  if (isModelFile(a.file)) return runModel(a);
  const TransportReader t(a.file);
  const auto& h = t.header();
  const long long storedValues = t.rows() * static_cast<long long>(t.rowLength());
  const nlohmann::json j = describeTransport(t);
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
            << "  light        "
            << (h.bounces > 0
                    ? concat("direct and up to ", h.bounces, " bounce(s): ", h.indirectSamples,
                             " paths per traced sample, ",
                             h.indirectCacheCell > 0
                                 ? concat("visibility cache cell ", h.indirectCacheCell,
                                          " of the scene's extent")
                                 : std::string("exact visibility at every vertex"))
                    : std::string("direct"))
            << "\n"
            << "  rows         "
            << (h.channels == 3 ? "R, G and B side by side (3 x l values per pixel)"
                                : "one per pixel, shared by R, G and B")
            << "\n"
            << "  storage      " << precisionName(h.precision) << ", " << storedValues
            << " values, " << formatBytes(t.fileBytes()) << " on disk\n"
            << "  relight cost " << t.latticeSize()
            << " multiply-adds of RGB triples per pixel (dense)\n";
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
