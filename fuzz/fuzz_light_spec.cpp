// Raw bytes as a --light spec, sweeps (A:B:S) expanded: refused with a
// UserError, or lights whose lattice lighting, seen from a few points, is
// finite and non-negative.
#include "fuzz/fuzz_support.h"
#include "lighting/local_light.h"

namespace {

void check(const acpca::LocalLight& light) {
  using namespace acpca;
  static const CubeLattice lattice(4);
  for (const Vec3& at : {Vec3(0, 0, 0), Vec3(1, -2, 0.5), Vec3(-1e3, 7, 3e4)}) {
    const LatticeLighting lighting = localLighting({light}, lattice, at);
    for (double v : lighting)
      if (!std::isfinite(v) || v < 0 || !std::isfinite(static_cast<float>(v))) {
        std::fprintf(stderr, "lighting %g from accepted light %s\n", v, light.spec.c_str());
        std::abort();
      }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  using namespace acpca;
  const std::string spec(reinterpret_cast<const char*>(data), size);
  return fuzz::runReader([&] {
    const std::vector<std::string> specs = expandLightSweep(spec);
    if (specs.empty() || static_cast<long long>(specs.size()) > kMaxLightSweepSpecs) std::abort();
    // The first and the last of a sweep: its ends.
    for (const std::string& one : {specs.front(), specs.back()}) check(parseLocalLight(one));
  });
}
