#include "tools/method_sweep.h"

#include <algorithm>
#include <chrono>
#include <cmath>
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
#include "relight/model_relighter.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

using Clock = std::chrono::steady_clock;

struct SweepArgs {
  CommonOptions common;
  std::string input, out;
  std::vector<double> globalEnergies{0.99, 0.999}, tolerances{0.99, 0.999};
  std::vector<int> cpcaClusters{10, 5000};
  std::vector<std::string> envs;
  std::vector<std::string> methods{
      "global", "block", "adaptive-quad", "adaptive-quad-exact", "adaptive-binary", "cpca"};
};

struct Row {
  std::string method, setting;
  double globalEnergy = 0, tolerance = 0;
  int clusters = 0;
  double costPerPixel = 0, transportError = 0, imageError = 0, seconds = 0;
};

double seconds(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

void run(const SweepArgs& a) {
  ThreadLimit limit(a.common.threads);
  const TransportReader transport(a.input);
  const CubeLattice lattice(transport.header().cubemapResolution);
  const std::vector<std::string> envs = a.envs.empty() ? defaultEvaluationSet() : a.envs;
  std::vector<LatticeLighting> lightings;
  for (const auto& e : envs) lightings.push_back(computeLighting(*loadEnvironment(e), lattice, {}));
  const auto truth = denseRelight(transport, lightings);
  const auto log = [&](const std::string& s) {
    if (!a.common.quiet) std::cerr << "bench methods: " << s << std::endl;
  };

  for (const auto& method : a.methods)
    if (method != "global" && method != "block" && method != "adaptive-quad" &&
        method != "adaptive-quad-exact" && method != "adaptive-binary" && method != "cpca")
      throw UserError(concat("--methods: unknown method '", method, "'"));
  const auto wanted = [&](const std::string& method) {
    return std::find(a.methods.begin(), a.methods.end(), method) != a.methods.end();
  };

  std::vector<Row> rows;
  const auto record = [&](Row r, const std::vector<double>& errors) {
    r.imageError = aggregateError(errors);
    log(concat(r.method, " ", r.setting, " g=", r.globalEnergy, " tol=", r.tolerance, ": ",
               r.clusters, " clusters, cost/pixel ", r.costPerPixel, ", image error ", r.imageError,
               ", transport error ", r.transportError));
    rows.push_back(r);
  };
  const auto evaluate = [&](const std::string& method, const std::string& setting, double g,
                            double tol, const GlobalBasis& basis,
                            const GlobalProjection& projection, const Partition& partition,
                            bool mean, double partitionSeconds, bool allocate = false) {
    const auto start = Clock::now();
    std::unique_ptr<ModelRelighter> relighter;
    Row r{method, setting, g, tol};
    std::vector<int> ranks;
    {
      ModelOptions options;
      options.tolerance = tol;
      options.mean = mean;
      options.allocateRanks = allocate;
      const Model m = buildModel(transport.header(), basis, projection, partition, options);
      relighter = std::make_unique<ModelRelighter>(m);
      r.clusters = m.clusters();
      r.costPerPixel = m.costPerPixel();
      r.transportError = m.transportError;
      ranks = m.ranks;
    }  // the relighter holds its own copy
    std::vector<double> errors;
    for (size_t k = 0; k < lightings.size(); ++k)
      errors.push_back(relativeL2(relighter->relight(lightings[k]), truth[k]));
    r.seconds = partitionSeconds + seconds(start);
    record(r, errors);
    // One PCA basis set is nested: its first k bases are the best rank-k fit, so
    // global PCA at lower ranks comes from the same model (--max-rank).
    if (method == "global" && !ranks.empty() && ranks[0] > 8) {
      const long long pixels = transport.rows();
      for (int divisor : {8, 4, 2}) {
        const int k = ranks[0] / divisor;
        relighter->setMaxRank(k);
        std::vector<double> truncated;
        for (size_t j = 0; j < lightings.size(); ++j)
          truncated.push_back(relativeL2(relighter->relight(lightings[j]), truth[j]));
        Row t = r;
        t.setting = concat("first ", k, " bases");
        t.costPerPixel = double(k) * (pixels + basis.globalBases()) / pixels;
        t.transportError = NAN;  // not measured for truncations
        record(t, truncated);
      }
    }
    return r.clusters;
  };

  for (double g : a.globalEnergies) {
    const auto basisStart = Clock::now();
    const GlobalBasis basis = computeGlobalBasis(transport, {g, 16384, 1});
    const GlobalProjection projection = projectOntoBasis(transport, basis);
    log(concat("global energy ", g, ": N = ", basis.globalBases(), " (", seconds(basisStart),
               " s)"));
    for (double tol : a.tolerances) {
      for (bool mean : {false, true}) {
        ClusterInput in{&projection.coefficients, &transport.header().pixels,
                        transport.header().camera.size, tol, mean};
        std::vector<int> all(in.rows());
        std::iota(all.begin(), all.end(), 0);
        auto t = Clock::now();
        if (!mean) {
          if (wanted("global"))
            evaluate("global", "N", g, tol, basis, projection, singleCluster(in), false,
                     seconds(t));
          for (int b : {8, 16}) {
            if (!wanted("block")) break;
            t = Clock::now();
            evaluate("block", concat("B=", b), g, tol, basis, projection, fixedBlocks(in, b), false,
                     seconds(t));
          }
          t = Clock::now();
          if (wanted("adaptive-quad"))
            evaluate("adaptive-quad", "greedy", g, tol, basis, projection,
                     adaptiveQuadTree(in, {64, 2, false}), false, seconds(t));
          t = Clock::now();
          if (wanted("adaptive-quad-exact"))
            evaluate("adaptive-quad-exact", "bottom-up", g, tol, basis, projection,
                     adaptiveQuadTree(in, {64, 2, true}), false, seconds(t));
        } else if (wanted("adaptive-binary") || wanted("cpca")) {
          BinaryOptions b;
          b.initialClusters = 8;
          std::vector<int> ks = a.cpcaClusters;
          if (wanted("adaptive-binary"))  // and CPCA with as many clusters as it found
            ks.push_back(evaluate("adaptive-binary", "K0=8", g, tol, basis, projection,
                                  adaptiveBinary(in, b), true, seconds(t)));
          if (!wanted("cpca")) ks.clear();
          for (int k : ks) {
            CpcaOptions o;
            o.clusters = k;
            t = Clock::now();
            evaluate("cpca", concat("K=", k), g, tol, basis, projection, cpca(in, all, o), true,
                     seconds(t));
          }
        }
      }
    }
  }

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
          << "," << r.seconds << "\n";
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
  for (const char* adaptive :
       {"adaptive-quad", "adaptive-quad-exact", "adaptive-quad+alloc", "adaptive-binary"})
    std::printf("%-22s / global  : %.3f @1%%  %.3f @3%%\n", adaptive,
                ratio(adaptive, "global", true), ratio(adaptive, "global", false));
  for (int k : a.cpcaClusters) {
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
  sub->add_option("--global-energies", args->globalEnergies, "Global energies to sweep")
      ->delimiter(',');
  sub->add_option("--tolerances", args->tolerances, "Cluster tolerances to sweep")->delimiter(',');
  sub->add_option("--cpca-clusters", args->cpcaClusters, "CPCA cluster counts")->delimiter(',');
  sub->add_option("--env", args->envs, "Evaluation lightings (default: the evaluation set)");
  sub->add_option("--methods", args->methods,
                  "Methods to run: global, block, adaptive-quad, adaptive-quad-exact, "
                  "adaptive-binary, cpca (default all)")
      ->delimiter(',');
  args->common.add(*sub);
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
