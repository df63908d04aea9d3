// Memory freed in many pieces goes back to the system only when the allocator lets it: glibc keeps
// blocks below its mmap threshold (which grows up to 32 MB) for later use, so a large structure
// freed piece by piece leaves the process's resident size where it was until malloc_trim.
#pragma once

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace ppm {

inline void return_freed_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace ppm
