#include "tools/method_sweep.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <numeric>

#include "cluster/compress.h"
#include "precompute/transport/error.h"
#include "relight/dense_relight.h"
#include "relight/evaluation.h"
#include "relight/lighting.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

const std::vector<std::string> kMethods{
    "global", "block", "adaptive-quad", "adaptive-quad-exact", "adaptive-binary", "cpca"};

}  // namespace

void checkSweepMethods(const std::vector<std::string>& methods) {
  for (const auto& m : methods)
    if (std::find(kMethods.begin(), kMethods.end(), m) == kMethods.end())
      throw UserError(concat("--methods: unknown method '", m, "'"));
}

EvaluationData loadEvaluationData(const TransportReader& transport, std::vector<std::string> envs) {
  EvaluationData d;
  d.transport = &transport;
  d.envs = envs.empty() ? defaultEvaluationSet() : std::move(envs);
  const CubeLattice lattice(transport.header().cubemapResolution);
  for (const auto& e : d.envs)
    d.lightings.push_back(computeLighting(*loadEnvironment(e), lattice, {}));
  d.truth = denseRelight(transport, d.lightings);
  return d;
}

std::vector<float> measureMaps(const EvaluationData& data, SweepResult& r, int frames,
                               const std::function<void(const LatticeLighting&, float*)>& relight) {
  std::vector<float> image(3 * data.transport->rows()), first;
  for (size_t k = 0; k < data.lightings.size(); ++k) {
    relight(data.lightings[k], image.data());
    r.errors.push_back(relativeL2(image, data.truth[k]));
    r.psnrs.push_back(psnr(image, data.truth[k]));
    if (k == 0) first = image;
  }
  r.imageError = aggregateError(r.errors);
  if (frames > 0 && !data.lightings.empty())
    r.msPerFrame = medianFrameMs([&] { relight(data.lightings[0], image.data()); }, frames);
  return first;
}

double medianFrameMs(const std::function<void()>& relight, int frames) {
  relight();  // warm-up
  std::vector<double> ms;
  for (int k = 0; k < frames; ++k) {
    const auto start = Clock::now();
    relight();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  }
  std::sort(ms.begin(), ms.end());
  return ms.empty() ? NAN : ms[ms.size() / 2];
}

std::vector<SweepResult> sweepMethods(const EvaluationData& data, const SweepSettings& s,
                                      const SweepObserver& observe) {
  checkSweepMethods(s.methods);
  const TransportReader& transport = *data.transport;
  const auto log = [&](const std::string& text) {
    if (!s.quiet) std::cerr << s.logName << ": " << text << std::endl;
  };
  const auto wanted = [&](const std::string& method) {
    return std::find(s.methods.begin(), s.methods.end(), method) != s.methods.end();
  };
  std::vector<SweepResult> results;

  // Relights every map, records errors (and timing), tells the observer.
  const auto measure = [&](SweepResult r, ModelRelighter& relighter,
                           const std::vector<int>& clusterOfRow) {
    const std::vector<float> first =
        measureMaps(data, r, s.timingFrames,
                    [&](const LatticeLighting& l, float* rgb) { relighter.relight(l, rgb); });
    r.modelBytes = relighter.bytesPerFrame();
    r.costPerPixel = relighter.costPerPixel();
    log(concat(r.method, " ", r.setting, " g=", r.globalEnergy, " tol=", r.tolerance, ": ",
               r.clusters, " clusters, cost/pixel ", r.costPerPixel, ", image error ", r.imageError,
               ", transport error ", r.transportError,
               std::isnan(r.msPerFrame) ? std::string() : concat(", ", r.msPerFrame, " ms/frame")));
    if (observe) observe(r, first, clusterOfRow);
    results.push_back(r);
  };

  for (double g : s.globalEnergies) {
    const auto basisStart = Clock::now();
    const GlobalBasis basis = computeGlobalBasis(transport, {g, 16384, 1});
    const GlobalProjection projection = projectOntoBasis(transport, basis);
    const double basisSeconds = seconds(basisStart);
    log(concat("global energy ", g, ": N = ", basis.globalBases(), " (", basisSeconds, " s)"));

    const auto evaluate = [&](const std::string& method, const std::string& setting, double tol,
                              const std::function<Partition()>& makePartition, bool mean) {
      const auto start = Clock::now();
      const Partition partition = makePartition();
      std::unique_ptr<ModelRelighter> relighter;
      SweepResult r{method, setting, g, tol};
      r.globalBases = basis.globalBases();
      r.basisSeconds = basisSeconds;
      std::vector<int> clusterOfRow;
      std::vector<int> ranks;
      {
        ModelOptions options;
        options.tolerance = tol;
        options.mean = mean;
        const Model m = buildModel(transport.header(), basis, projection, partition, options);
        relighter = std::make_unique<ModelRelighter>(m);
        r.clusters = m.clusters();
        r.transportError = m.transportError;
        ranks = m.ranks;
        if (observe) clusterOfRow = m.clusterOfRow();
      }  // the relighter holds its own copy
      r.compressSeconds = seconds(start);
      measure(r, *relighter, clusterOfRow);
      // PCA bases are nested: the first k of them are the best rank-k fit, so
      // global PCA at lower ranks comes from the same model (--max-rank).
      if (method == "global" && !ranks.empty() && ranks[0] > 8)
        for (int divisor : {8, 4, 2}) {
          const int k = ranks[0] / divisor;
          relighter->setMaxRank(k);
          SweepResult t = r;
          t.setting = concat("first ", k, " bases");
          t.transportError = NAN;
          measure(t, *relighter, clusterOfRow);
        }
      return r.clusters;
    };

    const bool highestEnergy =
        g == *std::max_element(s.globalEnergies.begin(), s.globalEnergies.end());
    const double highestTolerance = *std::max_element(s.tolerances.begin(), s.tolerances.end());
    for (double tol : s.tolerances) {
      for (bool mean : {false, true}) {
        const ClusterInput in{&projection.coefficients, &transport.header().pixels,
                              transport.header().camera.size, tol, mean};
        if (!mean) {
          // Global PCA once per basis: its nested truncations cover the lower tolerances.
          if (wanted("global") && tol == highestTolerance)
            evaluate(
                "global", "N", tol, [&] { return singleCluster(in); }, false);
          if (wanted("block"))
            for (int b : s.blockSizes)
              evaluate(
                  "block", concat("B=", b), tol, [&] { return fixedBlocks(in, b); }, false);
          if (wanted("adaptive-quad"))
            evaluate(
                "adaptive-quad", "greedy", tol,
                [&] {
                  return adaptiveQuadTree(in, {64, 2, false});
                },
                false);
          if (wanted("adaptive-quad-exact"))
            evaluate(
                "adaptive-quad-exact", "bottom-up", tol,
                [&] {
                  return adaptiveQuadTree(in, {64, 2, true});
                },
                false);
        } else if (wanted("adaptive-binary") || wanted("cpca")) {
          std::vector<int> all(in.rows());
          std::iota(all.begin(), all.end(), 0);
          BinaryOptions b;
          b.initialClusters = 8;
          const bool cpcaHere = wanted("cpca") && (highestEnergy || !s.cpcaAtHighestEnergyOnly);
          std::vector<int> ks = cpcaHere ? s.cpcaClusters : std::vector<int>{};
          if (wanted("adaptive-binary")) {
            const int found = evaluate(
                "adaptive-binary", "K0=8", tol, [&] { return adaptiveBinary(in, b); }, true);
            // CPCA with as many clusters as the adaptive split found: the paper's comparison.
            if (wanted("cpca") && s.cpcaMatchingBinary) ks.push_back(found);
          }
          for (int k : ks) {
            CpcaOptions o;
            o.clusters = k;
            evaluate(
                "cpca", concat("K=", k), tol, [&] { return cpca(in, all, o); }, true);
          }
        }
      }
    }
  }
  return results;
}

namespace {

struct SweepArgs {
  CommonOptions common;
  std::string input, out;
  SweepSettings settings;
  std::vector<std::string> envs;
};

void run(SweepArgs& a) {
  ThreadLimit limit(a.common.threads);
  const TransportReader transport(a.input);
  a.settings.quiet = a.common.quiet;
  if (a.settings.methods.empty()) a.settings.methods = kMethods;
  checkSweepMethods(a.settings.methods);
  const EvaluationData data = loadEvaluationData(transport, a.envs);
  const std::vector<SweepResult> rows = sweepMethods(data, a.settings);

  // Equal-error comparison.
  std::map<std::string, std::vector<ErrorCostPoint>> curves;
  for (const auto& r : rows) curves[r.method].push_back({r.imageError, r.costPerPixel});
  for (const auto& r : rows)
    if (r.method == "cpca") curves["cpca " + r.setting].push_back({r.imageError, r.costPerPixel});
  std::filesystem::create_directories(a.out);
  {
    std::ofstream csv(std::filesystem::path(a.out) / "methods.csv");
    csv << "method,setting,global_energy,tolerance,clusters,cost_per_pixel,image_error,transport_"
           "error,seconds\n";
    for (const auto& r : rows)
      csv << r.method << "," << r.setting << "," << r.globalEnergy << "," << r.tolerance << ","
          << r.clusters << "," << r.costPerPixel << "," << r.imageError << "," << r.transportError
          << "," << r.compressSeconds << "\n";
  }
  std::printf("\n%-26s %14s %14s\n", "method", "cost @ 1%", "cost @ 3%");
  std::map<std::string, std::pair<double, double>> atError;
  for (const auto& [method, points] : curves) {
    atError[method] = {costAtError(points, 0.01), costAtError(points, 0.03)};
    std::printf("%-26s %14.1f %14.1f\n", method.c_str(), atError[method].first,
                atError[method].second);
  }
  const auto ratio = [&](const std::string& a1, const std::string& b1, bool first) {
    const double x = first ? atError[a1].first : atError[a1].second;
    const double y = first ? atError[b1].first : atError[b1].second;
    return (x > 0 && y > 0) ? x / y : NAN;
  };
  std::printf("\nratios at equal image error (negative or nan: target outside the sweep)\n");
  for (const char* adaptive : {"adaptive-quad", "adaptive-quad-exact", "adaptive-binary"})
    std::printf("%-22s / global  : %.3f @1%%  %.3f @3%%\n", adaptive,
                ratio(adaptive, "global", true), ratio(adaptive, "global", false));
  for (int k : a.settings.cpcaClusters) {
    const std::string c = concat("cpca K=", k);
    std::printf("%-22s / adaptive-binary: %.3f @1%%  %.3f @3%%\n", c.c_str(),
                ratio(c, "adaptive-binary", true), ratio(c, "adaptive-binary", false));
  }
  // adaptive-binary against CPCA with the same number of clusters, setting by setting.
  for (size_t i = 0; i < rows.size(); ++i)
    if (rows[i].method == "adaptive-binary")
      for (size_t j = i + 1; j < rows.size(); ++j)
        if (rows[j].method == "cpca" && rows[j].globalEnergy == rows[i].globalEnergy &&
            rows[j].tolerance == rows[i].tolerance &&
            rows[j].setting == concat("K=", rows[i].clusters))
          std::printf(
              "adaptive-binary / cpca K=%d (g=%g tol=%g): cost %.1f / %.1f = %.3f, image error "
              "%.4f vs %.4f\n",
              rows[i].clusters, rows[i].globalEnergy, rows[i].tolerance, rows[i].costPerPixel,
              rows[j].costPerPixel, rows[i].costPerPixel / rows[j].costPerPixel, rows[i].imageError,
              rows[j].imageError);
  std::printf("\nall settings: %s\n", (std::filesystem::path(a.out) / "methods.csv").c_str());
}

}  // namespace

void registerMethodSweep(CLI::App& bench) {
  auto args = std::make_shared<SweepArgs>();
  auto* sub = bench.add_subcommand("methods", "Cost of every method at equal image error");
  sub->add_option("input", args->input, "Transport file")->required();
  sub->add_option("--out", args->out, "Directory for methods.csv")->required();
  sub->add_option("--global-energies", args->settings.globalEnergies, "Global energies to sweep")
      ->delimiter(',');
  sub->add_option("--tolerances", args->settings.tolerances, "Cluster tolerances to sweep")
      ->delimiter(',');
  sub->add_option("--cpca-clusters", args->settings.cpcaClusters, "CPCA cluster counts")
      ->delimiter(',');
  sub->add_option("--env", args->envs, "Evaluation lightings (default: the evaluation set)");
  sub->add_option("--methods", args->settings.methods,
                  "Methods to run: global, block, adaptive-quad, adaptive-quad-exact, "
                  "adaptive-binary, cpca (default all)")
      ->delimiter(',');
  args->common.add(*sub);
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
