// Linked into the two CAD worker programs only (the wirefur command, whose "cad-worker" mode is
// one, and wirefur-cad-worker; never into a library, where it would replace the allocator of
// every program that loads it): the C allocation functions are glibc's, until becomeWorker
// (core/worker_process.h) calls wirefur_worker_allocation_failures_are_fatal. From then on an
// allocation that fails ends the process with that status and one line on stderr. OpenCASCADE
// (Standard::Allocate) and VTK (vtkBuffer) allocate with malloc and catch their own failures:
// OpenCASCADE's mesher marks the face failed, VTK prints and goes on with a short array, so
// without this a file past the worker's memory cap came back with faces missing that depend on
// the memory, read as "skipped faces".
//
// The whole family is defined here, the C functions passed on to glibc and C++'s new and delete
// on to them: defined in the program, these win over an allocator preloaded with LD_PRELOAD
// (jemalloc, tcmalloc: both replace new and delete too), so that no block is allocated by one
// allocator and freed by the other (with malloc, calloc and realloc alone, `wirefur render`
// under LD_PRELOAD=libjemalloc.so.2 died in free). Not under AddressSanitizer, which has its own
// allocator.
#include "core/sanitizers.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdlib>
#include <new>

namespace {
int gFatalStatus = 0;  // 0: failures are returned, as glibc does
// A single request past this (the worker's whole memory cap, and 64 GiB) is no exhaustion but a corrupt count
// asking for the impossible (OpenCASCADE's mesher, asked for 1e14 bytes by one wrong digit):
// it fails as glibc's would, and the library handles it (OpenCASCADE skips the face, VTK reports
// a short array) instead of the whole file failing.
std::size_t gSingleLimit = ~std::size_t(0);

#if !defined(WF_UNDER_ASAN)  // (ASan's allocator stays: runWorker gives it the cap as options)
[[noreturn]] void outOfMemory() {
  static const char m[] = "out of memory under the worker's cap (an allocation failed)\n";
  [[maybe_unused]] const ssize_t n = write(STDERR_FILENO, m, sizeof m - 1);
  _exit(gFatalStatus);
}

// `asked`: the bytes asked for (0: none, a failure is no failure).
void* checked(void* p, std::size_t asked) {
  if (!p && asked != 0 && asked <= gSingleLimit && gFatalStatus) outOfMemory();
  return p;
}
std::size_t product(std::size_t a, std::size_t b) {
  std::size_t r = 0;
  return __builtin_mul_overflow(a, b, &r) ? ~std::size_t(0) : r;
}
#endif
}  // namespace

extern "C" void wirefur_worker_allocation_failures_are_fatal(int exitStatus) { gFatalStatus = exitStatus; }
extern "C" void wirefur_worker_single_allocation_limit(std::size_t bytes) { gSingleLimit = bytes; }

#if !defined(WF_UNDER_ASAN)
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void __libc_free(void*);
void* __libc_memalign(std::size_t, std::size_t);
void* __libc_valloc(std::size_t);
void* __libc_pvalloc(std::size_t);

void* malloc(std::size_t size) noexcept { return checked(__libc_malloc(size), size); }
void* calloc(std::size_t count, std::size_t size) noexcept {
  return checked(__libc_calloc(count, size), product(count, size));
}
void* realloc(void* old, std::size_t size) noexcept { return checked(__libc_realloc(old, size), size); }
void free(void* p) noexcept { __libc_free(p); }
void* memalign(std::size_t alignment, std::size_t size) noexcept {
  return checked(__libc_memalign(alignment, size), size);
}
void* aligned_alloc(std::size_t alignment, std::size_t size) noexcept {
  return checked(__libc_memalign(alignment, size), size);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t size) noexcept {
  if (alignment == 0 || (alignment & (alignment - 1)) != 0 || alignment % sizeof(void*) != 0) return EINVAL;
  void* p = checked(__libc_memalign(alignment, size), size);
  if (!p && size != 0) return ENOMEM;
  *out = p;
  return 0;
}
void* valloc(std::size_t size) noexcept { return checked(__libc_valloc(size), size); }
void* pvalloc(std::size_t size) noexcept { return checked(__libc_pvalloc(size), size); }
// glibc's own, looked up in libc itself (a preloaded allocator's would read glibc's blocks).
std::size_t malloc_usable_size(void* p) noexcept {
  using Size = std::size_t (*)(void*);
  static const Size glibc = [] {
    void* libc = dlopen("libc.so.6", RTLD_LAZY | RTLD_NOLOAD);
    return libc ? reinterpret_cast<Size>(dlsym(libc, "malloc_usable_size")) : nullptr;
  }();
  return glibc && p ? glibc(p) : 0;
}
}

// C++'s allocation, on the functions above (a failure: the new handler, then std::bad_alloc).
namespace {
void* allocate(std::size_t size, std::size_t alignment) {
  if (size == 0) size = 1;
  while (true) {
    void* p = alignment > alignof(std::max_align_t) ? __libc_memalign(alignment, size) : __libc_malloc(size);
    if (p) return p;
    if (size > gSingleLimit) throw std::bad_alloc();  // a corrupt count: the caller's to handle
    if (gFatalStatus) outOfMemory();
    std::new_handler handler = std::get_new_handler();
    if (!handler) throw std::bad_alloc();
    handler();
  }
}
void* allocateOrNull(std::size_t size, std::size_t alignment) noexcept {
  try {
    return allocate(size, alignment);
  } catch (...) {
    return nullptr;
  }
}
}  // namespace

void* operator new(std::size_t n) { return allocate(n, 0); }
void* operator new[](std::size_t n) { return allocate(n, 0); }
void* operator new(std::size_t n, std::align_val_t a) { return allocate(n, std::size_t(a)); }
void* operator new[](std::size_t n, std::align_val_t a) { return allocate(n, std::size_t(a)); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return allocateOrNull(n, 0); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return allocateOrNull(n, 0); }
void* operator new(std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return allocateOrNull(n, std::size_t(a));
}
void* operator new[](std::size_t n, std::align_val_t a, const std::nothrow_t&) noexcept {
  return allocateOrNull(n, std::size_t(a));
}
void operator delete(void* p) noexcept { __libc_free(p); }
void operator delete[](void* p) noexcept { __libc_free(p); }
void operator delete(void* p, std::size_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::size_t) noexcept { __libc_free(p); }
void operator delete(void* p, std::align_val_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { __libc_free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { __libc_free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { __libc_free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { __libc_free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { __libc_free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { __libc_free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { __libc_free(p); }
#endif
