#include "eval/scaling_study.h"

#include <cmath>
#include <filesystem>
#include <sstream>

#include "cluster/compress.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/stopwatch.h"
#include "core/table.h"
#include "eval/dimensionality_study.h"
#include "eval/eval_report.h"
#include "eval/method_sweep.h"
#include "lighting/lighting.h"
#include "relight/model_relighter.h"

namespace acpca {

namespace {

namespace fs = std::filesystem;

struct SizeResult {
  int size = 0;
  long long pixels = 0, occupied = 0;
  int globalBases = 0, clusters = 0;
  double totalCost = 0, costPerPixel = 0, msPerFrame = 0;
  long long modelBytes = 0;
  double slope = NAN, mu = NAN;             ///< dimensionality slope; mu = 2^-slope
  double costRatio = NAN, predicted = NAN;  ///< per 4x pixels, against the previous size
  /// Dimensionality of the same physical patch here over at the previous size
  /// (the paper's sec. 4.4 assumes 1: more pixels, same information).
  double samePatchGrowth = NAN;
  std::vector<std::pair<int, int>> centres;  ///< where the slopes were measured
  double precomputeSeconds = 0, compressSeconds = 0;
};

/// Mean over the previous size's centres of n(the 16-pixel square there) and
/// n(the square covering the same part of the image here).
double samePatchGrowth(const SizeResult& previous, const std::string& previousPath,
                       const TransportReader& current, double energy) {
  const TransportReader before(previousPath);
  const double f = double(current.header().camera.size.width) / previous.size;
  double sum = 0;
  int counted = 0;
  for (const auto& [x, y] : previous.centres) {
    const int n0 =
        patchDimensionality(readSquarePatch(before, x, y, 16), before.rowLength(), energy);
    const int n1 = patchDimensionality(
        readSquarePatch(current, static_cast<int>(std::lround((x + 0.5) * f - 0.5)),
                        static_cast<int>(std::lround((y + 0.5) * f - 0.5)),
                        static_cast<int>(std::lround(16 * f))),
        current.rowLength(), energy);
    if (n0 > 0) sum += double(n1) / n0, ++counted;
  }
  return counted ? sum / counted : NAN;
}

/// One size's figures from its transport: the model, its frame time, the
/// dimensionality slope, and the same-patch growth against the size before.
void measureSize(SizeResult& r, const TransportReader& transport, const ScalingOptions& a,
                 const std::vector<SizeResult>& results, const std::string& previousPath) {
  r.pixels = transport.header().camera.size.pixels();
  r.occupied = transport.rows();
  Stopwatch t;
  CompressOptions c;
  c.method = parseMethod(a.method);
  c.tolerance = a.tolerance;
  c.globalEnergy = a.globalEnergy;
  const Model model = compressTransport(transport, c);
  r.compressSeconds = t.seconds();
  r.globalBases = model.globalBases();
  r.clusters = model.clusters();
  r.totalCost = model.totalCost();
  r.costPerPixel = model.costPerPixel();
  ModelRelighter relighter(model);
  r.modelBytes = relighter.bytesPerFrame();
  const LatticeLighting sky = computeLighting(*loadEnvironment("sky"), CubeLattice(a.cubemap), {});
  std::vector<float> rgb(3 * relighter.rows());
  r.msPerFrame = medianMilliseconds([&] { relighter.relight(sky, rgb.data()); }, a.frames);
  const DimensionalityAnalysis dims =
      analyzeDimensionality(transport, {}, kAnalysisSides, a.energy, {});
  r.slope = dims.meanSlope;
  for (const auto& c : dims.centres) r.centres.push_back({c.x, c.y});
  if (!results.empty())
    r.samePatchGrowth = samePatchGrowth(results.back(), previousPath, transport, a.energy);
  // Doubling a patch's pixels splits it into two halves of mu n bases each.
  r.mu = muFromSlope(r.slope, 2);
}

/// scaling.csv in `outDir`, and the same rows as JSON.
nlohmann::json writeScalingTable(const std::vector<SizeResult>& results,
                                 const std::string& outDir) {
  Table csv({"size", "pixels", "occupied_pixels", "global_bases", "clusters", "total_cost",
             "cost_per_pixel", "ms_per_frame", "model_bytes", "slope", "mu", "cost_ratio",
             "predicted_ratio", "precompute_seconds", "compress_seconds", "same_patch_growth"});
  nlohmann::json rows = nlohmann::json::array();
  for (const auto& r : results) {
    csv.add({(long long)r.size, r.pixels, r.occupied, (long long)r.globalBases,
             (long long)r.clusters, r.totalCost, r.costPerPixel, r.msPerFrame, r.modelBytes,
             formatFixed(r.slope, 4), formatFixed(r.mu, 4), formatFixed(r.costRatio, 4),
             formatFixed(r.predicted, 4), r.precomputeSeconds, r.compressSeconds,
             formatFixed(r.samePatchGrowth, 4)});
    rows.push_back({{"size", r.size},
                    {"pixels", r.pixels},
                    {"occupied_pixels", r.occupied},
                    {"global_bases", r.globalBases},
                    {"clusters", r.clusters},
                    {"total_cost", r.totalCost},
                    {"cost_per_pixel", r.costPerPixel},
                    {"ms_per_frame", r.msPerFrame},
                    {"model_bytes", r.modelBytes},
                    {"slope", finiteOrNull(r.slope)},
                    {"mu", finiteOrNull(r.mu)},
                    {"cost_ratio", finiteOrNull(r.costRatio)},
                    {"predicted_ratio", finiteOrNull(r.predicted)},
                    {"same_patch_growth", finiteOrNull(r.samePatchGrowth)},
                    {"precompute_seconds", r.precomputeSeconds},
                    {"compress_seconds", r.compressSeconds}});
  }
  csv.writeCsv((fs::path(outDir) / "scaling.csv").string());
  return rows;
}

/// summary.md's text: the table and what it tests.
std::string scalingSummary(const ScalingOptions& a, const std::vector<SizeResult>& results,
                           const std::string& plotProblem) {
  std::ostringstream md;
  md << "# Cost against resolution: " << a.sceneName << "\n\n"
     << a.method << " at tolerance " << a.tolerance << ", global energy " << a.globalEnergy
     << ", 6x" << a.cubemap << "x" << a.cubemap
     << " lattice. mu is estimated at each size from the slope s of dimensionality against "
        "patch area (99.95% energy, five patch centres, areas "
     << kSlopeAreaMin << "-" << kSlopeAreaMax
     << "): doubling a patch's pixels splits it into two halves of mu n bases each, mu = 2^-s, "
        "so 4x pixels should multiply the total cost by 4 mu^2 (Mahajan et al. 2007 sec. 4.4, "
        "using the "
        "coarser size's mu).\n\n"
     << "| size | occupied | N | clusters | total cost | cost/pixel | ms/frame | model MB | "
        "slope | mu | cost ratio / 4x | 4 mu^2 | same-patch n growth |\n"
     << "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& r : results)
    md << "| " << r.size << " | " << r.occupied << " | " << r.globalBases << " | " << r.clusters
       << " | " << formatFixed(r.totalCost / 1e6, 1) << "M | " << formatFixed(r.costPerPixel, 1)
       << " | " << formatFixed(r.msPerFrame, 2) << " | " << formatFixed(r.modelBytes / 1e6, 1)
       << " | " << formatFixed(r.slope, 3) << " | " << formatFixed(r.mu, 3) << " | "
       << formatFixed(r.costRatio, 2) << " | " << formatFixed(r.predicted, 2) << " | "
       << formatFixed(r.samePatchGrowth, 2) << " |\n";
  md << "\nA ratio below 4 is sub-linear growth of cost with pixels. The prediction assumes "
        "that a patch keeps its dimensionality n when it gets more pixels (sec. 4.4); the last "
        "column measures that directly: n of a 16x16 square at the previous size against n of "
        "the square covering the same part of the image here, averaged over the previous "
        "size's centres (1 = the assumption holds).\n\n";
  if (plotProblem.empty())
    md << "![scaling](scaling.png)\n";
  else
    md << "No plot: " << plotProblem << "\n";
  return md.str();
}

}  // namespace

void validateScalingOptions(const ScalingOptions& a) {
  if (a.sizes.empty()) throw ParameterError("sizes", "", "give at least one size");
  for (int s : a.sizes)
    if (s < 8 || s > 8192) throw ParameterError("sizes", s, "is not in 8..8192");
  parseMethod(a.method);
  if (!a.precompute) throw ParameterError("precompute", "", "no way to make a transport given");
}

StudyOutput runScalingStudy(const ScalingOptions& a, const std::string& outDir) {
  validateScalingOptions(a);
  const Stopwatch watch;
  createOutputDirectory(outDir);
  const auto log = [&](const std::string& s) {
    if (a.log) a.log(s);
  };

  std::vector<SizeResult> results;
  std::string previousPath;
  for (int size : a.sizes) {
    SizeResult r;
    r.size = size;
    const std::string path = (fs::path(outDir) / concat("transport_", size, ".h5")).string();
    Stopwatch t;
    a.precompute(size, a.cubemap, path);
    r.precomputeSeconds = t.seconds();
    measureSize(r, TransportReader(path), a, results, previousPath);
    // The previous transport is kept until this size has been compared with it.
    if (!a.keepTransports && !previousPath.empty()) fs::remove(previousPath);
    previousPath = path;
    if (!results.empty()) {
      const SizeResult& prev = results.back();
      const double quadruplings = std::log(double(r.pixels) / prev.pixels) / std::log(4.0);
      r.costRatio = std::pow(r.totalCost / prev.totalCost, 1 / quadruplings);
      r.predicted = 4 * prev.mu * prev.mu;
    }
    log(concat(size, ": N = ", r.globalBases, ", ", r.clusters, " clusters, cost/pixel ",
               r.costPerPixel, ", total ", r.totalCost, ", ", r.msPerFrame, " ms/frame, slope ",
               formatFixed(r.slope, 3), ", mu ", formatFixed(r.mu, 3),
               std::isnan(r.costRatio)
                   ? std::string()
                   : concat(", cost ratio per 4x pixels ", formatFixed(r.costRatio, 2),
                            " (4 mu^2 = ", formatFixed(r.predicted, 2), "), same-patch n growth ",
                            formatFixed(r.samePatchGrowth, 2)),
               " [precompute ", formatFixed(r.precomputeSeconds, 0), " s, compress ",
               formatFixed(r.compressSeconds, 0), " s]"));
    results.push_back(r);
  }
  if (!a.keepTransports && !previousPath.empty()) fs::remove(previousPath);

  const nlohmann::json rows = writeScalingTable(results, outDir);
  const std::string plotProblem = drawPlots("scaling", outDir);
  const std::string md =
      scalingSummary(a, results, plotProblem) +
      concat("\n", results.size(), " sizes in ", formatFixed(watch.seconds(), 0), " s.\n");
  writeTextFile((fs::path(outDir) / "summary.md").string(), md);
  return {{{"scene", a.sceneName}, {"sizes", rows}}, md};
}

}  // namespace acpca
