#include "core/cleanup_on_signal.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstring>

namespace wf {

namespace {

constexpr int kSlots = 256;
constexpr int kChildren = 64;
constexpr size_t kPathMax = 4096;

// A slot's state: the low 2 bits its kind (0 free, 1 being written, 2 a file, 3 a folder), the
// rest a generation that changes whenever it is freed, so that the handler, which copies the
// path and then checks the state again, never acts on a path another thread was rewriting.
struct Slot {
  std::atomic<std::uint32_t> state{0};
  char path[kPathMax];
};
Slot slots[kSlots];
std::atomic<pid_t> children[kChildren];
std::atomic<bool> installed{false};

// Removes the files directly inside a folder (passes until one removes nothing: a pass that
// unlinks as it reads may skip entries), then the folder. The workers' folders hold files only.
void removeFolder(const char* path) {
  const int fd = open(path, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd >= 0) {
    for (int pass = 0; pass < 8; ++pass) {
      lseek(fd, 0, SEEK_SET);
      bool removed = false;
      alignas(8) char buffer[4096];
      for (;;) {
        const long n = syscall(SYS_getdents64, fd, buffer, sizeof buffer);
        if (n <= 0) break;
        for (long at = 0; at < n;) {
          struct Entry {  // linux_dirent64
            std::uint64_t ino;
            std::int64_t off;
            unsigned short reclen;
            unsigned char type;
            char name[1];
          };
          const Entry* e = reinterpret_cast<const Entry*>(buffer + at);
          if (std::strcmp(e->name, ".") != 0 && std::strcmp(e->name, "..") != 0 && unlinkat(fd, e->name, 0) == 0)
            removed = true;
          at += e->reclen;
        }
      }
      if (!removed) break;
    }
    close(fd);
  }
  rmdir(path);
}

void onSignal(int sig) {
  const int saved = errno;
  // The workers first, so that none writes into a folder being removed.
  for (std::atomic<pid_t>& c : children)
    if (const pid_t p = c.load(); p > 0) kill(p, SIGKILL);
  for (std::atomic<pid_t>& c : children)
    if (const pid_t p = c.load(); p > 0)
      while (waitpid(p, nullptr, 0) < 0 && errno == EINTR) {
      }
  for (Slot& s : slots) {
    const std::uint32_t before = s.state.load();
    const std::uint32_t kind = before & 3u;
    if (kind < 2) continue;
    char path[kPathMax];
    std::memcpy(path, s.path, kPathMax);
    path[kPathMax - 1] = '\0';
    if (s.state.load() != before) continue;  // freed or reused meanwhile
    if (kind == 2) unlink(path);
    else removeFolder(path);
  }
  errno = saved;
  // Die of the signal, as without the handler (the shell reports 130 / 143 / 129).
  signal(sig, SIG_DFL);
  raise(sig);
}

}  // namespace

int registerCleanup(const std::string& path, bool folder) {
  if (path.empty() || path.size() >= kPathMax) return -1;
  for (int i = 0; i < kSlots; ++i) {
    std::uint32_t expected = slots[i].state.load();
    if ((expected & 3u) != 0) continue;
    if (slots[i].state.compare_exchange_strong(expected, expected | 1u)) {
      std::memcpy(slots[i].path, path.c_str(), path.size() + 1);
      slots[i].state.store((expected & ~3u) | (folder ? 3u : 2u));
      return i;
    }
  }
  return -1;
}

void forgetCleanup(int slot) {
  if (slot < 0 || slot >= kSlots) return;
  const std::uint32_t s = slots[slot].state.load();
  slots[slot].state.store((s & ~3u) + 4u);  // free, next generation
}

int registerCleanupChild(pid_t pid) {
  for (int i = 0; i < kChildren; ++i) {
    pid_t expected = 0;
    if (children[i].compare_exchange_strong(expected, pid)) return i;
  }
  return -1;
}

void forgetCleanupChild(int slot) {
  if (slot >= 0 && slot < kChildren) children[slot].store(0);
}

void installCleanupOnSignals() {
  if (installed.exchange(true)) return;
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = onSignal;
  sigfillset(&sa.sa_mask);  // one handler at a time
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction old;
    // A signal ignored when we started (nohup's SIGHUP) stays ignored.
    if (sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    sigaction(sig, &sa, nullptr);
  }
}

}  // namespace wf
