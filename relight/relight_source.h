#pragma once
// What is relit: a model (the fast relighter) or a transport file (the dense
// ground truth), behind one interface for the CLI's batches and the Python
// module.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "lighting/environment.h"
#include "lighting/local_light.h"
#include "relight/lamp_light.h"
#include "relight/model_relighter.h"
#include "relight/rank_limit.h"
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
  /// applied); ms[k] is the time spent on frame k (its share of what the group
  /// shares, and its own). A transport relights the whole group in one pass
  /// over T, a model projects the group's lightings at once.
  std::function<std::vector<std::vector<float>>(const std::vector<LatticeLighting>&,
                                                std::vector<double>& ms)>
      relight;
  /// The local lights alone (3 floats per occupied row, albedo applied):
  /// exactly where `mode` and the file allow (relight/lamp_light.h), else
  /// from the model's reconstruction or T (relight/local_relight.h; with a
  /// warning, once, where the file cannot light them exactly); refuses a file
  /// without positions and lights that enclose a pixel's position.
  /// anchorSpread: models only, as modelLocalRelight.
  std::function<std::vector<float>(const std::vector<LocalLight>&, double anchorSpread,
                                   const LampSettings& settings)>
      relightLocal;
  /// A map's sources alone (3 floats per occupied row, albedo applied), lit
  /// exactly as distant discs (ExactLamps::relight), `rays` per camera
  /// sample in a penumbra; only where sourcesUnavailable is empty.
  std::function<std::vector<float>(const std::vector<MapSource>&, int rays)> relightSources;
  /// Why the file cannot light a map's sources exactly (exactLampsUnavailable's
  /// words); empty when it can.
  std::string sourcesUnavailable;
  /// The shadow rays its exact lamps have traced so far (0 where none).
  std::function<long long()> lampShadowRays = [] { return 0LL; };
};

/// Frames a batch relights together: a transport shares one pass over T among
/// them, a model one projection onto its bases (ModelRelighter::lightGroup);
/// the group bounds the lightings held.
inline constexpr size_t kFramesPerGroup = 32;

/// Frames [0, count) of a batch in groups of kFramesPerGroup, in order:
/// lightingsOf(first, n) makes frames first .. first + n - 1's lightings,
/// relightGroup(first, lightings) relights them. The seconds spent making
/// lightings are added to lightingSeconds when given. The CLI's batches
/// and Python's relight_batch both go through here.
void relightInGroups(
    size_t count,
    const std::function<std::vector<LatticeLighting>(size_t first, size_t n)>& lightingsOf,
    const std::function<void(size_t first, const std::vector<LatticeLighting>&)>& relightGroup,
    double* lightingSeconds = nullptr);
/// The same with lightingOf(i) frame i's lighting, called for a group's
/// frames at once (thread-safe).
void relightInGroups(
    size_t count, const std::function<LatticeLighting(size_t frame)>& lightingOf,
    const std::function<void(size_t first, const std::vector<LatticeLighting>&)>& relightGroup,
    double* lightingSeconds = nullptr);

/// Opens a model or transport file under a rank limit (models only: a
/// ParameterError for a transport that is given one).
RelightSource openRelightSource(const std::string& path, const RankLimit& maxRank = {});

}  // namespace acpca
