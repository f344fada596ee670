#pragma once
// Before any work, a command that writes large files or holds large arrays
// compares what it will need with what the machine has, and refuses with
// both figures and what to do instead: a 16384x16384 transport (3.3 TB) is
// a clear message, not std::bad_alloc hours in. Estimates are upper bounds
// (every pixel occupied, no compression).
#include <string>

namespace acpca {

struct ResourceNeed {
  std::string what;           ///< "the transport", "the frames"
  long long diskBytes = 0;    ///< written under diskDirectory
  long long largestFile = 0;  ///< the largest one file among them
  std::string diskDirectory;
  long long memoryBytes = 0;  ///< held at once
  /// What to do instead when the disk, or the memory, is too small.
  std::string diskAdvice, memoryAdvice;
};

/// Bytes free to this process on the file system holding `directory`.
long long freeDiskBytes(const std::string& directory);
/// The largest file this process may write (RLIMIT_FSIZE), or -1 for no limit.
long long fileSizeLimit();
/// Memory this process can still take: the least of MemAvailable, its
/// cgroup's limit less its use, and its address-space limit less its size.
long long availableMemoryBytes();

/// Throws UserError when `need` exceeds what is there, giving both figures
/// and its advice. Does nothing when `force` is set.
void requireResources(const ResourceNeed& need, bool force);

/// This process's peak resident memory so far (reported in --json and logs,
/// never in output files).
long long peakMemoryBytes();

}  // namespace acpca
