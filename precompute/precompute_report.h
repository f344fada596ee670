#pragma once
// What a precompute was asked and what it did: the JSON the CLI's --json,
// Python's precompute() and a build model's settings share (one key per
// field), and the same in words for the log.
#include <nlohmann/json.hpp>

#include "precompute/precompute_options.h"

namespace acpca {

/// How rows are rendered: cubemap, spp, antialiasing, texel_rays, precision,
/// bounces, indirect_samples, indirect_cache_cell (docs/formats.md).
nlohmann::json toJson(const PrecomputeOptions& options);

/// The figures of one precompute (rays, rows, seconds, the indirect cache).
nlohmann::json toJson(const PrecomputeStats& stats);

/// The same in a few lines of words, for the log (with this process's peak
/// memory and the rank count).
std::string describeInWords(const PrecomputeStats& stats, const PrecomputeOptions& options,
                            ImageSize size);

}  // namespace acpca
