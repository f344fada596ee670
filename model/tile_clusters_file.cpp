// The streamed build's tile files: a model's clusters without the image
// header or global basis (ModelFileKind::Clusters), read back to assemble the
// model.
#include "model/model_arrays.h"
#include "model/model_file.h"

namespace acpca {

ModelSizes readModelClusterSizes(const std::string& path, int globalBases) {
  const h5::Handle file = h5::openFileReadOnly(path);
  const hid_t f = file.get();
  if (!h5::hasAttribute(f, "format") ||
      h5::readStringAttribute(f, "format", path) != kClustersFormat)
    throw UserError(concat(path, ": not a file of model clusters"));
  const auto length = [&](const char* name) {
    const auto shape = h5::datasetShape(f, name, path);
    if (shape.size() != 1) throw UserError(concat(path, ": dataset '", name, "' is not 1-D"));
    return static_cast<long long>(shape[0]);
  };
  ModelSizes s{h5::readIntAttribute(f, "clusters", path), length("cluster_rows"), length("bases"),
               length("coefficients")};
  if (h5::readIntAttribute(f, "global_bases", path) != globalBases || s.clusters < 0)
    throw UserError(concat(path, ": clusters of another model"));
  return s;
}

Model readModelClusters(const std::string& path, const Model& head,
                        std::map<std::string, double>* extra) {
  const std::string& ctx = path;
  const h5::Handle file = h5::openFileReadOnly(path);
  const hid_t f = file.get();
  if (!h5::hasAttribute(f, "format") ||
      h5::readStringAttribute(f, "format", ctx) != kClustersFormat)
    throw UserError(concat(ctx, ": not a file of model clusters"));
  if (!h5::hasAttribute(f, "complete") || h5::readIntAttribute(f, "complete", ctx) != 1)
    throw UserError(concat(ctx, ": the file is incomplete"));
  const long long n = h5::readIntAttribute(f, "global_bases", ctx);
  const long long clusters = h5::readIntAttribute(f, "clusters", ctx);
  if (n != head.globalBases() ||
      h5::readStringAttribute(f, "coeffs", ctx) != coeffPrecisionName(head.precision) ||
      h5::readStringAttribute(f, "bases", ctx) != coeffPrecisionName(head.basisPrecision) ||
      (h5::readIntAttribute(f, "has_mean", ctx) != 0) != head.hasMean)
    throw UserError(concat(ctx, ": clusters of another model (global bases or precisions differ)"));
  const auto shape = h5::datasetShape(f, "cluster_rows", ctx);
  if (clusters < 0 || shape.size() != 1 || clusters > static_cast<long long>(shape[0]) + 1)
    throw UserError(concat(ctx, ": sizes do not add up"));
  Model m;
  m.hasMean = head.hasMean;
  m.precision = head.precision;
  m.basisPrecision = head.basisPrecision;
  readClusterArrays(f, m, static_cast<long long>(shape[0]), n, clusters, ctx);
  m.transportError = h5::readDoubleAttribute(f, "transport_error", ctx);
  m.globalEnergyKept = h5::readDoubleAttribute(f, "global_energy_kept", ctx);
  if (extra)
    for (auto& [name, value] : *extra) value = h5::readDoubleAttribute(f, name, ctx);
  return m;
}

}  // namespace acpca
