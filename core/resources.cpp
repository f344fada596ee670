#include "core/resources.h"

#include <sys/resource.h>
#include <sys/statvfs.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>

#include "core/error.h"
#include "core/text.h"

namespace acpca {

namespace {

constexpr long long kUnlimited = std::numeric_limits<long long>::max();

long long readNumber(const std::string& path) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text) || text == "max") return kUnlimited;
  try {
    return std::stoll(text);
  } catch (const std::exception&) {
    return kUnlimited;
  }
}

long long limitValue(int resource) {
  rlimit limit{};
  if (::getrlimit(resource, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return kUnlimited;
  return static_cast<long long>(std::min<rlim_t>(limit.rlim_cur, kUnlimited));
}

}  // namespace

long long freeDiskBytes(const std::string& directory) {
  struct statvfs s {};
  const std::string dir = directory.empty() ? "." : directory;
  if (::statvfs(dir.c_str(), &s) != 0) return kUnlimited;
  return static_cast<long long>(s.f_bavail) * static_cast<long long>(s.f_frsize);
}

long long fileSizeLimit() {
  const long long limit = limitValue(RLIMIT_FSIZE);
  return limit == kUnlimited ? -1 : limit;
}

long long availableMemoryBytes() {
  long long available = kUnlimited;
  {
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    long long kib = 0;
    while (meminfo >> key >> kib) {
      if (key == "MemAvailable:") {
        available = kib * 1024;
        break;
      }
      meminfo.ignore(256, '\n');
    }
  }
  // cgroup v2 (a container's limit), then v1.
  for (const auto& [limitFile, usageFile] :
       {std::pair<const char*, const char*>{"/sys/fs/cgroup/memory.max",
                                            "/sys/fs/cgroup/memory.current"},
        {"/sys/fs/cgroup/memory/memory.limit_in_bytes",
         "/sys/fs/cgroup/memory/memory.usage_in_bytes"}}) {
    const long long limit = readNumber(limitFile);
    if (limit == kUnlimited || limit >= (1LL << 60)) continue;
    const long long usage = readNumber(usageFile);
    available = std::min(available, std::max(0LL, limit - (usage == kUnlimited ? 0 : usage)));
    break;
  }
  // ulimit -v: what this process may still map.
  const long long addressSpace = limitValue(RLIMIT_AS);
  if (addressSpace != kUnlimited) {
    std::ifstream statm("/proc/self/statm");
    long long pages = 0;
    statm >> pages;
    available = std::min(available, std::max(0LL, addressSpace - pages * ::sysconf(_SC_PAGESIZE)));
  }
  return available;
}

void requireResources(const ResourceNeed& need, bool force) {
  if (force) return;
  const auto instead = [](const std::string& advice) {
    return concat(advice.empty() ? std::string() : "; " + advice,
                  "; forcing the run skips this check");
  };
  if (need.diskBytes > 0) {
    const long long free = freeDiskBytes(need.diskDirectory);
    std::error_code ec;
    const std::string where =
        std::filesystem::absolute(need.diskDirectory.empty() ? "." : need.diskDirectory, ec)
            .lexically_normal()
            .string();
    if (free != kUnlimited && need.diskBytes > free)
      throw UserError(concat(need.what, " needs up to ", formatBytes(need.diskBytes),
                             " on disk, and ", where, " has ", formatBytes(free), " free",
                             instead(need.diskAdvice)));
    const long long largest = need.largestFile > 0 ? need.largestFile : need.diskBytes;
    const long long fileLimit = fileSizeLimit();
    if (fileLimit >= 0 && largest > fileLimit)
      throw UserError(concat(need.what, " needs files of up to ", formatBytes(largest),
                             ", and this process may write files of at most ",
                             formatBytes(fileLimit), " (ulimit -f)", instead(need.diskAdvice)));
  }
  if (need.memoryBytes > 0) {
    const long long available = availableMemoryBytes();
    if (available != kUnlimited && need.memoryBytes > available)
      throw UserError(concat(need.what, " needs about ", formatBytes(need.memoryBytes),
                             " of memory, and ", formatBytes(available), " are available",
                             instead(need.memoryAdvice)));
  }
}

long long peakMemoryBytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<long long>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

}  // namespace acpca
