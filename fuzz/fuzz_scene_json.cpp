// Raw bytes as a scene file: refused with a UserError, or a scene that validates.
#include "fuzz/fuzz_support.h"
#include "precompute/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  using namespace acpca;
  const std::string path = fuzz::writeInput(data, size, ".json");
  return fuzz::runReader([&] { loadSceneJson(path).validate(); });
}
