// Running untrusted-input parsers in a process of their own: the wirefur command's CAD worker
// (apps/cad_input.cpp) and vtkWireFurCADReader's ReadInWorker (vtk_filters/cad/) start a child,
// wait for it with a time limit and read its result from a private temporary folder. A crash, a
// hang or a memory cap hit in the child is reported by the parent, which carries on.
#pragma once

#include <string>
#include <vector>

namespace wf {

/// How a worker ended.
struct WorkerExit {
  bool started = false;     ///< false: posix_spawn failed (startError says why)
  std::string startError;
  bool timedOut = false;    ///< killed after the time limit
  bool signalled = false;   ///< ended by a signal (a crash, or the kernel's OOM killer)
  int signal = 0;
  int status = 0;           ///< exit status when it exited
};

/// Starts `executable` with `args` (args[0] is the program's name as it sees it), stdout to
/// /dev/null (and stderr too when silenceStderr), waits at most timeoutSeconds (then kills it
/// with SIGKILL). Never throws.
WorkerExit runWorker(const std::string& executable, const std::vector<std::string>& args,
                     double timeoutSeconds, bool silenceStderr);

/// Called in a worker: caps its address space at half the machine's memory, between 2 and
/// 16 GiB, so that a parser talked into allocating without end (OpenCASCADE's mesher, by one
/// wrong digit: a parameter range of 1e14, found by fuzzing) fails or dies instead of the machine
/// swapping. Nothing under AddressSanitizer, whose shadow memory needs the address space.
void capWorkerMemory();

/// "signal 11, Segmentation fault".
std::string signalDescription(int signal);

/// A private folder (mode 0700) under $TMPDIR (or /tmp when unset or not a folder), removed with
/// everything in it when this object goes. path() is empty when it could not be made.
class TemporaryFolder {
 public:
  explicit TemporaryFolder(const std::string& prefix);
  ~TemporaryFolder();
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace wf
