#pragma once
// What is relit: a model (the fast relighter) or a transport file (the dense
// ground truth), behind one interface for the CLI's batches and the Python
// module.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "relight/environment.h"
#include "relight/model_relighter.h"
#include "transport/transport_file.h"

namespace acpca {

struct RelightSource {
  TransportHeader header;
  std::string method;  ///< the model's, or "dense"
  /// Bytes of model read per frame; for a transport, per pass over T (a pass
  /// relights a whole group of frames).
  long long bytesPerPass = 0;
  bool dense = false;
  /// The model's relighter (null for a transport): its rank limit may change.
  std::shared_ptr<ModelRelighter> model;
  /// Relights the group (per frame: 3 floats per occupied row, albedo
  /// applied); ms[k] is the time spent on frame k. A transport relights the
  /// whole group in one pass over T.
  std::function<std::vector<std::vector<float>>(const std::vector<LatticeLighting>&,
                                                std::vector<double>& ms)>
      relight;
};

/// Opens a model or transport file; maxRank as applyRankLimit (models only:
/// a ParameterError for a transport).
RelightSource openRelightSource(const std::string& path, const std::string& maxRank = "");

}  // namespace acpca
