#include "relight/batch_relight.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "cluster/model.h"
#include "cluster/model_file.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/input_guard.h"
#include "core/rank_gather.h"
#include "core/ranks.h"
#include "core/resources.h"
#include "core/statistics.h"
#include "core/stopwatch.h"
#include "core/table.h"
#include "core/text.h"
#include "relight/dense_relight.h"
#include "relight/image_output.h"
#include "relight/lighting.h"
#include "relight/model_relighter.h"
#include "relight/relight_source.h"
#include "relight/spec_parsing.h"

namespace acpca {

namespace {

namespace fs = std::filesystem;

/// One environment argument after expanding directories.
struct EnvInput {
  std::string spec;
  std::unique_ptr<Environment> env;
  std::string error;  // non-empty: could not be loaded
};

std::string extensionOf(ImageFormat f) {
  return f == ImageFormat::Exr ? ".exr" : ".png";
}

/// Refuses a batch whose frames, uncompressed in every format (an upper
/// bound), would not fit the disk.
void requireFrameSpace(const BatchRelightOptions& a, ImageSize size,
                       const std::vector<ImageFormat>& formats, bool batch) {
  const fs::path out(a.out);
  const long long pixels = static_cast<long long>(size.width) * size.height;
  const int channels = a.background == Background::Alpha ? 4 : 3;
  long long frameBytes = 0;
  for (ImageFormat f : formats)
    frameBytes += pixels * channels * (f == ImageFormat::Png ? 1 : a.exrFloat ? 4 : 2);
  ResourceNeed need;
  need.what =
      concat(a.envs.size() * a.rotations.size(), " frame(s) of ", size.width, "x", size.height);
  need.diskBytes = frameBytes * static_cast<long long>(a.envs.size() * a.rotations.size());
  need.largestFile = frameBytes;
  need.diskDirectory = batch ? a.out : (out.has_parent_path() ? out.parent_path().string() : ".");
  if (batch && !fs::exists(a.out)) need.diskDirectory = fs::path(a.out).parent_path().string();
  need.diskAdvice = "write fewer frames at once, or to another disk";
  requireResources(need, a.force);
}

/// Every lighting of the batch; in a batch, one that cannot be read is
/// skipped with a warning (and reported), otherwise its error stops the run.
std::vector<EnvInput> loadInputs(const std::vector<std::string>& specs, bool batch,
                                 const std::function<void(const std::string&)>& warn) {
  std::vector<EnvInput> inputs;
  for (const auto& spec : specs) {
    EnvInput in{spec, nullptr, ""};
    try {
      in.env = loadEnvironment(spec);
    } catch (const UserError& e) {
      if (!batch) throw;
      in.error = e.what();
      if (warn) warn(concat("skipping: ", e.what()));
    }
    inputs.push_back(std::move(in));
  }
  return inputs;
}

/// One group relit; in timing mode an untimed warm-up, then the timed
/// repeats (frameMs: each frame's median). Times that count go to msPerFrame
/// (rank 0's own here; the others' as they arrive).
std::vector<std::vector<float>> relightTimed(const RelightSource& source,
                                             const std::vector<LatticeLighting>& lightings,
                                             int timingRepeats, std::vector<double>& frameMs,
                                             std::vector<double>& msPerFrame) {
  const int rank = ranks::rank(), rankCount = ranks::count();
  const size_t count = lightings.size();
  std::vector<double> ms;
  std::vector<std::vector<float>> results = source.relight(lightings, ms);
  frameMs = ms;
  if (timingRepeats > 0) {
    frameMs.assign(count, 0.0);
    std::vector<std::vector<double>> repeats(count);
    for (int rep = 0; rep < timingRepeats; ++rep) {
      results = source.relight(lightings, ms);
      for (size_t k = 0; k < count; ++k) repeats[k].push_back(ms[k]);
      if (rankCount == 1) msPerFrame.insert(msPerFrame.end(), ms.begin(), ms.end());
    }
    for (size_t k = 0; k < count; ++k) frameMs[k] = median(repeats[k]);
    if (rankCount > 1 && rank == 0)
      msPerFrame.insert(msPerFrame.end(), frameMs.begin(), frameMs.end());
  } else if (rank == 0) {
    msPerFrame.insert(msPerFrame.end(), ms.begin(), ms.end());
  }
  return results;
}

/// The batch's times and bytes per frame, in words and as JSON.
void summarize(BatchRelightResult& result, const BatchRelightOptions& a,
               const RelightSource& source, size_t frames, std::vector<double> msPerFrame) {
  const double med = median(msPerFrame);
  const auto [lowest, highest] = std::minmax_element(msPerFrame.begin(), msPerFrame.end());
  const double fastest = msPerFrame.empty() ? 0 : *lowest,
               slowest = msPerFrame.empty() ? 0 : *highest;
  // Dense passes share one read of T among the frames of a group; the model is
  // read once per frame.
  const double bytesPerFrame = frames == 0 ? 0
                               : source.dense
                                   ? double(source.bytesPerPass) / std::min(kFramesPerGroup, frames)
                                   : double(source.bytesPerPass);
  const double gbPerSecond = med > 0 ? bytesPerFrame / (med * 1e6) : 0;
  result.summary =
      concat("relit ", frames, " frame(s) from ", a.input, " (", source.method,
             "): ", msPerFrame.size(), " timed, median ", med, " ms/frame (min ", fastest, ", max ",
             slowest, "), ", formatBytes(bytesPerFrame), " read per frame, ", gbPerSecond, " GB/s");
  result.method = source.method;
  result.frames = static_cast<long long>(frames);
  result.bytesPerFrame = bytesPerFrame;
  result.json = {{"input", a.input},
                 {"method", source.method},
                 {"frames", frames},
                 {"timed_frames", msPerFrame.size()},
                 {"ms_per_frame_median", med},
                 {"ms_per_frame_min", fastest},
                 {"ms_per_frame_max", slowest},
                 {"bytes_per_frame", bytesPerFrame},
                 {"gb_per_s", gbPerSecond}};
  result.msPerFrame = std::move(msPerFrame);
}

}  // namespace

void applyRankLimit(const std::string& text, ModelRelighter& relighter) {
  if (text.empty()) return;
  const bool percent = text.back() == '%';
  const double value =
      parseFiniteNumber(percent ? text.substr(0, text.size() - 1) : text, "maximum rank", text);
  if (percent) {
    if (value < 0 || value > 100)
      throw ParameterError("maximum rank", text, "a percentage is 0..100");
    relighter.setRankFraction(value / 100);
  } else if (value == std::floor(value)) {
    if (value < 0) throw ParameterError("maximum rank", text, "a rank is >= 0");
    relighter.setMaxRank(static_cast<int>(std::min(value, 1e9)));
  } else {
    if (value < 0 || value > 1)
      throw ParameterError("maximum rank", text, "a fraction is in (0, 1)");
    relighter.setRankFraction(value);
  }
}

std::vector<ImageFormat> imageFormatsFor(const std::string& format, const std::string& out,
                                         bool batch) {
  if (format == "both") return {ImageFormat::Exr, ImageFormat::Png};
  if (format == "exr") return {ImageFormat::Exr};
  if (format == "png") return {ImageFormat::Png};
  if (!format.empty()) throw ParameterError("image format", format, "is not exr, png or both");
  if (batch) return {ImageFormat::Exr};
  const std::string ext = fs::path(out).extension().string();
  if (ext == ".exr") return {ImageFormat::Exr};
  if (ext == ".png") return {ImageFormat::Png};
  throw ParameterError("output path", out,
                       "cannot tell the format from the extension; use .exr/.png or a format");
}

void validateBatchRelight(const BatchRelightOptions& a) {
  if (a.timingRepeats < 0) throw ParameterError("timing frames", a.timingRepeats, "must be >= 0");
  if (a.envs.empty()) throw ParameterError("environment", "", "give at least one lighting");
  if (a.rotations.empty()) throw ParameterError("rotation", "", "give at least one rotation");
  requireFinite(a.exposure, "exposure");
  const std::vector<ImageFormat> formats = imageFormatsFor(a.format, a.out, a.batch());
  // No frame may replace the model, the transport or a lighting it reads.
  std::vector<std::string> inputs = a.envs;
  inputs.push_back(a.input);
  if (a.batch()) {
    refuseDirectoryOverInputs(a.out, inputs);
    return;
  }
  const fs::path out(a.out);
  for (ImageFormat format : formats)
    refuseOutputOverInputs(
        formats.size() > 1
            ? (out.parent_path() / (out.stem().string() + extensionOf(format))).string()
            : a.out,
        inputs);
}

BatchRelightResult relightBatch(const BatchRelightOptions& a) {
  validateBatchRelight(a);
  const bool batch = a.batch();
  const fs::path out(a.out);
  const std::vector<ImageFormat> formats = imageFormatsFor(a.format, a.out, batch);
  const std::vector<EnvRotation>& rotations = a.rotations;
  const RelightSource source = openRelightSource(a.input, a.maxRank);
  const CubeLattice lattice(source.header.cubemapResolution);
  requireFrameSpace(a, source.header.camera.size, formats, batch);
  if (batch) createOutputDirectory(a.out);

  const std::vector<EnvInput> inputs = loadInputs(a.envs, batch, a.warn);

  // Frames in groups: each group streams T once; memory stays flat for any count.
  struct Frame {
    const EnvInput* input;
    EnvRotation rotation;
  };
  std::vector<Frame> frames;
  for (const auto& in : inputs)
    if (in.env)
      for (const auto& r : rotations) frames.push_back({&in, r});
  // No times in the manifest: equal runs write equal files (frame times go
  // to the JSON report).
  Table manifest({"input", "env", "yaw", "pitch", "roll", "exposure", "output"});
  std::vector<double> msPerFrame;
  nlohmann::json outputs = nlohmann::json::array();
  // Rank 0 writes every frame (images, manifest row), in frame order.
  const auto writeFrame = [&](size_t i, const Image& image, double ms) {
    const Frame& f = frames[i];
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
    std::string joined;
    for (const auto& p : paths) joined += (joined.empty() ? "" : ";") + p;
    manifest.add({a.input, f.input->spec, f.rotation.yaw, f.rotation.pitch, f.rotation.roll,
                  a.exposure, joined});
    outputs.push_back({{"env", f.input->spec},
                       {"yaw", f.rotation.yaw},
                       {"pitch", f.rotation.pitch},
                       {"roll", f.rotation.roll},
                       {"paths", paths},
                       {"ms", ms}});
    if (a.progress)
      a.progress(static_cast<long long>(i + 1), static_cast<long long>(frames.size()));
  };
  // Under mpirun -np K frame i goes to rank i mod K; rank 0 takes each
  // composed image (and its time) in frame order (a sender waits its turn, so
  // memory stays bounded): the same files for any K.
  const int rank = ranks::rank();
  const int channels = ImageComposer::channels(a.background);
  // Another rank's frame arrives with its time as one more value; rank 0's
  // own frames come as they are (no copy of the image to append it), their
  // time in ownMs.
  double ownMs = 0;
  const auto deliver = [&](long long i, std::vector<float>& pixels) {
    const bool own = ranks::ownerOf(i) == 0;
    ACPCA_CHECK(own || !pixels.empty(), "frame ", i, " arrived empty");
    const double ms = own ? ownMs : pixels.back();
    if (!own) pixels.pop_back(), msPerFrame.push_back(ms);  // rank 0's own are counted below
    const Image image{source.header.camera.size.width, source.header.camera.size.height, channels,
                      std::move(pixels)};
    writeFrame(static_cast<size_t>(i), image, ms);
  };
  ranks::Gather<float> gather(static_cast<long long>(frames.size()), ranks::GatherOrder::ItemOrder,
                              deliver);
  std::vector<size_t> mine;
  for (long long i : ranks::itemsOfThisRank(static_cast<long long>(frames.size())))
    mine.push_back(static_cast<size_t>(i));
  const auto lightingOf = [&](size_t k) {
    const Frame& f = frames[mine[k]];
    return computeLighting(*f.input->env, lattice, f.rotation, a.rotationMode);
  };
  relightInGroups(
      mine.size(), lightingOf, [&](size_t g, const std::vector<LatticeLighting>& lightings) {
        const size_t count = lightings.size();
        std::vector<double> frameMs;
        const std::vector<std::vector<float>> results =
            relightTimed(source, lightings, a.timingRepeats, frameMs, msPerFrame);
        for (size_t k = 0; k < count; ++k) {
          const size_t i = mine[g + k];
          Image image = composeImage(source.header, results[k], a.background, *frames[i].input->env,
                                     rotationMatrix(frames[i].rotation));
          if (rank == 0)
            ownMs = frameMs[k];
          else
            image.pixels.push_back(static_cast<float>(frameMs[k]));
          gather.put(static_cast<long long>(i), image.pixels);
        }
      });
  gather.finish();
  if (rank != 0) {  // rank 0 wrote the images and reports
    BatchRelightResult result;
    result.method = source.method;
    result.frames = static_cast<long long>(frames.size());
    return result;
  }
  if (batch) manifest.writeCsv((out / "manifest.csv").string());

  BatchRelightResult result;
  std::vector<std::string>& failed = result.failed;
  for (const auto& in : inputs)
    if (!in.env) failed.push_back(in.error);
  summarize(result, a, source, frames.size(), std::move(msPerFrame));
  result.json["outputs"] = outputs;
  result.json["failed"] = failed;
  return result;
}

}  // namespace acpca
