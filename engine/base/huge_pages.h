// A std::vector allocator that asks Linux for transparent huge pages (2 MiB)
// on large arrays. Random rays touch nodes and leaves all over arrays of tens
// of megabytes; with 4 KiB pages most of those reads also miss the TLB.
// Elsewhere, or where huge pages are off, it is a plain aligned allocation.
#pragma once

#include "base/fill_vector.h"

#include <cstddef>
#include <cstdlib>
#include <new>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace ppm {

template <class T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr size_t kHugePage = size_t(2) << 20;

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}

  T* allocate(size_t n) {
    const size_t bytes = n * sizeof(T);
#if defined(__linux__)
    if (bytes >= kHugePage) {
      void* p = std::aligned_alloc(kHugePage, round_up(bytes));
      if (!p) throw std::bad_alloc();
      madvise(p, round_up(bytes), MADV_HUGEPAGE);  // only a hint: failure is harmless
      return static_cast<T*>(p);
    }
#endif
    return static_cast<T*>(::operator new(bytes, std::align_val_t(alignof(T))));
  }

  void deallocate(T* p, size_t n) {
#if defined(__linux__)
    if (n * sizeof(T) >= kHugePage) {
      std::free(p);
      return;
    }
#endif
    ::operator delete(p, std::align_val_t(alignof(T)));
    (void)n;
  }

  template <class U>
  bool operator==(const HugePageAllocator<U>&) const { return true; }
  template <class U>
  bool operator!=(const HugePageAllocator<U>&) const { return false; }

 private:
  static size_t round_up(size_t bytes) { return (bytes + kHugePage - 1) / kHugePage * kHugePage; }
};

template <class T>
using HugePageVector = std::vector<T, HugePageAllocator<T>>;

// The same, whose resize() leaves new elements of a plain record type unwritten (fill_vector.h), for
// an array a parallel loop fills next: the page faults (with huge pages, the kernel's compaction to
// find them) then happen on every thread, not all on the one that resizes. 960 MB of leaf copies
// took 1.5-2.1 s to resize on one thread.
template <class T>
using HugePageFillVector = std::vector<T, UninitialisedAllocator<T, HugePageAllocator>>;

}  // namespace ppm
