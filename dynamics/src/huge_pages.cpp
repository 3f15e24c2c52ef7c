// Large arrays on transparent huge pages (huge_pages.hpp).
#include "billiards/dynamics/huge_pages.hpp"

#include <cstdint>
#include <new>

#if __has_include(<sys/mman.h>)
#include <sys/mman.h>
#endif

namespace billiards::dynamics {

namespace {

constexpr std::size_t huge_page = std::size_t(2) << 20;

std::size_t whole_pages(std::size_t bytes) { return (bytes + huge_page - 1) / huge_page * huge_page; }

}  // namespace

#ifdef MADV_HUGEPAGE

// Mapped with a huge page to spare and trimmed to the aligned pages: fresh memory, untouched,
// so that the first touch of each 2 MiB faults in a huge page (where the kernel has one free).
void* huge_page_allocate(std::size_t bytes, std::size_t align) {
  if (bytes < huge_page) return ::operator new(bytes, std::align_val_t(align));
  const std::size_t size = whole_pages(bytes);
  void* mapped = mmap(nullptr, size + huge_page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (mapped == MAP_FAILED) throw std::bad_alloc();
  const auto first = reinterpret_cast<std::uintptr_t>(mapped);
  const std::uintptr_t start = (first + huge_page - 1) & ~(huge_page - 1);
  if (start > first) munmap(mapped, start - first);
  munmap(reinterpret_cast<void*>(start + size), first + huge_page - start);
  void* p = reinterpret_cast<void*>(start);
  madvise(p, size, MADV_HUGEPAGE);  // (advice: refused where huge pages are off, and then moot)
  return p;
}

void huge_page_free(void* p, std::size_t bytes, std::size_t align) noexcept {
  if (bytes < huge_page) ::operator delete(p, std::align_val_t(align));
  else munmap(p, whole_pages(bytes));
}

#else

void* huge_page_allocate(std::size_t bytes, std::size_t align) { return ::operator new(bytes, std::align_val_t(align)); }

void huge_page_free(void* p, std::size_t, std::size_t align) noexcept { ::operator delete(p, std::align_val_t(align)); }

#endif

}  // namespace billiards::dynamics
