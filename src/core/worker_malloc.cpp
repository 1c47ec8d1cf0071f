// Linked into the two CAD worker programs only (the wirefur command, whose "cad-worker" mode is
// one, and wirefur-cad-worker; never into a library, where it would replace the allocator of
// every program that loads it): malloc, calloc and realloc are glibc's, until becomeWorker
// (core/worker_process.h) calls wirefur_worker_allocation_failures_are_fatal. From then on an
// allocation that fails ends the process with that status and one line on stderr. OpenCASCADE
// (Standard::Allocate) and VTK (vtkBuffer) allocate with malloc and catch their own failures:
// OpenCASCADE's mesher marks the face failed, VTK prints and goes on with a short array, so
// without this a file past the worker's memory cap came back with faces missing that depend on
// the memory, read as "skipped faces". Not under AddressSanitizer, which has its own allocator.
#include <unistd.h>

#include <cstddef>

#if defined(__SANITIZE_ADDRESS__)
#define WF_UNDER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define WF_UNDER_ASAN 1
#endif
#endif

namespace {
int gFatalStatus = 0;  // 0: failures are returned, as glibc does

[[noreturn]] void outOfMemory() {
  static const char m[] = "out of memory under the worker's cap (an allocation failed)\n";
  [[maybe_unused]] const ssize_t n = write(STDERR_FILENO, m, sizeof m - 1);
  _exit(gFatalStatus);
}
}  // namespace

extern "C" void wirefur_worker_allocation_failures_are_fatal(int exitStatus) { gFatalStatus = exitStatus; }

#if !defined(WF_UNDER_ASAN)
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);

void* malloc(std::size_t size) {
  void* p = __libc_malloc(size);
  if (!p && size && gFatalStatus) outOfMemory();
  return p;
}

void* calloc(std::size_t count, std::size_t size) {
  void* p = __libc_calloc(count, size);
  if (!p && count && size && gFatalStatus) outOfMemory();
  return p;
}

void* realloc(void* old, std::size_t size) {
  void* p = __libc_realloc(old, size);
  if (!p && size && gFatalStatus) outOfMemory();
  return p;
}
}
#endif
