// Large blocks on huge pages, and the cache of freed ones (core/large_memory.h).
#include "core/large_memory.h"

#include <sys/mman.h>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <new>
#include <utility>
#include <vector>

namespace wf {

namespace {
constexpr size_t kHuge = size_t(2) << 20;
size_t roundedLarge(size_t bytes) { return (bytes + kHuge - 1) / kHuge * kHuge; }

// The large blocks the last renders freed, kept for the next one: a viewer or a benchmark draws
// frame after frame with arrays of the same sizes, and a block the kernel hands out afresh is
// zeroed page by page on its first writes (8% of a 700,000-hair frame here). Bounded: at most
// kCachedBlocks blocks and cacheLimit() bytes (an eighth of the memory, at most 1 GiB), counted
// at the blocks' real sizes; a block is reused only for a request of more than half its size,
// so little of it lies idle; releaseRenderMemory() gives everything back.
constexpr int kCachedBlocks = 8;
struct BlockCache {
  std::mutex mutex;
  void* block[kCachedBlocks] = {};
  size_t size[kCachedBlocks] = {};  ///< real sizes (what aligned_alloc was asked for)
  size_t total = 0;
  /// Cached blocks handed out for a smaller request, with their real sizes: freeLarge learns the
  /// request's size only, and the cache must count (and bound) what it really holds.
  std::vector<std::pair<void*, size_t>> lent;
};
BlockCache& blockCache() {
  // Never destroyed: a PodVector freed during static destruction still finds it.
  static BlockCache& cache = *new BlockCache;
  return cache;
}
size_t cacheLimit() {
  static const size_t limit = [] {
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    const size_t eighth = pages > 0 && page > 0 ? size_t(pages) / 8 * size_t(page) : 0;
    return std::min(eighth, size_t(1) << 30);
  }();
  return limit;
}
}  // namespace

void* allocateLarge(size_t bytes) {
  const size_t rounded = roundedLarge(bytes);
  {
    BlockCache& c = blockCache();
    std::lock_guard<std::mutex> lock(c.mutex);
    int best = -1;  // the smallest cached block that fits and is less than twice the request
    for (int i = 0; i < kCachedBlocks; ++i)
      if (c.block[i] && c.size[i] >= rounded && c.size[i] / 2 < rounded && (best < 0 || c.size[i] < c.size[best])) best = i;
    if (best >= 0) {
      void* p = c.block[best];
      if (c.size[best] != rounded) c.lent.emplace_back(p, c.size[best]);  // may throw: nothing changed yet
      c.total -= c.size[best];
      c.block[best] = nullptr;
      c.size[best] = 0;
      return p;
    }
  }
  void* p = std::aligned_alloc(kHuge, rounded);
  if (!p) {
    releaseRenderMemory();  // what the cache holds may be what is missing
    p = std::aligned_alloc(kHuge, rounded);
    if (!p) throw std::bad_alloc();
  }
#ifdef MADV_HUGEPAGE
  madvise(p, rounded, MADV_HUGEPAGE);  // advice: refused (or no such kernel support) is fine
#endif
  return p;
}

void freeLarge(void* p, size_t bytes) noexcept {
  if (!p) return;
  size_t real = roundedLarge(bytes);  // what allocateLarge asked aligned_alloc for, unless lent
  void* evicted[kCachedBlocks];
  int nEvicted = 0;
  bool kept = false;
  {
    BlockCache& c = blockCache();
    std::lock_guard<std::mutex> lock(c.mutex);
    for (size_t i = 0; i < c.lent.size(); ++i)
      if (c.lent[i].first == p) {
        real = c.lent[i].second;
        c.lent[i] = c.lent.back();
        c.lent.pop_back();
        break;
      }
    if (real <= cacheLimit()) {
      // Make room: drop the largest cached blocks until this one fits the limits.
      while (true) {
        int empty = -1, largest = -1;
        for (int i = 0; i < kCachedBlocks; ++i) {
          if (!c.block[i]) empty = empty < 0 ? i : empty;
          else if (largest < 0 || c.size[i] > c.size[largest]) largest = i;
        }
        if (empty >= 0 && c.total + real <= cacheLimit()) {
          c.block[empty] = p;
          c.size[empty] = real;
          c.total += real;
          kept = true;
          break;
        }
        if (largest < 0) break;
        evicted[nEvicted++] = c.block[largest];
        c.total -= c.size[largest];
        c.block[largest] = nullptr;
        c.size[largest] = 0;
      }
    }
  }
  // Given back to the system outside the lock (a large free unmaps).
  for (int i = 0; i < nEvicted; ++i) std::free(evicted[i]);
  if (!kept) std::free(p);
}

void releaseRenderMemory() {
  void* blocks[kCachedBlocks];
  {
    BlockCache& c = blockCache();
    std::lock_guard<std::mutex> lock(c.mutex);
    for (int i = 0; i < kCachedBlocks; ++i) {
      blocks[i] = c.block[i];
      c.block[i] = nullptr;
      c.size[i] = 0;
    }
    c.total = 0;
  }
  for (void* b : blocks) std::free(b);
#if defined(__GLIBC__)
  // And what the render's smaller arrays left free in the allocator's heaps: glibc keeps freed
  // memory in the arena of the thread that used it, where another thread's next allocation may
  // not find it, so that a command rendering several times in turn could hold each render's
  // leftovers at once.
  malloc_trim(0);
#endif
}

size_t renderMemoryHeld() {
  BlockCache& c = blockCache();
  std::lock_guard<std::mutex> lock(c.mutex);
  return c.total;
}

}  // namespace wf
