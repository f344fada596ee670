// `adaptive-cpca relight`: transport (dense ground truth) + lightings -> images.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "cluster/model.h"
#include "precompute/transport/atomic_file.h"
#include "precompute/transport/error.h"
#include "relight/dense_relight.h"
#include "relight/image_output.h"
#include "relight/lighting.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct RelightArgs {
  CommonOptions common;
  std::string input, out, format, background = "env";
  std::vector<std::string> envs, rotations;
  double exposure = 0;
  int frames = 0;
  bool fastRotation = false, exrFloat = false;
};

/// One environment argument after expanding directories.
struct EnvInput {
  std::string spec;
  std::unique_ptr<Environment> env;
  std::string error;  // non-empty: could not be loaded
};

bool isImageFile(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext == ".exr" || ext == ".hdr" || ext == ".pfm" || ext == ".tif" || ext == ".tiff";
}

std::vector<std::string> expandEnvironments(const std::vector<std::string>& specs) {
  std::vector<std::string> out;
  for (const auto& spec : specs) {
    if (!isAnalyticEnvironment(spec) && fs::is_directory(spec)) {
      std::vector<std::string> files;
      for (const auto& entry : fs::directory_iterator(spec))
        if (entry.is_regular_file() && isImageFile(entry.path()))
          files.push_back(entry.path().string());
      if (files.empty())
        throw UserError(concat("--env '", spec, "': the directory holds no .exr/.hdr maps"));
      std::sort(files.begin(), files.end());
      out.insert(out.end(), files.begin(), files.end());
    } else {
      out.push_back(spec);
    }
  }
  return out;
}

std::vector<ImageFormat> formatsFor(const std::string& format, const fs::path& out, bool batch) {
  if (format == "both") return {ImageFormat::Exr, ImageFormat::Png};
  if (format == "exr") return {ImageFormat::Exr};
  if (format == "png") return {ImageFormat::Png};
  if (!format.empty()) throw UserError(concat("--format '", format, "' is not exr, png or both"));
  if (batch) return {ImageFormat::Exr};
  const std::string ext = out.extension().string();
  if (ext == ".exr") return {ImageFormat::Exr};
  if (ext == ".png") return {ImageFormat::Png};
  throw UserError(
      concat("--out '", out.string(),
             "': cannot tell the format from the extension; use .exr/.png or --format"));
}

std::string extensionOf(ImageFormat f) {
  return f == ImageFormat::Exr ? ".exr" : ".png";
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string quoted = "\"";
  for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

/// What is relit: a transport file (dense ground truth) or a model.
struct RelightSource {
  TransportHeader header;
  std::string method;
  long long bytesPerPass = 0;  ///< bytes of transport or model read per pass
  std::function<std::vector<std::vector<float>>(const std::vector<LatticeLighting>&)> relight;
};

RelightSource openSource(const std::string& path) {
  RelightSource s;
  if (isModelFile(path)) {
    auto model = std::make_shared<Model>(readModel(path));
    s.header = model->geometry;
    s.method = model->method;
    s.bytesPerPass = model->frameBytes();
    s.relight = [model](const std::vector<LatticeLighting>& l) {
      return relightModelReference(*model, l);
    };
    return s;
  }
  auto transport = std::make_shared<TransportReader>(path);
  s.header = transport->header();
  s.method = "dense";
  s.bytesPerPass = transport->rows() * static_cast<long long>(transport->latticeSize()) *
                   (transport->header().precision == Precision::F16 ? 2 : 4);
  s.relight = [transport](const std::vector<LatticeLighting>& l) {
    return denseRelight(*transport, l);
  };
  return s;
}

void run(const RelightArgs& a) {
  // Validate everything cheap first.
  const Background background = parseBackground(a.background);
  std::vector<EnvRotation> rotations;
  for (const auto& spec : a.rotations) {
    const auto parsed = parseRotationSpec(spec);
    rotations.insert(rotations.end(), parsed.begin(), parsed.end());
  }
  if (rotations.empty()) rotations.push_back({});
  if (a.frames < 0) throw UserError("--frames must be >= 0");
  const std::vector<std::string> specs = expandEnvironments(a.envs);
  const bool batch = specs.size() > 1 || rotations.size() > 1;
  const fs::path out(a.out);
  const std::vector<ImageFormat> formats = formatsFor(a.format, out, batch);
  const RotationMode mode = a.fastRotation ? RotationMode::FastLattice : RotationMode::Exact;

  ThreadLimit limit(a.common.threads);
  const RelightSource source = openSource(a.input);
  const CubeLattice lattice(source.header.cubemapResolution);
  if (batch) {
    std::error_code ec;
    fs::create_directories(out, ec);
    if (!fs::is_directory(out))
      throw UserError(concat("--out '", a.out, "': cannot create the output directory"));
  }

  std::vector<EnvInput> inputs;
  for (const auto& spec : specs) {
    EnvInput in{spec, nullptr, ""};
    try {
      in.env = loadEnvironment(spec);
    } catch (const UserError& e) {
      if (!batch) throw;
      in.error = e.what();
      std::cerr << "adaptive-cpca: skipping: " << e.what() << "\n";
    }
    inputs.push_back(std::move(in));
  }

  // Frames in groups: each group streams T once; memory stays flat for any count.
  struct Frame {
    const EnvInput* input;
    EnvRotation rotation;
  };
  std::vector<Frame> frames;
  for (const auto& in : inputs)
    if (in.env)
      for (const auto& r : rotations) frames.push_back({&in, r});
  constexpr size_t kGroup = 32;
  std::vector<std::string> manifest;
  std::vector<double> msPerFrame;
  nlohmann::json outputs = nlohmann::json::array();
  Progress progress("relight", "frames", a.common.quiet);
  for (size_t g = 0; g < frames.size(); g += kGroup) {
    const size_t count = std::min(kGroup, frames.size() - g);
    std::vector<LatticeLighting> lightings;
    for (size_t k = 0; k < count; ++k)
      lightings.push_back(
          computeLighting(*frames[g + k].input->env, lattice, frames[g + k].rotation, mode));
    std::vector<std::vector<float>> results;
    const int repeats = std::max(1, a.frames);
    for (int rep = 0; rep < repeats; ++rep) {
      const auto start = Clock::now();
      results = source.relight(lightings);
      const double ms = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
      msPerFrame.push_back(ms / count);
    }
    for (size_t k = 0; k < count; ++k) {
      const Frame& f = frames[g + k];
      const Image image = composeImage(source.header, results[k], background, *f.input->env,
                                       rotationMatrix(f.rotation));
      std::vector<std::string> paths;
      for (ImageFormat format : formats) {
        fs::path path = out;
        if (batch)
          path = out / (f.input->env->name() + "_" + f.rotation.label() + extensionOf(format));
        else if (formats.size() > 1)
          path = out.parent_path() / (out.stem().string() + extensionOf(format));
        writeImage(image, path.string(), format, a.exposure, a.exrFloat);
        paths.push_back(path.string());
      }
      const double ms = msPerFrame.back();
      std::string joined;
      for (const auto& p : paths) joined += (joined.empty() ? "" : ";") + p;
      manifest.push_back(concat(csvField(a.input), ",", csvField(f.input->spec), ",",
                                f.rotation.yaw, ",", f.rotation.pitch, ",", f.rotation.roll, ",",
                                a.exposure, ",", csvField(joined), ",", ms));
      outputs.push_back({{"env", f.input->spec},
                         {"yaw", f.rotation.yaw},
                         {"pitch", f.rotation.pitch},
                         {"roll", f.rotation.roll},
                         {"paths", paths}});
    }
    progress.update(static_cast<long long>(g + count), static_cast<long long>(frames.size()));
  }
  progress.finish();

  if (batch) {
    AtomicOutput file((out / "manifest.csv").string());
    {
      std::ofstream csv(file.tempPath());
      csv << "input,env,yaw,pitch,roll,exposure,output,ms\n";
      for (const auto& line : manifest) csv << line << "\n";
      if (!csv) throw UserError(concat(file.finalPath(), ": cannot write the manifest"));
    }
    file.commit();
  }

  std::vector<std::string> failed;
  for (const auto& in : inputs)
    if (!in.env) failed.push_back(in.error);
  const double med = median(msPerFrame);
  // Dense passes share one read of T among the frames of a group; the model's
  // reference relight reads the model once per frame.
  const double bytesPerFrame = frames.empty() ? 0
                               : source.method == "dense"
                                   ? double(source.bytesPerPass) / std::min(kGroup, frames.size())
                                   : double(source.bytesPerPass);
  if (!a.common.quiet)
    std::cerr << "relit " << frames.size() << " frame(s) from " << a.input << " (" << source.method
              << "): median " << med << " ms/frame (" << formatBytes(bytesPerFrame)
              << " read per frame)\n";
  nlohmann::json report = {
      {"input", a.input},
      {"method", "dense"},
      {"frames", frames.size()},
      {"ms_per_frame_median", med},
      {"ms_per_frame_min",
       msPerFrame.empty() ? 0 : *std::min_element(msPerFrame.begin(), msPerFrame.end())},
      {"ms_per_frame_max",
       msPerFrame.empty() ? 0 : *std::max_element(msPerFrame.begin(), msPerFrame.end())},
      {"bytes_per_frame", bytesPerFrame},
      {"gb_per_s", med > 0 ? bytesPerFrame / (med * 1e6) : 0},
      {"outputs", outputs},
      {"failed", failed}};
  writeJson(a.common.jsonPath, report);
  if (!failed.empty()) {
    std::string list;
    for (const auto& f : failed) list += "\n  " + f;
    throw UserError(concat(failed.size(), " of ", inputs.size(),
                           " environment maps could not be used (the others were written):", list));
  }
}

}  // namespace

void registerRelight(CLI::App& app) {
  auto args = std::make_shared<RelightArgs>();
  auto* sub = app.add_subcommand(
      "relight", "Relight a model, or a transport file (dense ground truth), under lightings");
  sub->add_option("input", args->input, "Model (M_FILE) or transport file (T_FILE)")->required();
  sub->add_option("--env", args->envs,
                  "Lighting: image (.exr/.hdr lat-long), directory of them, constant:V, "
                  "sun:THETA,PHI,SIZE_DEG,INTENSITY or sky (repeatable)")
      ->required();
  sub->add_option("--out", args->out, "Output image, or directory for several")->required();
  sub->add_option("--rotate", args->rotations,
                  "YAW[,PITCH,ROLL] or a yaw sweep A:B:S (repeatable)");
  sub->add_option("--exposure", args->exposure, "Exposure in stops applied to the outputs");
  sub->add_option("--format", args->format, "exr, png or both (default: from --out, exr in batch)");
  sub->add_option("--background", args->background, "env, black or alpha");
  sub->add_option("--frames", args->frames, "Repeat the relight K times and report ms/frame");
  sub->add_flag("--fast-rotation", args->fastRotation,
                "Rotate by bilinear lookup on the lattice (fast, not energy-preserving)");
  sub->add_flag("--exr-float", args->exrFloat, "Write 32-bit float EXR instead of half");
  args->common.add(*sub);
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
