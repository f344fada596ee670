// Raw bytes as a model file: refused with a UserError, or read and relit
// under constant light with a finite result, by both readers: the
// relighter's, cluster by cluster from the file, and the whole model's.
#include "fuzz/fuzz_support.h"
#include "lighting/environment.h"
#include "lighting/lighting.h"
#include "model/model.h"
#include "model/model_file.h"
#include "relight/model_relighter.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  using namespace acpca;
  const std::string path = fuzz::writeInput(data, size, ".h5");
  const auto relitFinite = [](ModelRelighter& relighter) {
    const CubeLattice lattice(relighter.geometry().cubemapResolution);
    const LatticeLighting light = computeLighting(*loadEnvironment("constant:1"), lattice, {});
    fuzz::requireFinite(relighter.relight(light), "relit value");
  };
  fuzz::runReader([&] {
    ModelRelighter relighter(readPackedModel(path));
    relitFinite(relighter);
  });
  return fuzz::runReader([&] {
    ModelRelighter relighter(readModel(path));
    relitFinite(relighter);
  });
}
