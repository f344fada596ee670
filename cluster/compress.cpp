#include "cluster/compress.h"
#include "cluster/blas_core.h"
#include "cluster/model_fit.h"

#include <iomanip>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/resources.h"
#include "core/stopwatch.h"

namespace acpca {

Method parseMethod(const std::string& text) {
  return kMethodNames.parse(text);
}

const char* methodName(Method m) {
  return kMethodNames.name(m);
}

int blockSideFor(const CompressOptions& o) {
  if (o.block != 0) return o.block;
  return o.method == Method::AdaptiveQuad ? 64 : 8;
}

void validateCompressOptions(const CompressOptions& o) {
  if (!(o.tolerance > 0 && o.tolerance <= 1))
    throw ParameterError("tolerance", o.tolerance, "is outside (0, 1]");
  if (!(o.globalEnergy > 0 && o.globalEnergy <= 1))
    throw ParameterError("global energy", o.globalEnergy, "is outside (0, 1]");
  if (o.clusters < 1) throw ParameterError("clusters", o.clusters, "must be >= 1");
  if (o.clusteringDims < 0)
    throw ParameterError("clustering dimensions", o.clusteringDims, "must be >= 0 (0: all)");
  if (blockSideFor(o) < 1) throw ParameterError("block side", blockSideFor(o), "must be >= 1");
  if (o.sampleRows < 1) throw ParameterError("sample rows", o.sampleRows, "must be >= 1");
}

bool keepsMean(Method m) {
  return m == Method::Cpca || m == Method::AdaptiveBinary;
}

Partition partitionRows(const ClusterInput& in, const CompressOptions& o) {
  CpcaOptions cpcaOptions;
  cpcaOptions.clusters = o.clusters;
  cpcaOptions.seed = o.seed;
  switch (o.method) {
    case Method::Global:
      return singleCluster(in);
    case Method::Block:
      return fixedBlocks(in, blockSideFor(o));
    case Method::Cpca: {
      std::vector<int> all(in.rows());
      for (long long r = 0; r < in.rows(); ++r) all[r] = static_cast<int>(r);
      return cpca(in, all, cpcaOptions);
    }
    case Method::AdaptiveQuad: {
      QuadTreeOptions q;
      q.rootBlock = blockSideFor(o);
      q.exact = o.exactQuadTree;
      return adaptiveQuadTree(in, q);
    }
    case Method::AdaptiveBinary: {
      BinaryOptions b;
      b.initialClusters = o.clusters;
      b.split = cpcaOptions;
      return adaptiveBinary(in, b);
    }
  }
  return {};
}

Model compressTransport(const TransportReader& transport, const CompressOptions& o) {
  validateCompressOptions(o);
  const Stopwatch watch;
  const auto log = [&](const std::string& s) {
    if (o.log) o.log(concat("[", std::fixed, std::setprecision(1), watch.seconds(), " s] ", s));
  };

  const GlobalBasis basis = computeGlobalBasis(transport, {o.globalEnergy, o.sampleRows, o.seed});
  log(concat("global basis: N = ", basis.globalBases(), " of ", basis.activeDirections,
             " directions the sample sees, ", basis.sampleEnergyKept, " of the sample's energy (",
             basis.heldOutEnergyKept, " on held-out rows)"));
  {
    // Every row's N coefficients in float, the array everything after works
    // on: the peak is this and the clustering's copies beside it.
    ResourceNeed need;
    need.what = concat("compressing ", transport.rows(), " rows onto N = ", basis.globalBases(),
                       " global bases");
    need.memoryBytes = transport.rows() * static_cast<long long>(basis.globalBases()) * 4;
    need.memoryAdvice =
        "keep less global energy (fewer bases), or render the image in tiles with the streamed "
        "build, which holds a few tiles at a time";
    requireResources(need, o.force);
  }
  const GlobalProjection projection = projectOntoBasis(transport, basis);
  log("projected every row onto the global basis");

  const bool mean = keepsMean(o.method);
  ClusterInput in{&projection.coefficients,
                  &transport.header().pixels,
                  transport.header().camera.size,
                  o.tolerance,
                  mean,
                  o.clusteringDims};
  const Partition partition = partitionRows(in, o);
  log(concat(methodName(o.method), ": ", partition.size(), " clusters"));
  ModelOptions modelOptions;
  modelOptions.tolerance = o.tolerance;
  modelOptions.mean = mean;
  modelOptions.precision = o.coeffs;
  modelOptions.basisPrecision = o.bases;
  modelOptions.allocateRanks = o.allocateRanks;
  Model model = buildModel(transport.header(), basis, projection, partition, modelOptions);
  model.method = methodName(o.method);
  nlohmann::json settings = compressSettings(o, basis.globalBases());
  settings["source"] = transport.path();
  model.settings = settings.dump();
  model.compressSeconds = watch.seconds();
  return model;
}

nlohmann::json compressSettings(const CompressOptions& o, int globalBases) {
  const int width = o.clusteringDims > 0 ? std::min(o.clusteringDims, globalBases) : globalBases;
  return {{"method", methodName(o.method)},
          {"tolerance", o.tolerance},
          {"global_energy", o.globalEnergy},
          {"clusters", o.clusters},
          {"block", blockSideFor(o)},
          {"exact_quad_tree", o.exactQuadTree},
          {"allocate_ranks", o.allocateRanks},
          {"coeffs", coeffPrecisionName(o.coeffs)},
          {"bases", coeffPrecisionName(o.bases)},
          {"sample_rows", o.sampleRows},
          {"clustering_dims", width},
          {"seed", o.seed},
          {"mean", keepsMean(o.method)},
          {"blas_core", blasCore()},
          {"eigensolver", linearAlgebraJson()["eigensolver"]}};
}

nlohmann::json linearAlgebraJson() {
  return {{"blas_core", blasCore()},
          {"blas_core_chosen_by", blasCoreChosenBy()},
          {"eigensolver", blasCoreUnsuited() ? "Eigen" : "LAPACK"}};
}

}  // namespace acpca
