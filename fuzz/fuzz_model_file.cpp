// Raw bytes as a model file: refused with a UserError, or read and relit
// under constant light with a finite result.
#include "fuzz/fuzz_support.h"
#include "lighting/environment.h"
#include "lighting/lighting.h"
#include "model/model.h"
#include "model/model_file.h"
#include "relight/model_relighter.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  using namespace acpca;
  const std::string path = fuzz::writeInput(data, size, ".h5");
  return fuzz::runReader([&] {
    const Model model = readModel(path);
    const CubeLattice lattice(model.geometry.cubemapResolution);
    const LatticeLighting light = computeLighting(*loadEnvironment("constant:1"), lattice, {});
    ModelRelighter relighter(model);
    fuzz::requireFinite(relighter.relight(light), "relit value");
  });
}
