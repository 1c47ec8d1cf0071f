// Memory for large arrays: the render's primitives and bins (render/pipeline.h's PodVector) and
// images (core/image.h). Blocks of kLargeAllocation bytes and more are laid on 2 MiB
// boundaries and offered to the kernel as huge pages, so that writing them the first time faults
// once per 2 MiB instead of once per 4 KiB: on a virtual machine a 4 KiB fault costs several
// microseconds (an 800 x 600 float image took 21 ms to zero, on huge pages under 1 ms). Freed
// blocks are kept for the next render (bounded; releaseRenderMemory).
#pragma once

#include <cstddef>
#include <limits>
#include <memory>
#include <new>

namespace wf {

void* allocateLarge(size_t bytes);
void freeLarge(void* p, size_t bytes) noexcept;
/// From 1 MiB: zeroing a whole 2 MiB page costs less than the 256 faults of 1 MiB on 4 KiB pages
/// (the gallery's set-up went from 0.21 s to 0.15 s when this came down from 4 MiB), and an
/// array is at most doubled by its rounding.
inline constexpr size_t kLargeAllocation = size_t(1) << 20;
/// What allocateLarge adds to an array of `bytes` at most: its rounding up to whole 2 MiB pages
/// (nothing for an array below kLargeAllocation, which the heap holds).
inline double largeArrayRounding(double bytes) { return bytes >= double(kLargeAllocation) ? double(size_t(2) << 20) : 0.0; }

/// The large blocks freed (primitives, bins, images) are kept for the next render, so that frame
/// after frame reuses memory the kernel has already handed out and zeroed: at most 8 blocks and
/// an eighth of the machine's memory (1 GiB at most). releaseRenderMemory() gives them back now,
/// with what the allocator keeps free (glibc: malloc_trim); renderMemoryHeld() is what is kept.
void releaseRenderMemory();
size_t renderMemoryHeld();

/// std::allocator, but with blocks of kLargeAllocation bytes and more from allocateLarge. (C++20:
/// a library whose std::allocator has C++23's allocate_at_least would need it here too, or the
/// vector would take such a block from the heap and give it back to freeLarge.)
template <class T>
struct LargeAllocator : std::allocator<T> {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = LargeAllocator<U>;
  };
  LargeAllocator() = default;
  template <class U>
  LargeAllocator(const LargeAllocator<U>&) noexcept {}
  T* allocate(size_t n) {
    if (n > std::numeric_limits<size_t>::max() / sizeof(T)) throw std::bad_array_new_length();
    if (n * sizeof(T) >= kLargeAllocation) return static_cast<T*>(allocateLarge(n * sizeof(T)));
    return std::allocator<T>::allocate(n);
  }
  void deallocate(T* p, size_t n) noexcept {
    if (n * sizeof(T) >= kLargeAllocation) freeLarge(p, n * sizeof(T));
    else std::allocator<T>::deallocate(p, n);
  }
};
template <class T, class U>
bool operator==(const LargeAllocator<T>&, const LargeAllocator<U>&) noexcept {
  return true;
}

}  // namespace wf
