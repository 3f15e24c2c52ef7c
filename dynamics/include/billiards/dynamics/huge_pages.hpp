// An allocator for the arrays a search reads at random places: a mesh's triangles and its BVH's
// nodes (tens of megabytes for 10⁵ triangles, thousands of 4 KiB pages, more than the
// processor's address-translation caches hold).  An allocation of 2 MiB or more is mapped on
// its own, aligned to 2 MiB, and marked for Linux's transparent huge pages before it is first
// touched (the kernel's `madvise` mode needs the mark, `always` does without), so that it
// spans one translation entry every 2 MiB; where huge pages are off the mark is moot.  Smaller allocations, and systems
// without madvise, take plain operator new.
#pragma once

#include <cstddef>
#include <vector>

namespace billiards::dynamics {

/// Allocates `bytes` aligned to `align` (≤ the huge page's 2 MiB), on huge pages from 2 MiB on.
void* huge_page_allocate(std::size_t bytes, std::size_t align);
/// Frees what huge_page_allocate(bytes, align) returned.
void huge_page_free(void* p, std::size_t bytes, std::size_t align) noexcept;

template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}
  T* allocate(std::size_t n) { return static_cast<T*>(huge_page_allocate(n * sizeof(T), alignof(T))); }
  void deallocate(T* p, std::size_t n) noexcept { huge_page_free(p, n * sizeof(T), alignof(T)); }
  friend bool operator==(const HugePageAllocator&, const HugePageAllocator&) { return true; }
};

/// A contiguous array on huge pages once it is large.
template <class T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

}  // namespace billiards::dynamics
