// An allocator that leaves new elements of trivial types uninitialised when no value is given.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <new>
#include <utility>

#if defined(__linux__)
#include <sys/mman.h>
#endif

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

  // Image-sized blocks are mapped on their own, aligned on 2 MiB and offered to the kernel for
  // transparent huge pages: one page fault per 2 MiB instead of per 4 KiB, which is most of the
  // cost of first touching a large image, and the memory goes back to the system as soon as the
  // block is freed (a heap would keep it). Smaller blocks come from the usual allocator.
  static constexpr std::size_t kHugePage = std::size_t(2) << 20;
  static constexpr std::size_t kLargeBlock = std::size_t(8) << 20;
  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
#if defined(__linux__)
    if (bytes >= kLargeBlock) return static_cast<T*>(mapHuge(bytes));
#endif
    return std::allocator<T>::allocate(n);
  }
  void deallocate(T* p, std::size_t n) noexcept {
#if defined(__linux__)
    if (n * sizeof(T) >= kLargeBlock) {
      ::munmap(p, roundedToHugePage(n * sizeof(T)));
      return;
    }
#endif
    std::allocator<T>::deallocate(p, n);
  }

  template <typename U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }

 private:
  static std::size_t roundedToHugePage(std::size_t bytes) {
    return (bytes + kHugePage - 1) / kHugePage * kHugePage;
  }
#if defined(__linux__)
  // Maps a little more than asked, keeps the 2 MiB-aligned part and unmaps the rest.
  static void* mapHuge(std::size_t bytes) {
    const std::size_t size = roundedToHugePage(bytes);
    void* raw = ::mmap(nullptr, size + kHugePage, PROT_READ | PROT_WRITE,
                       MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) throw std::bad_alloc();
    const std::uintptr_t start = reinterpret_cast<std::uintptr_t>(raw);
    const std::uintptr_t aligned = (start + kHugePage - 1) / kHugePage * kHugePage;
    if (aligned > start) ::munmap(raw, aligned - start);
    const std::size_t tail = start + size + kHugePage - (aligned + size);
    if (tail > 0) ::munmap(reinterpret_cast<void*>(aligned + size), tail);
#if defined(MADV_HUGEPAGE)
    ::madvise(reinterpret_cast<void*>(aligned), size, MADV_HUGEPAGE);  // advice only
#endif
    return reinterpret_cast<void*>(aligned);
  }
#endif
};

}  // namespace octarc
