// An allocator that leaves new elements of trivial types uninitialised when no value is given.
#pragma once

#include <memory>
#include <new>
#include <utility>

namespace octarc {

// A large buffer that is about to be overwritten (an image read from a file, catalog rows) is
// then not zero-filled first, and its pages are first touched by the threads that fill them.
template <typename T>
class UninitializedAllocator : public std::allocator<T> {
 public:
  template <typename U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  UninitializedAllocator() = default;
  template <typename U>
  UninitializedAllocator(const UninitializedAllocator<U>&) noexcept {}
  template <typename U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

}  // namespace octarc
