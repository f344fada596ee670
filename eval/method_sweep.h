#pragma once
// Every compression method over a sweep of settings, each model relit under an
// evaluation set and compared with the dense ground truth (docs/design.md section
// 7). The global basis and projection are computed once per global energy and
// shared by every method. `bench methods` compares costs at equal error from it
// (method_comparison.h); `eval` adds timing, images, plots and the baselines.
#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "lighting/environment.h"
#include "relight/model_relighter.h"
#include "transport/transport_file.h"

namespace acpca {

/// The lightings a sweep is judged by and their dense relights.
struct EvaluationData {
  const TransportReader* transport = nullptr;
  std::vector<std::string> envs;
  std::vector<LatticeLighting> lightings;
  std::vector<std::vector<float>> truth;  ///< per map: 3 floats per row, albedo applied
};
/// Loads the maps (default: the evaluation set) and relights them densely.
EvaluationData loadEvaluationData(const TransportReader& transport, std::vector<std::string> envs);

struct SweepSettings {
  /// global, block, adaptive-quad, adaptive-quad-exact, adaptive-binary, cpca
  std::vector<std::string> methods;
  std::vector<double> globalEnergies{0.99, 0.999}, tolerances{0.99, 0.999};
  std::vector<int> blockSizes{8, 16}, cpcaClusters{10, 5000};
  bool cpcaMatchingBinary = true;  ///< also CPCA with as many clusters as adaptive-binary found
  bool cpcaAtHighestEnergyOnly = false;  ///< the CPCA cluster counts at the largest energy only
  int timingFrames = 0;                  ///< > 0: median ms over that many frames after a warm-up
  std::function<void(const std::string&)> log;  ///< one line per setting measured
};
/// Throws ParameterError naming a method the sweep does not know.
void checkSweepMethods(const std::vector<std::string>& methods);

struct SweepResult {
  std::string method, setting;
  double globalEnergy = 0, tolerance = 0;
  int clusters = 0, globalBases = 0;
  double costPerPixel = 0;
  double transportError = NAN;  ///< not measured for truncations
  double compressSeconds = 0;   ///< partition + fits (the shared basis not included)
  double basisSeconds = 0;      ///< the shared global basis and projection
  double msPerFrame = NAN;
  long long modelBytes = 0;               ///< bytes one frame reads
  std::vector<double> errors{}, psnrs{};  ///< per map
  double imageError = 0;                  ///< RMS of the per-map relative L2
};

/// What a caller may keep of each setting: the relit first map and, for
/// clustered methods, each row's cluster.
using SweepObserver = std::function<void(const SweepResult&, const std::vector<float>& firstImage,
                                         const std::vector<int>& clusterOfRow)>;

std::vector<SweepResult> sweepMethods(const EvaluationData& data, const SweepSettings& settings,
                                      const SweepObserver& observe = {});

/// Relights every map of the set with `relight`, filling r.errors, r.psnrs and
/// r.imageError, and returns the first map's image; with frames > 0 also
/// r.msPerFrame, the median of that many frames of the first map.
std::vector<float> measureMaps(const EvaluationData& data, SweepResult& r, int frames,
                               const std::function<void(const LatticeLighting&, float*)>& relight);

/// The methods a sweep knows, in the order it runs them.
const std::vector<std::string>& sweepMethodNames();

}  // namespace acpca
