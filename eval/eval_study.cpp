#include "eval/eval_study.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/stopwatch.h"
#include "eval/error_measures.h"
#include "eval/haar_transport.h"
#include "eval/sh_transport.h"
#include "eval/sparse_transport.h"
#include "pictures/pictures.h"
#include "relight/image_composer.h"

namespace acpca {

namespace {

namespace fs = std::filesystem;

/// The relit first map of a method's most accurate setting, kept for pictures.
struct BestPicture {
  double error = INFINITY;
  std::string setting;
  std::vector<float> image;
  std::vector<int> clusterOfRow;
};

bool wants(const EvalOptions& o, const std::string& method) {
  return std::find(o.methods.begin(), o.methods.end(), method) != o.methods.end();
}

std::vector<std::string> sweptMethods(const EvalOptions& o) {
  std::vector<std::string> out;
  for (const auto& m : o.methods)
    if (m != "dense" && m != "haar" && m != "sh") out.push_back(m);
  return out;
}

/// Pictures of each method's most accurate setting under the first map.
std::vector<ReportPicture> writePictures(const TransportHeader& header, const EvaluationData& data,
                                         const std::map<std::string, BestPicture>& best,
                                         const fs::path& dir) {
  const auto env = loadEnvironment(data.envs[0]);
  const auto picture = [&](const std::vector<float>& rows) {
    return toneMappedBgr(
        composeImage(header, rows, Background::Env, *env, Eigen::Matrix3d::Identity()), 0);
  };
  writePng(picture(data.truth[0]), (dir / "images" / "truth.png").string());
  std::vector<ReportPicture> pictures;
  for (const auto& [method, b] : best) {
    ReportPicture p{method, b.setting};
    p.relit = "images/" + method + "_relit.png";
    writePng(picture(b.image), (dir / p.relit).string());
    p.error = "images/" + method + "_error.png";
    writePng(errorHeatMap(header, b.image, data.truth[0], 0.1), (dir / p.error).string());
    if (!b.clusterOfRow.empty() && method != "global") {
      cv::Mat map = picture(b.image);
      drawClusterBoundaries(map, clusterOfPixel(header, b.clusterOfRow), {0, 230, 255});
      p.clusters = "images/" + method + "_clusters.png";
      writePng(map, (dir / p.clusters).string());
    }
    pictures.push_back(p);
  }
  return pictures;
}

}  // namespace

SweepSettings EvalOptions::defaultSweep() {
  SweepSettings s;
  s.globalEnergies = {0.995, 0.999};
  s.tolerances = {0.99, 0.999, 0.9997};
  s.blockSizes = {4, 8, 16, 32};
  s.cpcaClusters = {10, 100, 1000, 5000};
  s.cpcaMatchingBinary = false;
  s.cpcaAtHighestEnergyOnly = true;
  s.timingFrames = 15;
  return s;
}

void EvalOptions::useQuickSweep() {
  sweep.globalEnergies = {0.999};
  sweep.tolerances = {0.99, 0.999};
  sweep.blockSizes = {8, 16};
  sweep.cpcaClusters = {10, 1000};
  sweep.cpcaMatchingBinary = true;  // the paper's comparison at the same K
  haarTerms = {50, 200};
  shOrders = {16, 64};
}

void validateEvalOptions(const EvalOptions& o) {
  checkSweepMethods(sweptMethods(o));
  for (int k : o.haarTerms)
    if (k <= 0) throw ParameterError("Haar terms", k, "is not a positive count");
  for (int n : o.shOrders) shBandsOf(n, "SH orders");
  if (o.shGroups < 1 || o.shGroups > 64)
    throw ParameterError("SH groups", o.shGroups, "is outside 1..64");
}

EvalReport runEvaluation(const TransportReader& transport, const EvalOptions& o,
                         const std::string& dir) {
  validateEvalOptions(o);
  const auto log = [&](const std::string& text) {
    if (o.log) o.log(text);
  };
  createOutputDirectory((fs::path(dir) / "images").string());

  const Stopwatch watch;
  const EvaluationData data = loadEvaluationData(transport, o.envs);
  log(concat("ground truth for ", data.envs.size(), " maps (", watch.seconds(), " s)"));
  std::vector<SweepResult> results;
  std::map<std::string, BestPicture> best;
  const auto keep = [&](const SweepResult& r, const std::vector<float>& first,
                        const std::vector<int>& clusterOfRow) {
    BestPicture& b = best[r.method];
    if (r.imageError < b.error) b = {r.imageError, r.setting, first, clusterOfRow};
    results.push_back(r);
  };
  const int frames = o.sweep.timingFrames;

  if (wants(o, "dense")) {
    const Stopwatch build;
    SparseTransport dense(transport);
    SweepResult r{"dense", "T in memory (f16)"};
    r.compressSeconds = build.seconds();
    r.costPerPixel =
        transport.latticeSize();  // RGB triples: a value of an RGB row meets one channel
    r.modelBytes = dense.bytesPerFrame();
    const auto first = measureMaps(data, r, std::min(frames, 5),
                                   [&](const auto& l, float* rgb) { dense.relight(l, rgb); });
    log(concat("dense: ", r.msPerFrame, " ms/frame, error ", r.imageError));
    keep(r, first, {});
  }
  if (!sweptMethods(o).empty()) {
    SweepSettings sweep = o.sweep;
    sweep.methods = sweptMethods(o);
    sweep.log = o.log;
    sweepMethods(data, sweep, keep);
  }
  if (wants(o, "haar") && transport.header().isLightSet()) {
    log("haar: skipped: its wavelets live on the cube map's faces, and this transport is over a "
        "captured light set");
  } else if (wants(o, "haar")) {
    const Stopwatch build;
    HaarTransport haar(transport, o.haarBits);
    const double buildSeconds = build.seconds();
    log(concat("haar: ", 100 * haar.fillRatio(), "% of the wavelet-domain transport kept at ",
               o.haarBits, " bits (", buildSeconds, " s)"));
    for (int k : o.haarTerms) {
      SweepResult r{"haar", concat("k=", k)};
      r.compressSeconds = buildSeconds;
      r.modelBytes = haar.bytes();
      double cost = 0;
      const auto first = measureMaps(data, r, frames, [&](const auto& l, float* rgb) {
        haar.relight(l, k, rgb);
        cost += haar.lastCostPerPixel();
      });
      // Its cost depends on which columns the lighting picks: the mean over the frames run.
      r.costPerPixel = cost / (data.lightings.size() + 1 + std::max(1, frames));
      log(concat("haar k=", k, ": cost/pixel ", r.costPerPixel, ", ", r.msPerFrame,
                 " ms/frame, error ", r.imageError));
      keep(r, first, {});
    }
  }
  if (wants(o, "sh") && !o.shOrders.empty()) {
    const Stopwatch build;
    ShTransport sh(transport, *std::max_element(o.shOrders.begin(), o.shOrders.end()), o.shGroups);
    const double buildSeconds = build.seconds();
    log(concat("sh: ", sh.groups(), " normal groups (", buildSeconds, " s)"));
    for (ShFit fit : o.shFits)
      for (int n : o.shOrders) {
        // One curve per fit: sh-uls, sh-cls, sh-ceb.
        SweepResult r{concat("sh-", shFitName(fit)), concat("n=", n)};
        const Stopwatch fitWatch;
        const ShCoefficients c = sh.fit(n, fit);
        r.compressSeconds = buildSeconds + fitWatch.seconds();
        r.costPerPixel = sh.costPerPixel(n);
        r.modelBytes = sh.frameBytes(c);
        const auto first =
            measureMaps(data, r, frames, [&](const auto& l, float* rgb) { sh.relight(c, l, rgb); });
        log(concat(r.method, " n=", n, ": cost/pixel ", r.costPerPixel, ", ", r.msPerFrame,
                   " ms/frame, error ", r.imageError));
        keep(r, first, {});
      }
  }

  const auto pictures = writePictures(transport.header(), data, best, dir);
  EvalReport report{transport.path(), data.envs, results, pictures, watch.seconds()};
  writeEvalReport(report, dir);
  return report;
}

}  // namespace acpca
