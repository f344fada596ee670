#include "eval/method_sweep.h"

#include <algorithm>
#include <numeric>

#include "cluster/compress.h"
#include "cluster/model_fit.h"
#include "core/error.h"
#include "core/stopwatch.h"
#include "eval/error_measures.h"
#include "lighting/domain_lighting.h"
#include "lighting/lighting.h"
#include "relight/dense_relight.h"

namespace acpca {

namespace {

const std::vector<std::string> kMethods{
    "global", "block", "adaptive-quad", "adaptive-quad-exact", "adaptive-binary", "cpca"};

}  // namespace

const std::vector<std::string>& sweepMethodNames() {
  return kMethods;
}

void checkSweepMethods(const std::vector<std::string>& methods) {
  for (const auto& m : methods)
    if (std::find(kMethods.begin(), kMethods.end(), m) == kMethods.end())
      throw ParameterError("methods", m,
                           "is not one of global, block, adaptive-quad, adaptive-quad-exact, "
                           "adaptive-binary, cpca");
}

EvaluationData loadEvaluationData(const TransportReader& transport, std::vector<std::string> envs) {
  EvaluationData d;
  d.transport = &transport;
  d.envs = envs.empty() ? defaultEvaluationSet() : std::move(envs);
  const DomainLighting domain(transport.header());
  for (const auto& e : d.envs) d.lightings.push_back(domain(*loadEnvironment(e), {}));
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
    r.msPerFrame = medianMilliseconds([&] { relight(data.lightings[0], image.data()); }, frames);
  return first;
}

namespace {

/// One sweep: a global basis per energy, then every wanted method's models
/// over it, each relit under every map and handed to the observer.
class MethodSweep {
 public:
  MethodSweep(const EvaluationData& data, const SweepSettings& s, const SweepObserver& observe)
      : data_(data), s_(s), observe_(observe), transport_(*data.transport) {}

  std::vector<SweepResult> run() {
    for (double g : s_.globalEnergies) sweepBasis(g);
    return std::move(results_);
  }

 private:
  void log(const std::string& text) const {
    if (s_.log) s_.log(text);
  }
  bool wanted(const std::string& method) const {
    return std::find(s_.methods.begin(), s_.methods.end(), method) != s_.methods.end();
  }

  /// Relights every map, records errors (and timing), tells the observer.
  void measure(SweepResult r, ModelRelighter& relighter, const std::vector<int>& clusterOfRow) {
    const std::vector<float> first =
        measureMaps(data_, r, s_.timingFrames,
                    [&](const LatticeLighting& l, float* rgb) { relighter.relight(l, rgb); });
    r.modelBytes = relighter.bytesPerFrame();
    r.costPerPixel = relighter.costPerPixel();
    log(concat(r.method, " ", r.setting, " g=", r.globalEnergy, " tol=", r.tolerance, ": ",
               r.clusters, " clusters, cost/pixel ", r.costPerPixel, ", image error ", r.imageError,
               ", transport error ", r.transportError,
               std::isnan(r.msPerFrame) ? std::string() : concat(", ", r.msPerFrame, " ms/frame")));
    if (observe_) observe_(r, first, clusterOfRow);
    results_.push_back(r);
  }

  /// The global basis at energy g and every method's settings over it.
  void sweepBasis(double g) {
    const Stopwatch basisWatch;
    GlobalBasisOptions basisOptions;
    basisOptions.energy = g;
    basis_ = computeGlobalBasis(transport_, basisOptions);
    projection_ = projectOntoBasis(transport_, basis_);
    basisSeconds_ = basisWatch.seconds();
    g_ = g;
    log(concat("global energy ", g, ": N = ", basis_.globalBases(), " (", basisSeconds_, " s)"));
    const bool highestEnergy =
        g == *std::max_element(s_.globalEnergies.begin(), s_.globalEnergies.end());
    const double highestTolerance = *std::max_element(s_.tolerances.begin(), s_.tolerances.end());
    for (double tol : s_.tolerances) {
      for (bool mean : {false, true}) {
        const ClusterInput in{&projection_.coefficients,
                              &transport_.header().pixels,
                              transport_.header().camera.size,
                              tol,
                              mean,
                              kDefaultClusteringDims};
        if (!mean)
          sweepWithoutMean(in, tol == highestTolerance);
        else if (wanted("adaptive-binary") || wanted("cpca"))
          sweepWithMean(in, highestEnergy);
      }
    }
  }

  void sweepWithoutMean(const ClusterInput& in, bool highestTolerance) {
    const double tol = in.tolerance;
    // Global PCA once per basis: its nested truncations cover the lower tolerances.
    if (wanted("global") && highestTolerance)
      evaluate(
          "global", "N", tol, [&] { return singleCluster(in); }, false);
    if (wanted("block"))
      for (int b : s_.blockSizes)
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
  }

  void sweepWithMean(const ClusterInput& in, bool highestEnergy) {
    const double tol = in.tolerance;
    std::vector<int> all(in.rows());
    std::iota(all.begin(), all.end(), 0);
    BinaryOptions b;
    b.initialClusters = 8;
    const bool cpcaHere = wanted("cpca") && (highestEnergy || !s_.cpcaAtHighestEnergyOnly);
    std::vector<int> ks = cpcaHere ? s_.cpcaClusters : std::vector<int>{};
    if (wanted("adaptive-binary")) {
      const int found = evaluate(
          "adaptive-binary", "K0=8", tol, [&] { return adaptiveBinary(in, b); }, true);
      // CPCA with as many clusters as the adaptive split found: the paper's comparison.
      if (wanted("cpca") && s_.cpcaMatchingBinary) ks.push_back(found);
    }
    for (int k : ks) {
      CpcaOptions o;
      o.clusters = k;
      evaluate(
          "cpca", concat("K=", k), tol, [&] { return cpca(in, all, o); }, true);
    }
  }

  /// One setting: its model fitted, relit and measured; for global PCA also
  /// its lower ranks. Returns the model's cluster count.
  int evaluate(const std::string& method, const std::string& setting, double tol,
               const std::function<Partition()>& makePartition, bool mean) {
    const Stopwatch watch;
    const Partition partition = makePartition();
    std::unique_ptr<ModelRelighter> relighter;
    SweepResult r{method, setting, g_, tol};
    r.globalBases = basis_.globalBases();
    r.basisSeconds = basisSeconds_;
    std::vector<int> clusterOfRow;
    std::vector<int> ranks;
    // Global PCA at lower ranks (below): the energy of its dropped
    // coefficients, per divisor (the bases are orthonormal and the residual
    // orthogonal to them, so the energies add).
    constexpr int kDivisors[] = {8, 4, 2};
    double dropped[3] = {0, 0, 0};
    {
      ModelOptions options;
      options.tolerance = tol;
      options.mean = mean;
      const Model m = buildModel(transport_.header(), basis_, projection_, partition, options);
      relighter = std::make_unique<ModelRelighter>(m);
      r.clusters = m.clusters();
      r.transportError = m.transportError;
      ranks = m.ranks;
      if (observe_) clusterOfRow = m.clusterOfRow();
      if (method == "global" && m.clusters() == 1)
        for (int d = 0; d < 3; ++d)
          for (long long row = 0; row < m.rows(); ++row)
            for (int j = m.ranks[0] / kDivisors[d]; j < m.ranks[0]; ++j)
              dropped[d] += double(m.coefficient(0, row, j)) * m.coefficient(0, row, j);
    }  // the relighter holds its own copy
    r.compressSeconds = watch.seconds();
    measure(r, *relighter, clusterOfRow);
    // PCA bases are nested: the first k of them are the best rank-k fit, so
    // global PCA at lower ranks comes from the same model (a rank limit).
    if (method == "global" && ranks.size() == 1 && ranks[0] > 8)
      for (int d = 0; d < 3; ++d) {
        const int k = ranks[0] / kDivisors[d];
        relighter->setMaxRank(k);
        SweepResult t = r;
        t.setting = concat("first ", k, " bases");
        t.transportError = std::sqrt(r.transportError * r.transportError +
                                     dropped[d] / std::max(projection_.transportEnergy(), 1e-300));
        measure(t, *relighter, clusterOfRow);
      }
    return r.clusters;
  }

  const EvaluationData& data_;
  const SweepSettings& s_;
  const SweepObserver& observe_;
  const TransportReader& transport_;
  std::vector<SweepResult> results_;
  GlobalBasis basis_;
  GlobalProjection projection_;
  double basisSeconds_ = 0, g_ = 0;
};

}  // namespace

std::vector<SweepResult> sweepMethods(const EvaluationData& data, const SweepSettings& s,
                                      const SweepObserver& observe) {
  checkSweepMethods(s.methods);
  return MethodSweep(data, s, observe).run();
}

}  // namespace acpca
