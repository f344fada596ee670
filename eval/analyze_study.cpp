#include "eval/analyze_study.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <filesystem>
#include <sstream>

#include "cluster/dimensionality.h"
#include "cluster/global_basis.h"
#include "cluster/partition.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/stopwatch.h"
#include "core/table.h"
#include "eval/dimensionality_study.h"
#include "eval/eval_report.h"
#include "model/cost_model.h"

namespace acpca {

namespace {

namespace fs = std::filesystem;

struct BlockCost {
  int side = 0;
  int clusters = 0;
  double globalToLocal = 0, localToPixel = 0;  ///< per pixel
  double total() const { return globalToLocal + localToPixel; }
};

/// Fixed blocks of each side, each cluster at its rank for the tolerance
/// (Fig. 9a): the two parts of eq. 18 per pixel.
std::vector<BlockCost> blockCosts(const ClusterInput& in, const std::vector<int>& sides) {
  std::vector<BlockCost> out;
  for (int side : sides) {
    const Partition blocks = fixedBlocks(in, side);
    std::vector<int> ranks(blocks.size());
    tbb::parallel_for(size_t(0), blocks.size(),
                      [&](size_t c) { ranks[c] = rankOf(in, blocks[c]); });
    BlockCost b{side, static_cast<int>(blocks.size()), 0, 0};
    for (size_t c = 0; c < blocks.size(); ++c) {
      b.globalToLocal += double(ranks[c]) * in.globalBases();
      b.localToPixel += double(ranks[c]) * blocks[c].size();
    }
    b.globalToLocal /= std::max<long long>(1, in.rows());
    b.localToPixel /= std::max<long long>(1, in.rows());
    out.push_back(b);
  }
  return out;
}

std::string describePStar(double mu, int r, int n) {
  const double p = optimalPatchSize(mu, r, n);
  if (mu <= 1.0 / r)
    return concat("mu <= 1/", r,
                  ": d > 0 at every size, so eq. 27 says subdivide as far as possible");
  if (mu >= 1) return "mu >= 1: subdividing never pays";
  return concat(std::lround(p), " pixels (side ", std::lround(std::sqrt(p)), ")");
}

}  // namespace

void validateAnalyzeOptions(const AnalyzeOptions& a) {
  if (!(a.energy > 0 && a.energy <= 1))
    throw ParameterError("dimensionality energy", a.energy, "must be in (0, 1]");
  for (int b : a.blocks)
    if (b < 1) throw ParameterError("block sides", b, "must be >= 1");
}

StudyOutput runAnalysis(const TransportReader& transport, const AnalyzeOptions& a,
                        const std::string& outDir) {
  validateAnalyzeOptions(a);
  const Stopwatch watch;
  createOutputDirectory(outDir);
  const auto log = [&](const std::string& s) {
    if (a.log) a.log(s);
  };

  // 1. Dimensionality against patch area.
  const DimensionalityAnalysis dims =
      analyzeDimensionality(transport, a.centres, kAnalysisSides, a.energy, log);
  writeDimensionalityCsv(dims, outDir);

  // 2. Cost against block size with the global basis.
  const GlobalBasis basis = computeGlobalBasis(transport, {a.globalEnergy, 16384, 1});
  const GlobalProjection projection = projectOntoBasis(transport, basis);
  const int n = basis.globalBases();
  log(concat("global basis: N = ", n, " at ", a.globalEnergy, " of the energy"));
  const ClusterInput in{&projection.coefficients, &transport.header().pixels,
                        transport.header().camera.size, a.tolerance, false};
  const std::vector<BlockCost> costs = blockCosts(in, a.blocks);
  Table csv({"block_side", "block_pixels", "clusters", "global_bases", "global_to_local",
             "local_to_pixel", "cost_per_pixel"});
  const BlockCost* best = nullptr;
  for (const auto& c : costs) {
    csv.add({(long long)c.side, (long long)c.side * c.side, (long long)c.clusters, (long long)n,
             c.globalToLocal, c.localToPixel, c.total()});
    if (!best || c.total() < best->total()) best = &c;
    log(concat("blocks of ", c.side, ": cost/pixel ", c.total()));
  }
  csv.writeCsv((fs::path(outDir) / "block_cost.csv").string());
  const std::string plotProblem = drawPlots("analyze", outDir);

  // 3. mu, N, p* beside the measured optimum.
  const double slope = dims.meanSlope;
  const double mu4 = muFromSlope(slope, 4), mu2 = muFromSlope(slope, 2);
  std::ostringstream md;
  md << "# Analysis of " << transport.path() << "\n\n"
     << "## Dimensionality against patch area\n\n"
     << "Square patches around " << dims.centres.size() << " centres; dimensionality = "
     << "eigenvalues holding " << 100 * a.energy << "% of the patch's energy; slopes fitted in "
     << "log-log over patch areas (occupied pixels) from " << kSlopeAreaMin << " to "
     << kSlopeAreaMax << ".\n\n| centre | slope | points |\n|---|---:|---:|\n";
  for (const auto& c : dims.centres)
    md << "| " << c.x << "," << c.y << " | " << formatFixed(c.fit.slope, 3) << " | " << c.fit.points
       << " |\n";
  md << "\nMean slope **" << formatFixed(slope, 3) << "** (the paper: about 1 for glossy "
     << "reflection and complex shadows, about 0.5 for simple shadows).\n\n"
     << "## Cost against block size (fixed blocks, tolerance " << a.tolerance << ")\n\n"
     << "N = " << n << " global bases (" << a.globalEnergy << " of the energy).\n\n"
     << "| block | pixels | clusters | n N per pixel | n p per pixel | cost per pixel |\n"
     << "|---:|---:|---:|---:|---:|---:|\n";
  for (const auto& c : costs)
    md << "| " << c.side << "x" << c.side << " | " << c.side * c.side << " | " << c.clusters
       << " | " << formatFixed(c.globalToLocal, 1) << " | " << formatFixed(c.localToPixel, 1)
       << " | " << formatFixed(c.total(), 1) << " |\n";
  md << "\nMeasured optimum: **" << best->side << "x" << best->side << "** ("
     << best->side * best->side << " pixels, cost " << formatFixed(best->total(), 1)
     << " per pixel).\n\n"
     << "## mu and the optimal patch size (sec. 5.1, eq. 27)\n\n"
     << "| r | mu = r^-slope | p* = N (r mu - 1) / (1 - mu) |\n|---:|---:|---|\n"
     << "| 4 (blocks) | " << formatFixed(mu4, 3) << " | " << describePStar(mu4, 4, n) << " |\n"
     << "| 2 (binary) | " << formatFixed(mu2, 3) << " | " << describePStar(mu2, 2, n) << " |\n\n"
     << "Measured optimum for blocks: " << best->side * best->side << " pixels; N = " << n
     << ".\n\n";
  if (plotProblem.empty())
    md << "![dimensionality](dimensionality.png)\n\n![cost against block size](block_cost.png)\n";
  else
    md << "No plots: " << plotProblem << "\n";
  writeTextFile((fs::path(outDir) / "summary.md").string(), md.str());

  nlohmann::json centres = nlohmann::json::array();
  for (const auto& c : dims.centres)
    centres.push_back({{"x", c.x},
                       {"y", c.y},
                       {"slope", finiteOrNull(c.fit.slope)},
                       {"large_patch_slope", finiteOrNull(c.largeFit.slope)}});
  nlohmann::json blocks = nlohmann::json::array();
  for (const auto& c : costs)
    blocks.push_back({{"side", c.side},
                      {"clusters", c.clusters},
                      {"global_to_local", c.globalToLocal},
                      {"local_to_pixel", c.localToPixel},
                      {"cost_per_pixel", c.total()}});
  const double pStar4 = optimalPatchSize(mu4, 4, n), pStar2 = optimalPatchSize(mu2, 2, n);
  const nlohmann::json report = {{"input", transport.path()},
                                 {"energy", a.energy},
                                 {"slope_area_range", {kSlopeAreaMin, kSlopeAreaMax}},
                                 {"centres", centres},
                                 {"mean_slope", finiteOrNull(slope)},
                                 {"mean_large_patch_slope", finiteOrNull(dims.meanLargeSlope)},
                                 {"global_bases", n},
                                 {"mu_r4", finiteOrNull(mu4)},
                                 {"mu_r2", finiteOrNull(mu2)},
                                 {"p_star_r4", finiteOrNull(pStar4)},
                                 {"p_star_r2", finiteOrNull(pStar2)},
                                 {"block_costs", blocks},
                                 {"best_block_side", best->side},
                                 {"seconds", watch.seconds()}};
  writeTextFile((fs::path(outDir) / "analysis.json").string(), report.dump(2) + "\n");
  return {report, md.str()};
}

}  // namespace acpca
