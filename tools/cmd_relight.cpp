// `adaptive-cpca relight`: transport (dense ground truth) + lightings -> images.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "cluster/model.h"
#include "precompute/transport/atomic_file.h"
#include "precompute/transport/error.h"
#include "relight/dense_relight.h"
#include "relight/evaluation.h"
#include "relight/image_output.h"
#include "relight/lighting.h"
#include "relight/model_relighter.h"
#include "relight/spec_parsing.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct RelightArgs {
  CommonOptions common;
  std::string input, out, format, background = "env", maxRank;
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

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string quoted = "\"";
  for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

/// Applies --max-rank: an integer K keeps each cluster's first K bases; a
/// fraction in (0, 1) or a percentage ("50%") keeps that share of each.
void applyMaxRank(const std::string& text, ModelRelighter& relighter) {
  if (text.empty()) return;
  const std::string what = concat("--max-rank '", text, "'");
  const bool percent = text.back() == '%';
  const double value = parseFiniteNumber(percent ? text.substr(0, text.size() - 1) : text, what);
  if (percent) {
    if (value < 0 || value > 100) throw UserError(concat(what, ": a percentage is 0..100"));
    relighter.setRankFraction(value / 100);
  } else if (value == std::floor(value)) {
    if (value < 0) throw UserError(concat(what, ": a rank is >= 0"));
    relighter.setMaxRank(static_cast<int>(std::min(value, 1e9)));
  } else {
    if (value < 0 || value > 1) throw UserError(concat(what, ": a fraction is in (0, 1)"));
    relighter.setRankFraction(value);
  }
}

/// What is relit: a transport file (dense ground truth) or a model.
struct RelightSource {
  TransportHeader header;
  std::string method;
  /// Bytes of model read per frame; for a transport, per pass over T (a pass
  /// relights a whole group of frames).
  long long bytesPerPass = 0;
  bool dense = false;
  /// Relights the group; ms[k] is the time spent on frame k.
  std::function<std::vector<std::vector<float>>(const std::vector<LatticeLighting>&,
                                                std::vector<double>& ms)>
      relight;
};

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

RelightSource openSource(const std::string& path, const std::string& maxRank) {
  RelightSource s;
  if (isModelFile(path)) {
    std::shared_ptr<ModelRelighter> relighter;
    {
      const Model model = readModel(path);
      s.method = model.method;
      relighter = std::make_shared<ModelRelighter>(model);
    }  // the relighter keeps its own packed copy
    applyMaxRank(maxRank, *relighter);
    s.header = relighter->geometry();
    s.bytesPerPass = relighter->bytesPerFrame();
    s.relight = [relighter](const std::vector<LatticeLighting>& l, std::vector<double>& ms) {
      std::vector<std::vector<float>> out;
      ms.clear();
      for (const auto& lighting : l) {
        const auto start = Clock::now();
        out.push_back(relighter->relight(lighting));
        ms.push_back(millisecondsSince(start));
      }
      return out;
    };
    return s;
  }
  if (!maxRank.empty())
    throw UserError(concat("--max-rank: '", path, "' is a transport file, which has no ranks"));
  auto transport = std::make_shared<TransportReader>(path);
  s.header = transport->header();
  s.method = "dense";
  s.dense = true;
  s.bytesPerPass = transport->rows() * static_cast<long long>(transport->latticeSize()) *
                   (transport->header().precision == Precision::F16 ? 2 : 4);
  s.relight = [transport](const std::vector<LatticeLighting>& l, std::vector<double>& ms) {
    const auto start = Clock::now();
    auto out = denseRelight(*transport, l);
    ms.assign(l.size(), millisecondsSince(start) / std::max<size_t>(1, l.size()));
    return out;
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
  const RelightSource source = openSource(a.input, a.maxRank);
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
    // Timing mode: one untimed warm-up, then --frames timed repeats.
    std::vector<double> ms;
    std::vector<std::vector<float>> results = source.relight(lightings, ms);
    std::vector<double> frameMs = ms;
    if (a.frames > 0) {
      frameMs.assign(count, 0.0);
      std::vector<std::vector<double>> repeats(count);
      for (int rep = 0; rep < a.frames; ++rep) {
        results = source.relight(lightings, ms);
        for (size_t k = 0; k < count; ++k) repeats[k].push_back(ms[k]);
        msPerFrame.insert(msPerFrame.end(), ms.begin(), ms.end());
      }
      for (size_t k = 0; k < count; ++k) frameMs[k] = median(repeats[k]);
    } else {
      msPerFrame.insert(msPerFrame.end(), ms.begin(), ms.end());
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
      const double ms = frameMs[k];
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
  const auto [lowest, highest] = std::minmax_element(msPerFrame.begin(), msPerFrame.end());
  const double fastest = msPerFrame.empty() ? 0 : *lowest,
               slowest = msPerFrame.empty() ? 0 : *highest;
  // Dense passes share one read of T among the frames of a group; the model is
  // read once per frame.
  const double bytesPerFrame = frames.empty() ? 0
                               : source.dense
                                   ? double(source.bytesPerPass) / std::min(kGroup, frames.size())
                                   : double(source.bytesPerPass);
  const double gbPerSecond = med > 0 ? bytesPerFrame / (med * 1e6) : 0;
  if (!a.common.quiet)
    std::cerr << "relit " << frames.size() << " frame(s) from " << a.input << " (" << source.method
              << "): " << msPerFrame.size() << " timed, median " << med << " ms/frame (min "
              << fastest << ", max " << slowest << "), " << formatBytes(bytesPerFrame)
              << " read per frame, " << gbPerSecond << " GB/s\n";
  nlohmann::json report = {{"input", a.input},
                           {"method", source.method},
                           {"frames", frames.size()},
                           {"timed_frames", msPerFrame.size()},
                           {"ms_per_frame_median", med},
                           {"ms_per_frame_min", fastest},
                           {"ms_per_frame_max", slowest},
                           {"bytes_per_frame", bytesPerFrame},
                           {"gb_per_s", gbPerSecond},
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
  sub->add_option("--frames", args->frames,
                  "Timing mode: after a warm-up, repeat the relight K times and report ms/frame");
  sub->add_option("--max-rank", args->maxRank,
                  "Models: use each cluster's first K bases, or a fraction (0.5 or 50%)");
  sub->add_flag("--fast-rotation", args->fastRotation,
                "Rotate by bilinear lookup on the lattice (fast, not energy-preserving)");
  sub->add_flag("--exr-float", args->exrFloat, "Write 32-bit float EXR instead of half");
  args->common.add(*sub);
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
