#pragma once
// `adaptive-cpca web`: a static site that relights a model on the GPU in a
// browser (docs/formats.md, "Web page"). The model is packed for WebGL2 at
// its stored precision (i8 or f16 coefficients, f16 bases), with the
// directions no pixel sees left out; each map goes as its checked pixels (a
// lat-long file) or its spec (a built-in map), and the page integrates it onto
// the lattice under each rotation as the CLI does.
#include <string>
#include <vector>

#include "relight/rank_limit.h"

namespace acpca {

struct WebExportOptions {
  std::string model;              ///< a model file (compress or build)
  std::string out;                ///< the site's directory
  std::vector<std::string> envs;  ///< maps for the picker (empty: sky)
  RankLimit maxRank;
  std::string title;  ///< empty: the model's file name
};

struct WebExportReport {
  long long pageBytes = 0;   ///< every file the site holds
  long long modelBytes = 0;  ///< model.bin
  long long mapBytes = 0;    ///< the maps' pixels
  std::vector<std::string> files;
  int seenTexels = 0, latticeTexels = 0;
};

/// Writes the site: refuses (UserError) an output directory holding files it
/// did not write, a model without a camera (a captured light set) and a map
/// the page cannot integrate (a cube cross), each naming the input.
WebExportReport exportWebPage(const WebExportOptions& options);

}  // namespace acpca
