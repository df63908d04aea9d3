// What the spatial indices (quantile grid, hashed grid) share: the check of
// their input (item centres and optional radii) and the relabelling of point
// items into the order their cells store them.
#pragma once

#include "math/types.h"

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace ppm {

// Items and references are addressed with uint32_t.
constexpr uint64_t kMaxGridIndex = std::numeric_limits<uint32_t>::max();

// Throws std::invalid_argument naming the item for a non-finite centre, a
// negative or non-finite radius, or mismatched sizes; std::length_error for
// more items than uint32_t addresses. `who` prefixes the message.
inline void check_grid_items(const std::string& who, const std::vector<Vec3>& centers,
                             const std::vector<double>& radii) {
  if (centers.size() > kMaxGridIndex) throw std::length_error(who + "too many items");
  if (!radii.empty() && radii.size() != centers.size())
    throw std::invalid_argument(who + "radii.size() != centers.size()");
  for (size_t i = 0; i < centers.size(); ++i) {
    if (!is_finite(centers[i]))
      throw std::invalid_argument(who + "center of item " + std::to_string(i) + " is not finite");
    if (!radii.empty() && !(radii[i] >= 0.0 && radii[i] < kInf))
      throw std::invalid_argument(who + "radius of item " + std::to_string(i) + " is negative or not finite");
  }
}

// Points only: `items` lists item labels in cell order. Relabels them
// 0..n-1 in that order (so item k is stored at position k) and leaves in
// `old_of_new`, for each new label, the old one. The two buffers are swapped,
// so a caller that passes the same vector every time allocates nothing.
inline void relabel_items_in_order(std::vector<uint32_t>& items, std::vector<uint32_t>& old_of_new) {
  old_of_new.swap(items);
  items.resize(old_of_new.size());
  for (uint32_t i = 0; i < items.size(); ++i) items[i] = i;
}

}  // namespace ppm
