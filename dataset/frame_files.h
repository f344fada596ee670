#pragma once
// A batch's file names (docs/datasets.md, "Frame names"): every frame's files
// start with its index in the batch, zero-padded, so that no two frames share
// a file whatever their lightings are called, and names sort in batch order.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace acpca {

/// Digits of a frame index in a batch of `frames`: at least 5, and enough for
/// the last index.
int frameIndexDigits(long long frames);

/// "00042_sky_y15": the frame's index in the batch, zero-padded to `digits`,
/// then its readable part (map, rotation, light set, view).
std::string indexedFrameStem(long long index, int digits, const std::string& readable);

/// Refuses (UserError, before any work) a batch of `frames` frames that would
/// write one path twice: `filesOf(i)` are frame i's paths, `lightingOf(i)` its
/// lighting in words; the error names the path and both lightings. It keeps a
/// hash per path rather than the paths, so a batch of a million frames costs
/// a few MB while it is checked.
void requireDistinctFiles(size_t frames,
                          const std::function<std::vector<std::string>(size_t)>& filesOf,
                          const std::function<std::string(size_t)>& lightingOf);

}  // namespace acpca
