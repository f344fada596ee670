#include "eval/relight_benchmark.h"

#include <algorithm>
#include <cstdio>
#include <functional>
#include <optional>

#include "core/error.h"
#include "core/statistics.h"
#include "core/stopwatch.h"
#include "core/text.h"
#include "eval/error_measures.h"
#include "eval/sparse_transport.h"
#include "lighting/domain_lighting.h"
#include "lighting/lighting.h"
#include "model/model.h"
#include "model/model_file.h"
#include "relight/memory_bandwidth.h"
#include "relight/model_relighter.h"
#include "relight/relight_kernels.h"

namespace acpca {

namespace {

struct FrameTimes {
  double median = 0, p10 = 0, p90 = 0;
  std::vector<double> ms;         ///< every timed frame, in order
  std::vector<double> streamGbs;  ///< the paired pass read right before each frame
};

/// Times `frames` calls after two warm-up calls; with `paired`, one pass of it
/// is read right before each timed frame.
FrameTimes timeFrames(int frames, const std::function<void()>& frame, StreamingRead* paired) {
  for (int i = 0; i < 2; ++i) frame();
  FrameTimes t;
  for (int i = 0; i < frames; ++i) {
    if (paired) t.streamGbs.push_back(paired->pass());
    const Stopwatch watch;
    frame();
    t.ms.push_back(watch.milliseconds());
  }
  std::vector<double> ms = t.ms;
  std::sort(ms.begin(), ms.end());
  const auto at = [&](double q) { return ms[static_cast<size_t>(q * (ms.size() - 1) + 0.5)]; };
  t.median = at(0.5), t.p10 = at(0.1), t.p90 = at(0.9);
  return t;
}

struct Measured {
  std::string name, file, coeffs;
  FrameTimes times;
  double bytes = 0, costPerPixel = 0, error = -1;
  std::vector<std::vector<float>> images;  ///< one per lighting
  double gbPerSecond() const { return times.median > 0 ? bytes / (times.median * 1e6) : 0; }
  /// Median over frames of the frame's GB/s over its paired pass's.
  double pairedShare() const {
    std::vector<double> shares;
    for (size_t i = 0; i < times.streamGbs.size(); ++i)
      shares.push_back(bytes / (times.ms[i] * 1e6) / times.streamGbs[i]);
    return median(shares);
  }
};

/// Models and transports are compared pixel by pixel: they must cover the
/// same pixels of the same image (a transport made again by another build
/// may cover a few more or fewer).
void requireSameImage(const std::string& path, const std::vector<std::int32_t>& pixels,
                      const std::string& reference, const std::vector<std::int32_t>& expected) {
  if (pixels != expected)
    throw UserError(concat(path, ": covers ", pixels.size(), " pixels, not the ", expected.size(),
                           " of ", reference, ": not made from the same transport"));
}

/// Times the first lighting; relights the others once, for the errors. With
/// everyLevel, also times the first lighting with each other kernel level the
/// CPU runs (rows named for their level, no error).
std::vector<Measured> measureModel(const Model& model, const std::string& path,
                                   const std::vector<LatticeLighting>& lightings, int frames,
                                   StreamingRead& paired, bool everyLevel = false) {
  ModelRelighter relighter(model);
  Measured m;
  const kernels::Level active = kernels::activeLevel();
  m.name = concat(model.method, " [", kernels::kLevelNames.name(active), "]");
  m.file = path;
  m.coeffs =
      concat(coeffPrecisionName(model.precision), "/", coeffPrecisionName(model.basisPrecision));
  for (const auto& lighting : lightings) m.images.push_back(relighter.relight(lighting));
  m.times = timeFrames(
      frames, [&] { relighter.relight(lightings[0], m.images[0].data()); }, &paired);
  m.bytes = double(relighter.bytesPerFrame());
  m.costPerPixel = relighter.costPerPixel();
  std::vector<Measured> out{m};
  if (!everyLevel) return out;
  std::vector<float> image(m.images[0].size());
  for (kernels::Level level : kernels::supportedLevels()) {
    if (level == active) continue;
    kernels::useLevel(level);
    Measured other = m;
    other.name = concat(model.method, " [", kernels::kLevelNames.name(level), "]");
    other.images.clear();
    other.times = timeFrames(
        frames, [&] { relighter.relight(lightings[0], image.data()); }, &paired);
    out.push_back(std::move(other));
  }
  kernels::useLevel(active);
  return out;
}

/// The dense relight from memory, timed, and every model's image error
/// against it (the evaluation's aggregate over the lightings).
Measured measureDense(const TransportReader& reader, const std::vector<LatticeLighting>& lightings,
                      int denseFrames, StreamingRead& paired, std::vector<Measured>& models,
                      std::string& out) {
  const Stopwatch load;
  SparseTransport sparse(reader);
  const double loadSeconds = load.seconds();
  Measured dense;
  dense.name = "dense (f16, zero segments skipped)";
  dense.file = reader.path();
  dense.coeffs = "f16 T";
  for (const auto& lighting : lightings) dense.images.push_back(sparse.relight(lighting));
  dense.times = timeFrames(
      denseFrames, [&] { sparse.relight(lightings[0], dense.images[0].data()); }, &paired);
  dense.bytes = double(sparse.bytesPerFrame());
  dense.costPerPixel = sparse.keptFraction() * reader.latticeSize();  // in RGB triples
  out += formatted("dense reference: loaded in %.1f s, %.1f%% of T's entries kept\n", loadSeconds,
                   100 * sparse.keptFraction());
  // Image error over the lightings as the evaluation defines it (docs/design.md 7).
  for (auto& m : models) {
    if (m.images.empty()) continue;  // another kernel level: same image, within rounding
    std::vector<double> errors;
    for (size_t k = 0; k < lightings.size(); ++k)
      errors.push_back(relativeL2(m.images[k], dense.images[k]));
    m.error = aggregateError(errors);
  }
  return dense;
}

/// A line per relighter in `out`, and the same as JSON rows.
nlohmann::json relighterRows(const std::vector<Measured>& models, double streamGbs,
                             std::string& out) {
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& m : models) {
    char error[32] = "-";
    if (m.error >= 0) std::snprintf(error, sizeof error, "%.3f%%", 100 * m.error);
    out += formatted("%-36s %8s %10.3f %9.3f %9.3f %10.1f %8.1f %6.0f%% %6.0f%% %9.1f %8s\n",
                     m.name.c_str(), m.coeffs.c_str(), m.times.median, m.times.p10, m.times.p90,
                     m.bytes / 1e6, m.gbPerSecond(), 100 * m.gbPerSecond() / streamGbs,
                     100 * m.pairedShare(), m.costPerPixel, error);
    rows.push_back(
        {{"name", m.name},
         {"file", m.file},
         {"coeffs", m.coeffs},
         {"ms_per_frame_median", m.times.median},
         {"ms_per_frame_p10", m.times.p10},
         {"ms_per_frame_p90", m.times.p90},
         {"bytes_per_frame", m.bytes},
         {"gb_per_s", m.gbPerSecond()},
         {"fraction_of_stream", m.gbPerSecond() / streamGbs},
         {"paired_stream_gb_per_s", median(m.times.streamGbs)},
         {"fraction_of_paired_stream", m.pairedShare()},
         {"cost_per_pixel", m.costPerPixel},
         {"relative_l2_vs_dense", m.error < 0 ? nlohmann::json() : nlohmann::json(m.error)}});
  }
  return rows;
}

}  // namespace

void validateRelightBenchmarkOptions(const RelightBenchmarkOptions& a) {
  if (a.frames < 1) throw ParameterError("timed frames", a.frames, "must be >= 1");
  if (a.denseFrames < 1) throw ParameterError("dense frames", a.denseFrames, "must be >= 1");
  if (!(a.streamGiB > 0 && a.streamGiB <= 64))
    throw ParameterError("stream size (GiB)", a.streamGiB, "must be in (0, 64]");
}

StudyOutput runRelightBenchmark(const RelightBenchmarkOptions& a) {
  validateRelightBenchmarkOptions(a);
  std::string out;
  const std::vector<std::string> envs = a.envs.empty() ? defaultEvaluationSet() : a.envs;

  if (!isModelFile(a.model)) throw UserError(concat(a.model, ": not an adaptive-cpca model file"));
  // The bandwidth of this machine drifts (shared hosts): measure it before and
  // after the relighters and use the mean of the two medians.
  const BandwidthMeasurement before = measureStreamingRead(a.streamGiB * (1 << 30), 5);
  // Within seconds, too: each timed frame also gets its own pass of a smaller
  // array (still 8x the last-level cache of the machines we use) read just before.
  StreamingRead paired(std::min(a.streamGiB, 0.25) * (1 << 30));
  std::vector<Measured> models;
  Measured main;
  {
    const Model mainModel = readModel(a.model);
    const std::vector<std::int32_t>& pixels = mainModel.geometry.pixels;
    // Every file is read and checked once, before any is timed.
    std::vector<Model> baselines;
    for (const auto& path : a.baselines) {
      if (!isModelFile(path)) throw UserError(concat(path, ": not an adaptive-cpca model file"));
      baselines.push_back(readModel(path));
      requireSameImage(path, baselines.back().geometry.pixels, a.model, pixels);
    }
    std::optional<TransportReader> reader;
    if (!a.transport.empty()) {
      reader.emplace(a.transport);
      requireSameImage(a.transport, reader->header().pixels, a.model, pixels);
    }
    const DomainLighting domain(mainModel.geometry);
    std::vector<LatticeLighting> lightings;
    for (const auto& e : envs) lightings.push_back(domain(*loadEnvironment(e), {}));
    std::vector<Measured> levels =
        measureModel(mainModel, a.model, lightings, a.frames, paired, true);
    main = levels[0];
    for (size_t i = 0; i < baselines.size(); ++i)
      models.push_back(measureModel(baselines[i], a.baselines[i], lightings, a.frames, paired)[0]);
    models.insert(models.begin(), levels.begin(), levels.end());

    if (reader)
      models.push_back(measureDense(*reader, lightings, a.denseFrames, paired, models, out));
  }

  const BandwidthMeasurement after = measureStreamingRead(a.streamGiB * (1 << 30), 5);
  BandwidthMeasurement stream = before;
  stream.gbPerSecondMedian = (before.gbPerSecondMedian + after.gbPerSecondMedian) / 2;
  out += formatted(
      "streaming read, %.2f GiB array, %d threads: %.1f GB/s (median before %.1f, after %.1f)\n",
      stream.bytes / double(1 << 30), a.threads, stream.gbPerSecondMedian, before.gbPerSecondMedian,
      after.gbPerSecondMedian);
  out += formatted(
      "paired: each frame's GB/s over a %.2f GiB pass read right before it, median of frames\n",
      paired.bytes() / double(1 << 30));
  out += formatted(
      "timed under %s; error: aggregate relative L2 over %zu lighting(s), of the raw "
      "reconstruction (before the clamp at zero)\n",
      envs[0].c_str(), envs.size());
  out += formatted("%-36s %8s %10s %9s %9s %10s %8s %7s %7s %9s %8s\n", "relighter", "u/bases",
                   "ms median", "p10", "p90", "MB/frame", "GB/s", "stream", "paired", "cost/px",
                   "error");
  const nlohmann::json rows = relighterRows(models, stream.gbPerSecondMedian, out);
  nlohmann::json speedups = nlohmann::json::object();
  for (size_t i = 1; i < models.size(); ++i) {
    const double ratio = models[i].times.median / models[0].times.median;
    out += formatted("speed-up of %s over %s: %.2fx\n", a.model.c_str(), models[i].name.c_str(),
                     ratio);
    speedups[models[i].file == a.model ? models[i].name : models[i].file] = ratio;
  }
  return {{{"threads", a.threads},
           {"envs", envs},
           {"frames", a.frames},
           {"stream_bytes", stream.bytes},
           {"stream_gb_per_s", stream.gbPerSecondMedian},
           {"relighters", rows},
           {"speedup_over", speedups}},
          out};
}

}  // namespace acpca
