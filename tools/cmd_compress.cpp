// `adaptive-cpca compress`: transport file -> model.
#include <iostream>
#include <map>

#include "cluster/compress.h"
#include "cluster/model_file.h"
#include "relight/file_info.h"
#include "tools/cli_common.h"
#include "tools/commands.h"

namespace acpca::cli {

namespace {

struct CompressArgs {
  CommonOptions common;
  std::string input, out, method, coeffs = "f32", bases = "f32";
  double tolerance = 0.999, globalEnergy = 0.999;
  int clusters = 10, block = 0, sampleRows = 16384, clusteringDims = kDefaultClusteringDims;
  unsigned long long seed = 1;
  bool exactQuadTree = false, allocateRanks = false;
};

void run(const CompressArgs& a) {
  CompressOptions o;
  o.method = parseMethod(a.method);
  o.tolerance = a.tolerance;
  o.globalEnergy = a.globalEnergy;
  o.clusters = a.clusters;
  o.block = a.block;
  o.exactQuadTree = a.exactQuadTree;
  o.allocateRanks = a.allocateRanks;
  o.coeffs = parseCoeffPrecision(a.coeffs);
  o.bases = parseBasisPrecision(a.bases);
  o.sampleRows = a.sampleRows;
  o.clusteringDims = a.clusteringDims;
  o.seed = a.seed;
  if (!a.common.quiet) o.log = [](const std::string& s) { std::cerr << "compress: " << s << "\n"; };
  ThreadLimit limit(a.common.threads);
  const TransportReader transport(a.input);
  Model model = compressTransport(transport, o);
  model.peakMemoryBytes = peakMemoryBytes();
  writeModel(model, a.out);
  if (!a.common.quiet)
    std::cerr << "wrote " << a.out << ": " << model.method << ", " << model.clusters()
              << " clusters, N = " << model.globalBases() << ", cost " << model.totalCost() << " ("
              << model.costPerPixel() << " per pixel), transport error " << model.transportError
              << ", " << formatBytes(model.frameBytes()) << " read per frame, "
              << model.compressSeconds << " s, peak memory " << formatBytes(model.peakMemoryBytes)
              << "\n";
  writeJson(a.common.jsonPath, {{"out", a.out},
                                {"method", model.method},
                                {"clusters", model.clusters()},
                                {"global_bases", model.globalBases()},
                                {"total_cost", model.totalCost()},
                                {"cost_per_pixel", model.costPerPixel()},
                                {"transport_error", model.transportError},
                                {"global_energy_kept", model.globalEnergyKept},
                                {"bytes_per_frame", model.frameBytes()},
                                {"rank_histogram", rankHistogramJson(model)},
                                {"seconds", model.compressSeconds},
                                {"peak_memory_bytes", model.peakMemoryBytes}});
}

}  // namespace

void registerCompress(CLI::App& app) {
  auto args = std::make_shared<CompressArgs>();
  auto* sub =
      app.add_subcommand("compress", "Compress a transport file into a clustered PCA model");
  sub->add_option("input", args->input, "Transport file (T_FILE)")->required();
  sub->add_option("--out", args->out, "Model file to write (HDF5)")->required();
  sub->add_option("--method", args->method, "global, block, cpca, adaptive-quad or adaptive-binary")
      ->required();
  sub->add_option("--tolerance", args->tolerance, "Fraction of each cluster's energy kept");
  sub->add_option("--global-energy", args->globalEnergy,
                  "Fraction of energy the global basis keeps (1: every direction)");
  sub->add_option("--clusters", args->clusters, "cpca: K; adaptive-binary: initial clusters");
  sub->add_option("--block", args->block, "block: side (default 8); adaptive-quad: root side (64)");
  sub->add_flag("--exact-tree", args->exactQuadTree,
                "adaptive-quad: bottom-up optimal tree instead of the paper's greedy test");
  sub->add_flag("--allocate-ranks", args->allocateRanks,
                "Spend one error budget, (1 - tolerance) of all energy, where it buys the most");
  sub->add_option("--coeffs", args->coeffs, "Coefficient storage: f32, f16 or i8");
  sub->add_option("--bases", args->bases,
                  "Cluster basis storage: f32 or f16 (halves the bytes a frame reads for them)");
  sub->add_option("--sample-rows", args->sampleRows, "Rows sampled for the global basis");
  sub->add_option("--clustering-dims", args->clusteringDims,
                  "cpca, adaptive-binary: leading global coefficients rows are clustered on "
                  "(0: all)");
  sub->add_option("--seed", args->seed, "Random seed (sampling, CPCA seeding)");
  args->common.add(*sub);
  sub->callback([args] { run(*args); });
}

}  // namespace acpca::cli
