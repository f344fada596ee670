// A map's sources split off for the Python relighter as relight --sun splits
// them (docs/lighting.md, "Lit exactly"): the split made once per map and
// finding, and shared by every frame that relights the map.
#include <map>
#include <mutex>
#include <tuple>

#include "python/module_parts.h"

namespace acpca::python {

struct SourceSplits {
  std::mutex mutex;
  std::map<std::tuple<int, double, double, double>, std::shared_ptr<const SplitEnvironment>> made;
};

namespace {

/// The map's split under `finding`, made on first use.
std::shared_ptr<const SplitEnvironment> splitOf(SourceSplits& splits, const Environment& env,
                                                const SourceFinding& finding) {
  const std::lock_guard lock(splits.mutex);
  const auto key = std::make_tuple(finding.maxSources, finding.brightFactor, finding.minEnergyShare,
                                   finding.maxRadiusDegrees);
  auto& split = splits.made[key];
  if (!split) split = std::make_shared<const SplitEnvironment>(env.splitSources(finding));
  return split;
}

}  // namespace

std::shared_ptr<SourceSplits> newSourceSplits() {
  return std::make_shared<SourceSplits>();
}

const Environment& latticePartOf(const PyEnvironment& env, const PySun& sun, bool exactLamps,
                                 const std::string& unavailable,
                                 const std::function<void()>& warnOnce,
                                 std::vector<MapSource>& sources) {
  sources.clear();
  const int* count = std::get_if<int>(&sun);
  const std::optional<SourceFinding> finding =
      parseSourceFinding(count ? std::to_string(*count) : std::get<std::string>(sun));
  // Only lightings made here (not darkness) carry the cache, and have sources.
  if (!finding || !exactLamps || !env.splits) return *env.env;
  const std::shared_ptr<const SplitEnvironment> split = splitOf(*env.splits, *env.env, *finding);
  if (split->sources.empty()) return *env.env;
  if (!unavailable.empty()) {
    warnOnce();
    return *env.env;
  }
  sources = split->sources;
  return *split->rest;  // kept alive by the cache the PyEnvironment holds
}

}  // namespace acpca::python
