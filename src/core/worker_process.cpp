#include "core/worker_process.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <thread>

extern char** environ;

namespace wf {

WorkerExit runWorker(const std::string& executable, const std::vector<std::string>& args,
                     double timeoutSeconds, bool silenceStderr) {
  WorkerExit r;
  std::vector<std::string> copy = args;
  std::vector<char*> argv;
  for (std::string& a : copy) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);  // OpenCASCADE prints
  if (silenceStderr) posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, executable.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    r.startError = std::strerror(spawned);
    return r;
  }
  r.started = true;
  const auto t0 = std::chrono::steady_clock::now();
  int status = 0;
  // Polled rather than waited on with a signal or a timer: nothing here may disturb the host's
  // own signal handling (ParaView, MPI). 2 ms of latency against reads of tens of milliseconds.
  while (true) {
    const pid_t w = waitpid(pid, &status, WNOHANG);
    if (w == pid) break;
    if (w < 0 && errno != EINTR) {  // not our child any more (a host that reaps every child)
      r.status = -1;
      return r;
    }
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > timeoutSeconds) {
      kill(pid, SIGKILL);
      while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
      }
      r.timedOut = true;
      return r;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (WIFSIGNALED(status)) {
    r.signalled = true;
    r.signal = WTERMSIG(status);
  } else if (WIFEXITED(status)) {
    r.status = WEXITSTATUS(status);
  }
  return r;
}

void capWorkerMemory() {
#if !defined(__SANITIZE_ADDRESS__)
  const double phys = double(sysconf(_SC_PHYS_PAGES)) * double(sysconf(_SC_PAGESIZE));
  const double cap = std::clamp(0.5 * phys, 2.0 * (1 << 30), 16.0 * (1 << 30));
  const rlimit lim{rlim_t(cap), rlim_t(cap)};
  setrlimit(RLIMIT_AS, &lim);
#endif
}

std::string signalDescription(int sig) {
  const char* d = strsignal(sig);
  return std::string("signal ") + std::to_string(sig) + (d ? std::string(", ") + d : std::string());
}

TemporaryFolder::TemporaryFolder(const std::string& prefix) {
  std::string base = "/tmp";
  if (const char* t = std::getenv("TMPDIR"); t && *t) {
    std::error_code ec;
    if (std::filesystem::is_directory(t, ec)) base = t;
  }
  std::string pattern = base + "/" + prefix + "XXXXXX";
  if (mkdtemp(pattern.data())) path_ = pattern;
}

TemporaryFolder::~TemporaryFolder() {
  if (path_.empty()) return;
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

}  // namespace wf
