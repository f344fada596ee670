#pragma once
// The precompute: fills the transport row of every occupied pixel with Embree
// and streams it to a transport file (docs/design.md section 4).
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/resources.h"
#include "precompute/precompute_options.h"
#include "precompute/scene.h"
#include "transport/transport_file.h"

namespace acpca {

/// What precompute needs at most: every pixel a row (three with bounced
/// light) on disk, and its camera samples, row headers and scene in memory.
ResourceNeed precomputeNeed(const Scene& scene, const std::string& outPath,
                            const PrecomputeOptions& options);

/// Validates the options (UserError on bad values) and writes the transport file
/// atomically: on any failure no file appears at outPath.
PrecomputeStats precomputeTransport(const Scene& scene, const std::string& outPath,
                                    const PrecomputeOptions& options);

/// The rows of chosen pixels on demand, for a build that never writes the
/// whole transport: the G-buffer, lattice, shadow rays and (with bounces) the
/// indirect cache are built once, in the caller's TBB arena; each call renders
/// only the rows asked for, each exactly as precomputeTransport renders it.
class RowSource {
 public:
  /// Validates the options (UserError on bad values); options.threads is not
  /// used (the caller's arena is).
  RowSource(const Scene& scene, const PrecomputeOptions& options);
  ~RowSource();
  /// The header a transport file of the scene would carry: every occupied pixel.
  const TransportHeader& header() const;
  int rowLength() const { return header().rowLength(); }
  /// Fills out (rows.size() x rowLength floats) with the rows of these row
  /// indices, rounded through half when the header's precision is f16 (as the
  /// file stores them), in parallel. Returns the occlusion and path rays traced.
  std::pair<long long, long long> render(const std::vector<long long>& rows, float* out) const;
  /// Triangles, degenerate triangles, the indirect cache's figures.
  const PrecomputeStats& setupStats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace acpca
