// Raw bytes as a lights file (JSON or CSV, chosen by the first character as
// the reader chooses): refused with a UserError, or lights whose directions
// are unit vectors, two never the same, with positive intensities and solid
// angles given for all or none.
#include "capture/lights_file.h"
#include "fuzz/fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  using namespace acpca;
  const std::string text(reinterpret_cast<const char*>(data), size);
  return fuzz::runReader([&] {
    const LightsFile file = parseLightsFile(text, "fuzz/lights.csv");
    if (file.lights.empty()) std::abort();
    for (size_t i = 0; i < file.lights.size(); ++i) {
      const LightEntry& e = file.lights[i];
      if (!e.direction.allFinite() || std::abs(e.direction.norm() - 1) > 1e-9 ||
          !(e.irradiance.array() > 0).all() || !e.irradiance.allFinite() ||
          (e.solidAngle >= 0) != file.cellsGiven() || e.image.empty())
        std::abort();
      for (size_t j = 0; j < i; ++j)
        if (e.direction == file.lights[j].direction) std::abort();
    }
  });
}
