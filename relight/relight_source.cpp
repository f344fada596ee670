#include "relight/relight_source.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/error.h"
#include "core/stopwatch.h"
#include "core/warning.h"
#include "lighting/spec_parsing.h"
#include "model/model_file.h"
#include "relight/dense_relight.h"
#include "relight/local_relight.h"

namespace acpca {

namespace {

/// A file's exact lamps where it can light them (null otherwise), and the
/// warning, given once, of why it cannot. `owner` keeps the header alive.
class LampsOfFile {
 public:
  template <typename Owner>
  LampsOfFile(const std::shared_ptr<Owner>& owner, const std::string& path, bool model)
      : state_(std::make_shared<State>()) {
    const TransportHeader& header = headerOf(*owner);
    state_->owner = owner;
    state_->why = exactLampsUnavailable(header, model);
    state_->path = path;
    if (state_->why.empty()) state_->exact = std::make_unique<ExactLamps>(header);
  }
  std::vector<float> relight(
      const std::vector<LocalLight>& lights, const LampSettings& settings,
      const std::function<std::vector<float>(const std::vector<LocalLight>&)>& lattice) const {
    return relightLocalLights(lights, settings, state_->exact.get(), lattice, [&] {
      std::call_once(state_->warned, [&] { warn(latticeLampsWarning(state_->path, state_->why)); });
    });
  }
  long long shadowRays() const { return state_->exact ? state_->exact->shadowRays() : 0; }
  /// Why its lamps cannot be lit exactly; empty when they can.
  const std::string& unavailable() const { return state_->why; }
  std::vector<float> relightDiscs(const std::vector<MapSource>& discs, int rays) const {
    ACPCA_CHECK(state_->exact, "a map's sources lit exactly from ", state_->path, ": ",
                state_->why);
    return state_->exact->relight({}, rays, discs);
  }

 private:
  static const TransportHeader& headerOf(const ModelRelighter& m) { return m.geometry(); }
  static const TransportHeader& headerOf(const TransportReader& t) { return t.header(); }
  struct State {
    std::shared_ptr<const void> owner;
    std::string why, path;
    std::unique_ptr<ExactLamps> exact;
    std::once_flag warned;
  };
  std::shared_ptr<State> state_;
};

/// What a source says of its file's exact lamps: the rays traced, and the
/// map's sources lit exactly (or why not).
void attachLamps(RelightSource& s, const LampsOfFile& lamps) {
  s.lampShadowRays = [lamps] { return lamps.shadowRays(); };
  s.sourcesUnavailable = lamps.unavailable();
  s.relightSources = [lamps](const std::vector<MapSource>& discs, int rays) {
    return lamps.relightDiscs(discs, rays);
  };
}

}  // namespace

RelightSource openRelightSource(const std::string& path, const RankLimit& maxRank) {
  RelightSource s;
  if (isModelFile(path)) {
    // Read cluster by cluster into the relighter's layout: no copy of the file's arrays.
    const std::shared_ptr<const PackedModel> packed = readPackedModel(path);
    s.method = packed->method;
    s.model = std::make_shared<ModelRelighter>(packed);
    maxRank.applyTo(*s.model);
    s.header = s.model->geometry();
    s.bytesPerPass = s.model->bytesPerFrame();
    s.relight = [relighter = s.model](const std::vector<LatticeLighting>& l,
                                      std::vector<double>& ms) {
      // One projection for the group, then each frame's pixels: a frame's
      // time is its share of the projection plus its own shading.
      const Stopwatch group;
      relighter->lightGroup(l);
      const double shared = group.milliseconds() / std::max<size_t>(1, l.size());
      std::vector<std::vector<float>> out;
      ms.clear();
      for (size_t k = 0; k < l.size(); ++k) {
        const Stopwatch watch;
        out.emplace_back(3 * relighter->rows());
        relighter->shadeFrame(k, out.back().data());
        ms.push_back(shared + watch.milliseconds());
      }
      return out;
    };
    // The columns local lights meet, kept from frame to frame (made at the
    // first local light: environment-only runs never need them).
    auto kept = std::make_shared<std::optional<LocalLightColumns>>();
    const LampsOfFile lamps(s.model, path, true);
    attachLamps(s, lamps);
    s.relightLocal = [relighter = s.model, path, kept, lamps](const std::vector<LocalLight>& lights,
                                                              double anchorSpread,
                                                              const LampSettings& settings) {
      requireLocalLightsApply(relighter->geometry(), path, true, lights);
      return lamps.relight(lights, settings, [&](const std::vector<LocalLight>& some) {
        if (!*kept) kept->emplace(relighter->packed());
        return modelLocalRelight(*relighter, some, anchorSpread, &**kept);
      });
    };
    return s;
  }
  if (maxRank.limited())
    throw ParameterError("maximum rank", maxRank.text(),
                         concat(path, " is a transport file, which has no ranks"));
  auto transport = std::make_shared<TransportReader>(path);
  s.header = transport->header();
  s.method = "dense";
  s.dense = true;
  s.bytesPerPass = transport->rows() * static_cast<long long>(transport->rowLength()) *
                   (transport->header().precision == Precision::F16 ? 2 : 4);
  s.relight = [transport](const std::vector<LatticeLighting>& l, std::vector<double>& ms) {
    const Stopwatch watch;
    auto out = denseRelight(*transport, l);
    ms.assign(l.size(), watch.milliseconds() / std::max<size_t>(1, l.size()));
    return out;
  };
  const LampsOfFile lamps(transport, path, false);
  attachLamps(s, lamps);
  s.relightLocal = [transport, path, lamps](const std::vector<LocalLight>& lights, double,
                                            const LampSettings& settings) {
    requireLocalLightsApply(transport->header(), path, false, lights);
    return lamps.relight(lights, settings, [&](const std::vector<LocalLight>& some) {
      return denseLocalRelight(*transport, some);
    });
  };
  return s;
}

void relightInGroups(
    size_t count,
    const std::function<std::vector<LatticeLighting>(size_t first, size_t n)>& lightingsOf,
    const std::function<void(size_t first, const std::vector<LatticeLighting>&)>& relightGroup,
    double* lightingSeconds) {
  for (size_t first = 0; first < count; first += kFramesPerGroup) {
    const Stopwatch watch;
    const size_t n = std::min(count - first, kFramesPerGroup);
    const std::vector<LatticeLighting> lightings = lightingsOf(first, n);
    ACPCA_CHECK(lightings.size() == n, lightings.size(), " lightings for ", n, " frames");
    if (lightingSeconds) *lightingSeconds += watch.seconds();
    relightGroup(first, lightings);
  }
}

void relightInGroups(
    size_t count, const std::function<LatticeLighting(size_t frame)>& lightingOf,
    const std::function<void(size_t first, const std::vector<LatticeLighting>&)>& relightGroup,
    double* lightingSeconds) {
  // A group's lightings at once: one map's integration keeps a few cores
  // busy, a group's keep them all.
  const auto lightingsOf = [&](size_t first, size_t n) {
    std::vector<LatticeLighting> lightings(n);
    tbb::parallel_for(size_t(0), n, [&](size_t k) { lightings[k] = lightingOf(first + k); });
    return lightings;
  };
  relightInGroups(count, lightingsOf, relightGroup, lightingSeconds);
}

}  // namespace acpca
