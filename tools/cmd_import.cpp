// `adaptive-cpca import`: a one-light-at-a-time image set and its lights file
// -> a transport file over the light set (docs/formats.md, "Captured transport").
#include <filesystem>
#include <iostream>

#include "capture/lights_file.h"
#include "capture/olat_import.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

namespace fs = std::filesystem;

struct ImportArgs {
  CommonOptions common;
  std::string lights, out, mask, precision = "f16";
  bool linear = false, srgb = false;
  double capDegrees = 0;
  bool force = false;
};

void run(const ImportArgs& a) {
  const LightsFile file = readLightsFile(a.lights);
  std::vector<std::string> paths;
  OlatLights lights;
  for (const LightEntry& e : file.lights) {
    paths.push_back(e.imagePath);
    lights.directions.push_back(e.direction);
    lights.irradiance.push_back(e.irradiance);
    if (file.cellsGiven()) lights.solidAngles.push_back(e.solidAngle);
  }
  std::vector<std::string> inputs = paths;
  inputs.push_back(a.lights);
  if (!a.mask.empty()) inputs.push_back(a.mask);
  refuseOutputsOverInputs(inputs, {a.out, a.common.jsonPath});
  if (!a.common.quiet) warnOfUnlistedImages(file);

  OlatImportOptions o;
  o.out = a.out;
  o.mask = a.mask;
  o.precision = parsePrecision(a.precision);
  o.capDegrees = a.capDegrees;
  o.force = a.force;
  o.name = fs::path(a.lights).stem().string();
  ThreadLimit limit(a.common.threads);
  const auto images = openImageFiles(paths, a.linear ? TransferFunction::Linear
                                            : a.srgb ? TransferFunction::Srgb
                                                     : TransferFunction::Auto);
  Progress progress("import " + o.name, "image rows", a.common.quiet);
  o.progress = [&](long long done, long long total) { progress.update(done, total); };
  const OlatImportResult r = importOlat(*images, lights, o);
  progress.finish();
  const TransportHeader& h = r.header;
  if (!a.common.quiet)
    std::cerr << "wrote " << a.out << ": " << h.lights.describe() << ", " << h.rows()
              << " covered pixels of " << h.camera.size.width << "x" << h.camera.size.height << ", "
              << (h.channels == 3 ? "RGB" : "grey") << " rows, "
              << formatBytes(double(r.bytesWritten)) << " in " << r.seconds << " s\n";
  nlohmann::json report = importReport(r, a.out);
  report["peak_memory_bytes"] = peakMemoryBytes();
  writeJson(a.common.jsonPath, report);
}

}  // namespace

void registerImport(CLI::App& app) {
  auto args = std::make_shared<ImportArgs>();
  auto* sub = app.add_subcommand(
      "import", "Make a transport file of a captured one-light-at-a-time image set");
  sub->add_option("lights", args->lights,
                  "Lights file (JSON or CSV): each light's image, direction and intensity")
      ->required();
  sub->add_option("--out", args->out, "Transport file to write (HDF5)")->required();
  sub->add_option("--mask", args->mask,
                  "Coverage image: its alpha (or first) channel, 0 = background; default: pixels "
                  "black in every image are background");
  auto* linear = sub->add_flag("--linear", args->linear,
                               "Take 8/16-bit images as linear values (default: sRGB-decoded)");
  sub->add_flag("--srgb", args->srgb, "sRGB-decode every image, floating-point ones too")
      ->excludes(linear);
  sub->add_option("--cell-cap", args->capDegrees,
                  "Largest angle (degrees) a light's cell reaches from it; default: the largest "
                  "angle from a light to its nearest neighbour")
      ->check(CLI::Range(0.0, 180.0));
  sub->add_option("--precision", args->precision, "Stored precision: f16 or f32");
  sub->add_flag("--force", args->force, "Import even when the rows may not fit memory or the disk");
  args->common.add(*sub);
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
