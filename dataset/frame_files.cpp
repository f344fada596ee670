#include "dataset/frame_files.h"

#include <algorithm>
#include <iomanip>
#include <utility>

#include "core/error.h"

namespace acpca {

int frameIndexDigits(long long frames) {
  const std::string last = std::to_string(std::max(0LL, frames - 1));
  return std::max(5, static_cast<int>(last.size()));
}

std::string indexedFrameStem(long long index, int digits, const std::string& readable) {
  return concat(std::setw(digits), std::setfill('0'), index, "_", readable);
}

void requireDistinctFiles(size_t frames,
                          const std::function<std::vector<std::string>(size_t)>& filesOf,
                          const std::function<std::string(size_t)>& lightingOf) {
  // Each path's hash and frame, sorted: equal paths have equal hashes, so
  // only frames whose hashes meet are compared by name.
  std::vector<std::pair<size_t, size_t>> hashes;
  for (size_t i = 0; i < frames; ++i)
    for (const std::string& path : filesOf(i))
      hashes.emplace_back(std::hash<std::string>{}(path), i);
  std::sort(hashes.begin(), hashes.end());
  for (size_t k = 1; k < hashes.size(); ++k) {
    if (hashes[k].first != hashes[k - 1].first) continue;
    const size_t first = hashes[k - 1].second, second = hashes[k].second;
    const std::vector<std::string> a = filesOf(first), b = filesOf(second);
    for (const std::string& path : b)
      if (std::count(a.begin(), a.end(), path) > (first == second ? 1 : 0))
        throw UserError(concat("two frames of the batch would be written to ", path, " (",
                               lightingOf(first), ", and ", lightingOf(second),
                               "): the second would replace the first"));
  }
}

}  // namespace acpca
