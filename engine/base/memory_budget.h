// What the machine can still give a render. Linux overcommits: an allocation larger than the
// memory there is succeeds, and the process is killed when it touches the pages; inside
// Blender that loses the user's unsaved work. A render checks what its largest arrays will
// need before it makes them and fails with a message instead (Python: MemoryError).
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace ppm {

struct MemoryShortage : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// MemAvailable of /proc/meminfo (what can be allocated without swapping); 0 where unknown.
size_t available_memory_bytes();

// Throws MemoryShortage, naming `what` and `advice`, if `needed` bytes exceed what is available.
void check_memory(size_t needed, const std::string& what, const std::string& advice);

}  // namespace ppm
