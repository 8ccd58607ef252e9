// Private: an allocator for the engine's few arrays that grow with the world (bodies, fixtures, the
// broad phase's proxies and sorted entries).
//
// In a world of a million bodies these arrays are hundreds of megabytes, and a step reaches into them
// at scattered places (the two bodies of a candidate pair, the bodies of an event). With 4 KiB pages
// nearly every such access also misses the TLB and walks the page table; backed by 2 MiB pages (Linux
// transparent huge pages, asked for with madvise: the default setting, "madvise", gives them only to
// memory that asks) the same arrays need 512 times fewer TLB entries. Small arrays are allocated as
// usual. Addresses never reach results, so this changes speed only.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace rattle::detail {

template <class T>
struct LargeArrayAllocator {
  using value_type = T;
  static constexpr std::size_t kHugePage = std::size_t{2} << 20;

  LargeArrayAllocator() = default;
  template <class U>
  LargeArrayAllocator(const LargeArrayAllocator<U>&) noexcept {}  // NOLINT: rebinding, as std::allocator

  T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kHugePage) return static_cast<T*>(::operator new(bytes, std::align_val_t{alignof(T)}));
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, rounded);
    if (p == nullptr) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(p, rounded, MADV_HUGEPAGE);  // a hint: without huge pages it is ordinary memory
#endif
    return static_cast<T*>(p);
  }

  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) < kHugePage) {
      ::operator delete(p, std::align_val_t{alignof(T)});
    } else {
      std::free(p);
    }
  }

  template <class U>
  bool operator==(const LargeArrayAllocator<U>&) const noexcept {
    return true;
  }
};

/// A std::vector whose storage, once large, is asked to live on huge pages.
template <class T>
using LargeArray = std::vector<T, LargeArrayAllocator<T>>;

}  // namespace rattle::detail
