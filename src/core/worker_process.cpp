#include "core/worker_process.h"

#include "core/cleanup_on_signal.h"
#include "core/sanitizers.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <random>
#include <sstream>
#include <thread>


extern char** environ;

namespace wf {

namespace {

// Under AddressSanitizer, whether the worker's stderr holds ASan's report of a request or a
// resident size past the cap runWorker gave it. False in other builds.
bool asanReportedOutOfMemory(const std::string& stderrPath) {
#if defined(WF_UNDER_ASAN)
  if (stderrPath.empty()) return false;
  std::ifstream in(stderrPath);
  std::string line;
  while (std::getline(in, line))
    if (line.find("AddressSanitizer: requested allocation size") != std::string::npos ||
        line.find("AddressSanitizer: allocator is out of memory") != std::string::npos ||
        line.find("AddressSanitizer: out of memory") != std::string::npos ||
        line.find("hard rss limit exhausted") != std::string::npos)
      return true;
#else
  (void)stderrPath;
#endif
  return false;
}

}  // namespace

WorkerExit runWorker(const std::string& executable, const std::vector<std::string>& args,
                     const WorkerOptions& options) {
  WorkerExit r;
  std::vector<std::string> copy = args;
  std::vector<char*> argv;
  for (std::string& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);  // (a host's socket)
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);  // OpenCASCADE prints
  if (!options.stderrPath.empty())
    posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, options.stderrPath.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0600);
  // Nothing past stderr: a host's sockets (pvserver's client, MPI's transport) held open by a
  // worker would outlive the host.
  posix_spawn_file_actions_addclosefrom_np(&actions, STDERR_FILENO + 1);
  // No blocked or ignored signal from the host (ParaView, MPI and Python set some).
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t none, all;
  sigemptyset(&none);
  sigfillset(&all);
  // ... but for a hang-up ignored by the user's choice (nohup): the worker outlives the
  // terminal as its parent does, instead of dying as a "stopped" read.
  struct sigaction hup;
  if (sigaction(SIGHUP, nullptr, &hup) == 0 && hup.sa_handler == SIG_IGN) sigdelset(&all, SIGHUP);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &all);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  pid_t pid = 0;
#if defined(WF_UNDER_ASAN)
  // AddressSanitizer's shadow memory leaves no room for RLIMIT_DATA (capWorkerMemory) and it
  // replaces malloc (worker_malloc.cpp): its own options set the cap instead. A single request
  // past the cap ends the worker at once with ASan's report, as RLIMIT_DATA's failed allocation
  // ends it in other builds (so no library is handed NULL and goes on with less: the output
  // never depends on the memory), instead of being mapped and then filled: VTK's XML reader,
  // told of 2e9 components, value-initialises a std::vector of 16 GB, which swapped for ten
  // minutes. A resident size past the cap, plus room for ASan's shadow (an eighth) and its
  // quarantine (256 MiB by default), ends the worker too (ASan polls it every 100 ms).
  // Later options override earlier ones in ASAN_OPTIONS. Either report reads as
  // kWorkerExitOutOfMemory (asanReportedOutOfMemory, below).
  std::vector<std::string> envCopy;
  std::vector<char*> envp;
  {
    const double mib = 1024.0 * 1024.0, cap = std::clamp(workerMemoryCap(), 64 * mib, 1e15);
    std::string asan = "ASAN_OPTIONS=";
    if (const char* set = std::getenv("ASAN_OPTIONS"); set && *set) asan += std::string(set) + ":";
    asan += "allocator_may_return_null=0:max_allocation_size_mb=" + std::to_string((long long)(cap / mib)) +
            ":hard_rss_limit_mb=" + std::to_string((long long)((cap + cap / 8 + 512 * mib) / mib));
    for (char** e = environ; e && *e; ++e)
      if (std::strncmp(*e, "ASAN_OPTIONS=", 13) != 0) envCopy.emplace_back(*e);
    envCopy.push_back(asan);
    for (std::string& e : envCopy) envp.push_back(e.data());
    envp.push_back(nullptr);
  }
  char** const workerEnvironment = envp.data();
#else
  char** const workerEnvironment = environ;
#endif
  const int spawned = posix_spawn(&pid, executable.c_str(), &actions, &attr, argv.data(), workerEnvironment);
  posix_spawnattr_destroy(&attr);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    r.startError = std::strerror(spawned);
    return r;
  }
  r.started = true;
  // Killed by the command's handler if it is stopped meanwhile (core/cleanup_on_signal.h).
  // The slot is forgotten while the child is still a zombie, before it is reaped: a signal
  // arriving after that cannot kill another process that got the pid.
  struct ForgetChild {
    int slot;
    void now() {
      forgetCleanupChild(slot);
      slot = -1;
    }
    ~ForgetChild() { forgetCleanupChild(slot); }
  } forgetChild{registerCleanupChild(pid)};
  const double limit = std::isfinite(options.timeoutSeconds) && options.timeoutSeconds > 0
                           ? options.timeoutSeconds
                           : HUGE_VAL;
  const auto t0 = std::chrono::steady_clock::now();
  int status = 0;
  // Reaps a child known to have ended (or ending): forgotten first, then waited for.
  // False when the host reaped it first (its own SIGCHLD handler).
  auto reap = [&] {
    forgetChild.now();
    // (Blocks only while the child is in uninterruptible sleep, a hung network file system.)
    pid_t w = -1;
    while ((w = waitpid(pid, &status, 0)) < 0 && errno == EINTR) {
    }
    return w == pid;
  };
  auto killAndReap = [&] {
    kill(pid, SIGKILL);
    siginfo_t info{};
    while (waitid(P_PID, id_t(pid), &info, WEXITED | WNOWAIT) < 0 && errno == EINTR) {
    }
    reap();
  };
  // Polled rather than waited on with a signal or a timer: nothing here may disturb the host's
  // own signal handling (ParaView, MPI). 2 ms of latency against reads of tens of milliseconds.
  // WNOWAIT: seen ended but left a zombie until reap() has forgotten its slot.
  while (true) {
    siginfo_t info{};
    const int w = waitid(P_PID, id_t(pid), &info, WEXITED | WNOHANG | WNOWAIT);
    if (w == 0 && info.si_pid == pid) {
      if (reap()) break;
      r.statusUnknown = true;
      return r;
    }
    if (w < 0 && errno != EINTR) {  // not our child any more: the host reaped it
      r.statusUnknown = true;
      return r;
    }
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > limit) {
      killAndReap();
      r.timedOut = true;
      return r;
    }
    bool goOn = true;
    try {
      goOn = !options.poll || options.poll();
    } catch (...) {
      killAndReap();
      throw;
    }
    if (!goOn) {
      killAndReap();
      r.aborted = true;
      return r;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (WIFSIGNALED(status)) {
    r.signalled = true;
    r.signal = WTERMSIG(status);
  } else if (WIFEXITED(status)) {
    r.status = WEXITSTATUS(status);
    // Under AddressSanitizer the cap is its options' (above), and exhausting it ends the worker
    // with ASan's report and status 1: the same out of memory as in other builds.
    if (r.status != 0 && asanReportedOutOfMemory(options.stderrPath)) r.status = kWorkerExitOutOfMemory;
  }
  return r;
}

namespace {

// The memory this process may use: the machine's, or a cgroup v2 limit above it when lower.
double usableMemory() {
  double bytes = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGESIZE));
  std::ifstream cgroups("/proc/self/cgroup");
  std::string line;
  while (std::getline(cgroups, line)) {
    if (line.rfind("0::", 0) != 0) continue;
    std::filesystem::path p = std::filesystem::path("/sys/fs/cgroup") / line.substr(4);
    for (; p.string().size() >= std::string("/sys/fs/cgroup").size(); p = p.parent_path()) {
      std::ifstream max(p / "memory.max");
      std::string v;
      if (max >> v && v != "max") {
        double limit = 0;
        if (parseWorkerNumber(v, limit) && limit > 0) bytes = std::min(bytes, limit);
      }
      if (p == p.parent_path()) break;
    }
  }
  return bytes;
}

}  // namespace

double workerMemoryCap() {
  double cap = 0;
  if (const char* set = std::getenv("WIREFUR_WORKER_MEMORY_CAP"); set && parseWorkerNumber(set, cap) && cap > 0)
    return cap;
  cap = std::clamp(0.5 * usableMemory(), 1.0 * (1 << 30), 16.0 * (1 << 30));
  rlimit now{};
  if (getrlimit(RLIMIT_DATA, &now) == 0 && now.rlim_max != RLIM_INFINITY) cap = std::min(cap, double(now.rlim_max));
  return cap;
}

double capWorkerMemory() {
  const double cap = workerMemoryCap();
#if defined(WF_UNDER_ASAN)
  return cap;  // (set by runWorker's ASAN_OPTIONS instead)
#endif
  if (cap > 0) {
    const rlimit lim{rlim_t(cap), rlim_t(cap)};
    if (setrlimit(RLIMIT_DATA, &lim) != 0) return 0.0;
  }
  return cap;
}

}  // namespace wf

// Defined by worker_malloc.cpp in the programs that link it (weak: absent elsewhere).
extern "C" void wirefur_worker_allocation_failures_are_fatal(int exitStatus) __attribute__((weak));
extern "C" void wirefur_worker_single_allocation_limit(std::size_t bytes) __attribute__((weak));

namespace wf {

void becomeWorker(const std::string& parentPid, const std::string& timeoutSeconds) {
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  // The parent may have gone before the line above: then we are someone else's child now.
  if (std::to_string(getppid()) != parentPid) _exit(kWorkerExitOrphaned);
  double timeout = 0;
  if (parseWorkerNumber(timeoutSeconds, timeout) && std::isfinite(timeout) && timeout > 0)
    alarm(unsigned(std::min(std::ceil(timeout) + 10.0, 4.0e9)));
  const rlimit noCore{0, 0};
  setrlimit(RLIMIT_CORE, &noCore);
  const double cap = capWorkerMemory();
  // One request past the whole cap is a corrupt count, not exhaustion: it fails back to the
  // library (worker_malloc.cpp) instead of ending the worker.
  // (Past 64 GiB at least, whatever the cap: on a small machine a large real request below
  // that still ends the worker as out of memory, not as a face quietly dropped.)
  if (cap > 0 && wirefur_worker_single_allocation_limit)
    wirefur_worker_single_allocation_limit(std::size_t(std::max(cap, 68719476736.0)));
  std::set_new_handler([] {
    static const char m[] = "out of memory under the worker's cap\n";
    [[maybe_unused]] const ssize_t n = write(STDERR_FILENO, m, sizeof m - 1);
    _exit(kWorkerExitOutOfMemory);
  });
  if (wirefur_worker_allocation_failures_are_fatal) wirefur_worker_allocation_failures_are_fatal(kWorkerExitOutOfMemory);
}

void endWorker(int status) {
  std::fflush(stderr);
  std::fflush(stdout);
  _exit(status);
}

std::string workerNumber(double value) {
  char buffer[64];
  const std::to_chars_result r = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, r.ptr);
}

bool parseWorkerNumber(const std::string& text, double& value) {
  const char* end = text.data() + text.size();
  const std::from_chars_result r = std::from_chars(text.data(), end, value);
  return r.ec == std::errc() && r.ptr == end;
}

std::string signalDescription(int sig) {
  const char* d = strsignal(sig);
  return std::string("signal ") + std::to_string(sig) + (d ? std::string(", ") + d : std::string());
}

std::string lastLineOf(const std::string& path, size_t maxChars) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::string();
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size <= 0) return std::string();
  const std::streamoff from = std::max<std::streamoff>(0, size - 4096);
  in.seekg(from);
  std::string text(size_t(size - from), '\0');
  in.read(text.data(), std::streamsize(text.size()));
  std::string last, line;
  std::istringstream lines(text);
  while (std::getline(lines, line)) {
    const bool blank = std::all_of(line.begin(), line.end(), [](char c) { return std::isspace(static_cast<unsigned char>(c)); });
    if (!blank) last = line;
  }
  for (char& c : last)
    if (static_cast<unsigned char>(c) < 32 || c == 127) c = ' ';
  if (last.size() > maxChars) {
    size_t cut = maxChars - 3;
    while (cut > 0 && (static_cast<unsigned char>(last[cut]) & 0xC0) == 0x80) --cut;  // (whole UTF-8 characters)
    last = last.substr(0, cut) + "...";
  }
  return last;
}

unsigned uniqueishNumber() {
  // std::random_device may throw where there is no entropy source (it never did for mkdtemp's
  // callers, ParaView among them): the clock then.
  try {
    std::random_device entropy;
    return entropy();
  } catch (...) {
    return unsigned(std::uint64_t(std::chrono::steady_clock::now().time_since_epoch().count()) * 2654435761u);
  }
}

TemporaryFolder::TemporaryFolder(const std::string& prefix) {
  std::vector<std::string> bases;
  if (const char* t = std::getenv("TMPDIR"); t && *t) bases.push_back(t);
  bases.push_back("/tmp");
  // mkdtemp's job by hand, so that the name is registered for removal on a stopping signal
  // (core/cleanup_on_signal.h) before the folder exists: a signal in between would leave it.
  static std::atomic<unsigned> counter{0};
  for (const std::string& base : bases) {
    for (int attempt = 0; attempt < 100; ++attempt) {
      char suffix[48];
      std::snprintf(suffix, sizeof suffix, "%d.%u.%08x", int(getpid()), counter++, uniqueishNumber());
      const std::string name = base + "/" + prefix + suffix;
      const int slot = registerCleanup(name, true);
      if (mkdir(name.c_str(), 0700) == 0) {
        path_ = name;
        cleanupSlot_ = slot;
        return;
      }
      const int err = errno;
      forgetCleanup(slot);
      if (err != EEXIST) break;
    }
  }
}

TemporaryFolder::~TemporaryFolder() {
  if (path_.empty()) return;
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
  forgetCleanup(cleanupSlot_);
}

}  // namespace wf
