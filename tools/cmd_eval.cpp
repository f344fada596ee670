// `adaptive-cpca eval`: error against run time for every method (design.md
// section 7): the method sweep with timing, the dense relight, Ng 2003's
// Haar-wavelet baseline and paper 004's spherical-harmonics fits, written as
// CSV/JSON, images, plots and summary.md.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <opencv2/imgproc.hpp>

#include "precompute/transport/atomic_file.h"
#include "precompute/transport/error.h"
#include "relight/evaluation.h"
#include "relight/haar_transport.h"
#include "relight/sh_transport.h"
#include "relight/sparse_transport.h"
#include "tools/cli_common.h"
#include "tools/commands.h"
#include "tools/method_sweep.h"
#include "tools/report.h"
#include "tools/report_images.h"

namespace acpca::cli {

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct EvalArgs {
  CommonOptions common;
  std::string input, out;
  std::vector<std::string> envs;
  std::vector<std::string> methods{"dense",         "global",          "block", "cpca",
                                   "adaptive-quad", "adaptive-binary", "haar",  "sh"};
  SweepSettings sweep;
  std::vector<int> haarTerms{20, 50, 100, 200};
  int haarBits = 6;
  std::vector<int> shOrders{16, 25, 49, 64};
  std::vector<std::string> shFits{"uls", "cls", "ceb"};
  int shGroups = 8;
};

/// The relit first map of a method's most accurate setting, kept for pictures.
struct BestPicture {
  double error = INFINITY;
  std::string setting;
  std::vector<float> image;
  std::vector<int> clusterOfRow;
};

double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

void run(EvalArgs& a) {
  ThreadLimit limit(a.common.threads);
  const TransportReader transport(a.input);
  const TransportHeader& header = transport.header();
  const auto log = [&](const std::string& text) {
    if (!a.common.quiet) std::cerr << "eval: " << text << std::endl;
  };
  const auto wanted = [&](const std::string& m) {
    return std::find(a.methods.begin(), a.methods.end(), m) != a.methods.end();
  };
  std::vector<std::string> sweepMethodsWanted;
  for (const auto& m : a.methods)
    if (m != "dense" && m != "haar" && m != "sh") sweepMethodsWanted.push_back(m);
  checkSweepMethods(sweepMethodsWanted);
  for (int k : a.haarTerms)
    if (k <= 0) throw UserError(concat("--haar-terms: ", k, " is not a positive count"));
  for (int n : a.shOrders) shBandsOf(n, "--sh-orders");
  std::vector<ShFit> shFits;
  for (const auto& f : a.shFits) shFits.push_back(parseShFit(f));
  fs::create_directories(fs::path(a.out) / "images");
  if (!fs::is_directory(a.out))
    throw UserError(concat("--out '", a.out, "': cannot create the report directory"));

  const auto start = Clock::now();
  const EvaluationData data = loadEvaluationData(transport, a.envs);
  log(concat("ground truth for ", data.envs.size(), " maps (", secondsSince(start), " s)"));
  std::vector<SweepResult> results;
  std::map<std::string, BestPicture> best;
  const auto keep = [&](const SweepResult& r, const std::vector<float>& first,
                        const std::vector<int>& clusterOfRow) {
    BestPicture& b = best[r.method];
    if (r.imageError < b.error) b = {r.imageError, r.setting, first, clusterOfRow};
  };

  if (wanted("dense")) {
    const auto t = Clock::now();
    SparseTransport dense(transport);
    SweepResult r{"dense", "T in memory (f16)"};
    r.compressSeconds = secondsSince(t);
    r.costPerPixel = transport.latticeSize();
    r.modelBytes = dense.bytesPerFrame();
    const std::vector<float> first =
        measureMaps(data, r, std::min(a.sweep.timingFrames, 5),
                    [&](const LatticeLighting& l, float* rgb) { dense.relight(l, rgb); });
    log(concat("dense: ", r.msPerFrame, " ms/frame, error ", r.imageError));
    keep(r, first, {});
    results.push_back(r);
  }
  if (!sweepMethodsWanted.empty()) {
    a.sweep.methods = sweepMethodsWanted;
    a.sweep.quiet = a.common.quiet;
    a.sweep.logName = "eval";
    const auto swept = sweepMethods(data, a.sweep, keep);
    results.insert(results.end(), swept.begin(), swept.end());
  }
  if (wanted("haar")) {
    const auto t = Clock::now();
    HaarTransport haar(transport, a.haarBits);
    const double buildSeconds = secondsSince(t);
    log(concat("haar: ", 100 * haar.fillRatio(), "% of the wavelet-domain transport kept at ",
               a.haarBits, " bits (", buildSeconds, " s)"));
    for (int k : a.haarTerms) {
      SweepResult r{"haar", concat("k=", k)};
      r.compressSeconds = buildSeconds;
      r.modelBytes = haar.bytes();
      double cost = 0;
      const std::vector<float> first =
          measureMaps(data, r, a.sweep.timingFrames, [&](const LatticeLighting& l, float* rgb) {
            haar.relight(l, k, rgb);
            cost += haar.lastCostPerPixel();
          });
      // Its cost depends on which columns the lighting picks: the mean over the frames run.
      r.costPerPixel = cost / (data.lightings.size() + 1 + std::max(1, a.sweep.timingFrames));
      log(concat("haar k=", k, ": cost/pixel ", r.costPerPixel, ", ", r.msPerFrame,
                 " ms/frame, error ", r.imageError));
      keep(r, first, {});
      results.push_back(r);
    }
  }

  if (wanted("sh") && !a.shOrders.empty()) {
    const auto t = Clock::now();
    ShTransport sh(transport, *std::max_element(a.shOrders.begin(), a.shOrders.end()), a.shGroups);
    const double buildSeconds = secondsSince(t);
    log(concat("sh: ", sh.groups(), " normal groups (", buildSeconds, " s)"));
    for (ShFit fit : shFits)
      for (int n : a.shOrders) {
        // One curve per fit: sh-uls, sh-cls, sh-ceb.
        SweepResult r{concat("sh-", shFitName(fit)), concat("n=", n)};
        const auto fitStart = Clock::now();
        const ShCoefficients c = sh.fit(n, fit);
        r.compressSeconds = buildSeconds + secondsSince(fitStart);
        r.costPerPixel = sh.costPerPixel(n);
        r.modelBytes = sh.frameBytes(c);
        const std::vector<float> first =
            measureMaps(data, r, a.sweep.timingFrames,
                        [&](const LatticeLighting& l, float* rgb) { sh.relight(c, l, rgb); });
        log(concat(r.method, " n=", n, ": cost/pixel ", r.costPerPixel, ", ", r.msPerFrame,
                   " ms/frame, error ", r.imageError));
        keep(r, first, {});
        results.push_back(r);
      }
  }

  // Pictures of each method's most accurate setting under the first map.
  const fs::path images = fs::path(a.out) / "images";
  const auto env = loadEnvironment(data.envs[0]);
  const auto picture = [&](const std::vector<float>& rows) {
    return toneMappedBgr(
        composeImage(header, rows, Background::Env, *env, Eigen::Matrix3d::Identity()), 0);
  };
  writePng(picture(data.truth[0]), (images / "truth.png").string());
  std::vector<ReportPicture> pictures;
  for (const auto& [method, b] : best) {
    ReportPicture p{method, b.setting};
    p.relit = "images/" + method + "_relit.png";
    writePng(picture(b.image), (fs::path(a.out) / p.relit).string());
    p.error = "images/" + method + "_error.png";
    writePng(errorHeatMap(header, b.image, data.truth[0], 0.1),
             (fs::path(a.out) / p.error).string());
    if (!b.clusterOfRow.empty() && method != "global") {
      cv::Mat map = picture(b.image);
      drawClusterBoundaries(map, clusterOfPixel(header, b.clusterOfRow), {0, 230, 255});
      p.clusters = "images/" + method + "_clusters.png";
      writePng(map, (fs::path(a.out) / p.clusters).string());
    }
    pictures.push_back(p);
  }

  EvalReport report{a.input, data.envs, results, pictures, secondsSince(start)};
  writeEvalReport(report, a.out);
  writeJson(a.common.jsonPath, evalReportJson(report));
  log(concat("done in ", secondsSince(start), " s: ", (fs::path(a.out) / "summary.md").string()));
}

}  // namespace

void registerEval(CLI::App& app) {
  auto args = std::make_shared<EvalArgs>();
  args->sweep.globalEnergies = {0.995, 0.999};
  args->sweep.tolerances = {0.99, 0.999, 0.9997};
  args->sweep.blockSizes = {4, 8, 16, 32};
  args->sweep.cpcaClusters = {10, 100, 1000, 5000};
  args->sweep.cpcaMatchingBinary = false;
  args->sweep.cpcaAtHighestEnergyOnly = true;  // CPCA's fits are the sweep's slowest
  args->sweep.timingFrames = 15;
  auto* sub = app.add_subcommand(
      "eval", "Error against run time for every method: CSV/JSON, plots, images, summary.md");
  sub->add_option("input", args->input, "Transport file (T_FILE)")->required();
  sub->add_option("--env", args->envs, "Evaluation lightings (default: the evaluation set)");
  sub->add_option("--out", args->out, "Report directory")->required();
  sub->add_option("--methods", args->methods,
                  "dense, global, block, cpca, adaptive-quad, adaptive-quad-exact, "
                  "adaptive-binary, haar, sh (default: all but adaptive-quad-exact)")
      ->delimiter(',');
  sub->add_option("--tolerances", args->sweep.tolerances, "Cluster tolerances to sweep")
      ->delimiter(',');
  sub->add_option("--global-energies", args->sweep.globalEnergies, "Global energies to sweep")
      ->delimiter(',');
  sub->add_option("--block-sizes", args->sweep.blockSizes, "Fixed block sides")->delimiter(',');
  sub->add_option("--cpca-clusters", args->sweep.cpcaClusters, "CPCA cluster counts")
      ->delimiter(',');
  sub->add_option("--haar-terms", args->haarTerms, "Wavelet terms kept of the lighting")
      ->delimiter(',');
  sub->add_option(
      "--haar-bits", args->haarBits,
      "Wavelet-domain transport: drop coefficients below 2^-bits of their row's largest");
  sub->add_option("--sh-orders", args->shOrders,
                  "Spherical-harmonics coefficient counts (squares of 1..16)")
      ->delimiter(',');
  sub->add_option("--sh-fits", args->shFits, "SH fits of paper 004: uls, cls, ceb")->delimiter(',');
  sub->add_option("--sh-groups", args->shGroups,
                  "Cube resolution the rows' normals are grouped on for the SH fits (1..64)")
      ->check(CLI::Range(1, 64));
  sub->add_option("--frames", args->sweep.timingFrames, "Timed frames per setting (median)")
      ->check(CLI::PositiveNumber);
  args->common.add(*sub);
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
