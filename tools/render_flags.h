#pragma once
// The flags that say how a scene's rows are rendered and compressed, shared by
// precompute and build (rendering) and by compress and build (compression).
// Numbers bind straight to the library's option structs, so their defaults are
// the library's; names (methods, precisions) are parsed into them.
#include <CLI/CLI.hpp>
#include <string>

#include "cluster/compress.h"
#include "precompute/scene.h"
#include "precompute/transport_renderer.h"

namespace acpca::cli {

struct RenderFlags {
  std::string scene, size, camera;
  PrecomputeOptions values;
  std::string precision = precisionName(values.precision);
  std::string antialiasing = kAntialiasingNames.name(values.antialiasing);

  void add(CLI::App& app);
  /// Parsed (UserError on bad names); threads as given.
  PrecomputeOptions options(int threads) const;
  /// The scene with --size and --camera applied, validated.
  Scene loadScene() const;
};

struct CompressFlags {
  CompressOptions values;
  std::string method;  ///< empty: required (compress) or adaptive-quad (build)
  std::string coeffs = coeffPrecisionName(values.coeffs);
  std::string bases = coeffPrecisionName(values.bases);

  /// streamed: build's subset (adaptive-quad by default; no CPCA options).
  void add(CLI::App& app, bool streamed);
  CompressOptions options() const;
};

}  // namespace acpca::cli
