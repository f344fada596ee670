// Raw bytes as a model file: the first byte picks the format (OBJ, glTF,
// GLB, PLY, OFF, Collada, STL), the rest is the file. Refused with a
// UserError, or meshes that validate. assimp runs in a child process
// (mesh_import.h): a crash inside Debian's uninstrumented assimp is contained
// and reported as a UserError, while the parent's checks and mesh building,
// our own code, run here under the sanitizers.
#include "fuzz/fuzz_support.h"
#include "precompute/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  using namespace acpca;
  if (size < 1) return 0;
  static const char* const kExtensions[] = {".obj", ".gltf", ".glb", ".ply",
                                            ".off", ".dae",  ".stl"};
  const std::string path = fuzz::writeInput(data + 1, size - 1, kExtensions[data[0] % 7]);
  return fuzz::runReader([&] {
    Scene scene;
    // Well inside libFuzzer's -timeout: a file that makes assimp loop (a PLY
    // header cut short did) is refused as "did not finish", not a finding.
    scene.meshes = loadMeshFile(path, NormalMode::File, kDefaultCreaseDegrees, 5.0);
    scene.validate();
  });
}
