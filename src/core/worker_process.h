// Running untrusted-input parsers in a process of their own: the wirefur command's CAD worker
// (apps/cad_input.cpp) and vtkWireFurCADReader's ReadInWorker (vtk_filters/cad/) start a child,
// wait for it with a time limit and read its result from a private temporary folder. A crash, a
// hang or a memory cap hit in the child is reported by the parent, which carries on.
//
// The child inherits nothing it should not: no file descriptor past stderr (a pvserver's client
// socket, an MPI transport's), no blocked or ignored signal; it dies with its parent
// (becomeWorker) and stops itself shortly after its time limit even when nobody is left to kill
// it. Numbers cross on the command line in a form no locale changes (workerNumber).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace wf {

/// How a worker ended.
struct WorkerExit {
  bool started = false;     ///< false: posix_spawn failed (startError says why)
  std::string startError;
  bool timedOut = false;    ///< killed after the time limit
  bool aborted = false;     ///< killed because WorkerOptions::poll returned false
  bool signalled = false;   ///< ended by a signal (a crash, or the kernel's OOM killer)
  int signal = 0;
  int status = 0;           ///< exit status when it exited
  /// The host reaped the child before we could (SIGCHLD ignored, or a waitpid(-1) elsewhere):
  /// how it ended is unknown, and the caller judges by the result the worker left (a
  /// completion marker written last).
  bool statusUnknown = false;
};

/// Exit statuses a worker uses besides 0 (done) and 2 (the input is bad, with a message).
constexpr int kWorkerExitUsage = 3;        ///< wrong arguments: a worker of another version
constexpr int kWorkerExitWriteFailed = 4;  ///< the result could not be written (a full disk)
constexpr int kWorkerExitOutOfMemory = 5;  ///< an allocation failed under the memory cap
constexpr int kWorkerExitOrphaned = 6;     ///< its parent was gone when it started: nobody to read it
constexpr int kWorkerExitCannotRun = 127;  ///< the loader could not start it (a missing library)

struct WorkerOptions {
  /// Wall-clock limit; then SIGKILL. Not finite or not positive (NaN included): no limit.
  double timeoutSeconds = 600.0;
  /// Where the worker's stderr goes: empty, inherited; else this file (or "/dev/null").
  std::string stderrPath;
  /// Called about every 2 ms while the worker runs; returning false kills it (aborted). If it
  /// throws, the worker is killed and reaped and the exception goes on.
  std::function<bool()> poll;
};

/// Starts `executable` with `args` (args[0] is the program's name as it sees it), stdin and
/// stdout on /dev/null, and waits for it as `options` say. Throws only what poll throws.
WorkerExit runWorker(const std::string& executable, const std::vector<std::string>& args,
                     const WorkerOptions& options);

/// Called first in a worker's main, with the parent's pid and time limit from its command line:
/// the worker gets SIGKILL when its parent goes (and ends now, kWorkerExitOrphaned, if it has
/// gone already), stops itself (SIGALRM) 10 s after the limit, writes no core dump, its memory
/// is capped (capWorkerMemory) and a failed allocation ends it with kWorkerExitOutOfMemory: C++
/// new, and malloc / calloc / realloc too in a program that links worker_malloc.cpp (the two
/// CAD workers: OpenCASCADE and VTK allocate with them, and catch their own failures). A single
/// request larger than the whole cap and than 64 GiB (a corrupt count) fails back to its caller
/// instead: NULL from malloc, std::bad_alloc from new.
void becomeWorker(const std::string& parentPid, const std::string& timeoutSeconds);

/// A worker's end once its result is written: stderr flushed, then _exit(status), so that no
/// static destructor (OpenCASCADE's registries, TBB, VTK) can turn a whole result into a crash.
[[noreturn]] void endWorker(int status);

/// Caps the data the process may map (RLIMIT_DATA: heap, thread stacks and other private
/// writable mappings, not the address space malloc's arenas reserve) at half the memory it may
/// use: the machine's, or its cgroup's memory.max when lower; between 1 and 16 GiB, and never
/// above a hard limit already in force. So a parser talked into allocating without end
/// (OpenCASCADE's mesher, by one wrong digit: a parameter range of 1e14, found by fuzzing)
/// fails instead of the machine swapping. WIREFUR_WORKER_MEMORY_CAP (bytes) sets the cap
/// instead (tests). Under AddressSanitizer, whose shadow memory needs the room, runWorker sets
/// the cap through ASan's options instead (hard_rss_limit_mb, max_allocation_size_mb). Returns
/// the cap in force, in bytes (0: none).
double capWorkerMemory();

/// The cap capWorkerMemory sets (bytes), for messages.
double workerMemoryCap();

/// A double on the command line: shortest round-trip form, the same in every locale (a Qt or
/// Python host may have set LC_NUMERIC to a decimal comma). parseWorkerNumber reads it back
/// exactly; false when the text is not a whole number in that form.
std::string workerNumber(double value);
bool parseWorkerNumber(const std::string& text, double& value);

/// "signal 11, Segmentation fault".
std::string signalDescription(int signal);

/// The last non-empty line of a small text file (a worker's stderr), at most maxChars long,
/// control characters replaced by spaces; empty when there is none.
std::string lastLineOf(const std::string& path, size_t maxChars = 240);

/// A number for temporary names: random where the system has entropy, else from the clock (the
/// names also carry the pid and a counter; O_EXCL / mkdir make sure they are ours).
unsigned uniqueishNumber();

/// A private folder (mode 0700) under $TMPDIR, or /tmp when TMPDIR is unset or no folder can be
/// made there; removed with everything in it when this object goes, or on a fatal signal in a
/// program that handles them (core/cleanup_on_signal.h). path() is empty when it could not be
/// made.
class TemporaryFolder {
 public:
  explicit TemporaryFolder(const std::string& prefix);
  ~TemporaryFolder();
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  int cleanupSlot_ = -1;
};

}  // namespace wf
