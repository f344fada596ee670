// Raw bytes as an environment image (the first byte picks the format):
// refused with a UserError, or integrated onto a small lattice, finite.
#include "fuzz/fuzz_support.h"
#include "lighting/environment.h"
#include "lighting/lighting.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  using namespace acpca;
  if (size < 1) return 0;
  static const char* const kExtensions[] = {".hdr", ".exr", ".pfm", ".png"};
  const std::string path = fuzz::writeInput(data + 1, size - 1, kExtensions[data[0] % 4]);
  return fuzz::runReader([&] {
    const auto env = loadEnvironmentImage(path);
    const LatticeLighting l = computeLighting(*env, CubeLattice(4), {});
    fuzz::requireFinite(std::vector<float>(l.begin(), l.end()), "lighting");
  });
}
