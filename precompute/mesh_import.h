#pragma once
// A model file read by assimp in a child process. Real files are often broken
// (Debian's assimp-testmodels has some that crash the importer or abort it
// with no message), and a crash there must not take the renderer with it: the
// child reads the file and copies what assimp returns into plain arrays,
// checking only what it must follow (null arrays, counts, the mesh and
// material indices of nodes); the parent checks everything else (vertex
// indices, finite values) and builds the meshes. A crash, abort or hang of
// the child is reported as "cannot read the mesh", naming the file.
#include <cstdint>
#include <string>
#include <vector>

namespace acpca {

/// A material as the file gives it; its texture is not read yet.
struct ImportedMaterial {
  std::string name;
  float color[3] = {1, 1, 1};
  bool hasColor = false;
  std::string textureReference;  ///< empty: no base-colour or diffuse texture
  unsigned uvSet = 0;
  bool textureTransformed = false;  ///< a UV transform the renderer ignores
  /// An embedded texture: the image file's bytes (compressed: embeddedHeight
  /// 0, format hint set) or raw 8-bit BGRA texels, top row first.
  bool embedded = false;
  std::string formatHint;
  unsigned embeddedWidth = 0, embeddedHeight = 0;
  std::vector<std::uint8_t> embeddedBytes;
};

/// One mesh of the file under one node, in the file's coordinates (the node
/// transforms applied): its triangles' corners index its own vertices.
struct ImportedPart {
  std::string name;
  unsigned material = 0;
  std::vector<float> positions;  ///< 3 per vertex
  std::vector<float> normals;    ///< 3 per vertex (inverse transpose), or none
  std::vector<float> uvs;        ///< 2 per vertex of the material's uv set, or none
  /// 3 per vertex, or none: the file's, or assimp's from the first uv set
  /// (aiProcess_CalcTangentSpace), node transform applied; unchecked.
  std::vector<float> tangents;
  std::vector<std::uint32_t> corners;  ///< 3 per triangle, unchecked
};

struct ImportedModel {
  std::vector<ImportedMaterial> materials;
  std::vector<ImportedPart> parts;
};

/// Reads `path` with assimp in a child process (see above). Throws UserError
/// naming the file when assimp refuses it or crashes, aborts or runs past
/// `seconds` on it (negative: defaultImportSeconds). The child dies with the
/// process that waits for it.
ImportedModel importModelIsolated(const std::string& path, double seconds = -1);

/// A minute plus a second per MiB of file: assimp reads tens of MiB a second,
/// and some malformed files make it loop for ever (a PLY header cut short).
double defaultImportSeconds(const std::string& path);

}  // namespace acpca
