// What the machine can still give a render (see memory_budget.h).
#include "base/memory_budget.h"

#include <cstdio>
#include <fstream>
#include <string>

namespace ppm {

size_t available_memory_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  size_t kib = 0;
  std::string unit;
  while (meminfo >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024;
  return 0;
}

void check_memory(size_t needed, const std::string& what, const std::string& advice) {
  const size_t available = available_memory_bytes();
  if (available == 0 || needed <= available) return;
  char message[160];
  std::snprintf(message, sizeof message, "needs about %.1f GB, but %.1f GB of memory are available",
                static_cast<double>(needed) / 1e9, static_cast<double>(available) / 1e9);
  throw MemoryShortage(what + " " + message + "; " + advice);
}

}  // namespace ppm
