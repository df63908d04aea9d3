// FillVector: a std::vector whose resize() leaves new elements of a plain
// record type unwritten, for large arrays that a parallel loop fills (or
// zeroes) next. That loop is then the first to touch the pages, on every
// thread: zeroing 250 MB of hit points on one thread first took a third of
// the eye pass.
#pragma once

#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace ppm {

// `Base` allocates (std::allocator by default; huge_pages.h passes its own); construction without
// arguments leaves a plain record unwritten.
template <class T, template <class> class Base = std::allocator>
struct UninitialisedAllocator : Base<T> {
  template <class U>
  struct rebind {
    using other = UninitialisedAllocator<U, Base>;
  };
  UninitialisedAllocator() = default;
  template <class U>
  UninitialisedAllocator(const UninitialisedAllocator<U, Base>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept {
    static_assert(std::is_trivially_default_constructible_v<U>, "only for plain records");
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <class T>
using FillVector = std::vector<T, UninitialisedAllocator<T>>;

}  // namespace ppm
