#pragma once
// Large arrays on 2 MiB pages where the kernel allows it (transparent huge
// pages in "madvise" mode, Debian's default, need the request). A frame of the
// relighter streams a few hundred MB; on 4 KiB pages that is a TLB miss, and a
// restart of the hardware prefetcher, every 4 KiB. Small arrays stay on the
// ordinary heap.
#include <cstddef>
#include <new>
#include <utility>
#include <vector>

namespace acpca {

namespace huge_pages {
/// Arrays of at least this many bytes get their own 2 MiB-aligned mapping.
inline constexpr std::size_t kMinimumBytes = std::size_t(4) << 20;
void* allocate(std::size_t bytes);
void release(void* p, std::size_t bytes);
}  // namespace huge_pages

template <typename T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <typename U>
  HugePageAllocator(const HugePageAllocator<U>&) {}
  T* allocate(std::size_t n) { return static_cast<T*>(huge_pages::allocate(n * sizeof(T))); }
  /// Default-initializes: a vector sized without a value leaves numbers
  /// unset, for whoever fills every one on many threads (zeroing them first
  /// would touch every fresh page on one).
  template <typename U>
  void construct(U* p) {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  void deallocate(T* p, std::size_t n) { huge_pages::release(p, n * sizeof(T)); }
  template <typename U>
  bool operator==(const HugePageAllocator<U>&) const {
    return true;
  }
  template <typename U>
  bool operator!=(const HugePageAllocator<U>&) const {
    return false;
  }
};

/// A vector whose storage is asked for on huge pages once it is large.
/// HugePageVector<float>(n) and resize(n) leave the new numbers unset.
template <typename T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace acpca
