#include "core/huge_pages.h"

#include <sys/mman.h>

#include <cstdlib>

namespace acpca::huge_pages {

namespace {
constexpr std::size_t kHugePage = std::size_t(2) << 20;
std::size_t roundedUp(std::size_t bytes) {
  return (bytes + kHugePage - 1) / kHugePage * kHugePage;
}
}  // namespace

void* allocate(std::size_t bytes) {
  if (bytes < kMinimumBytes) return ::operator new(bytes);
  void* p = std::aligned_alloc(kHugePage, roundedUp(bytes));
  if (!p) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
  // Advice only: where the kernel has no huge pages to give, ordinary ones.
  madvise(p, roundedUp(bytes), MADV_HUGEPAGE);
#endif
  return p;
}

void release(void* p, std::size_t bytes) {
  if (bytes < kMinimumBytes)
    ::operator delete(p);
  else
    std::free(p);
}

}  // namespace acpca::huge_pages
