// Reading untrusted files in a worker process (the wirefur command's CAD and mesh readers).
//
// OpenCASCADE 7.6 and VTK 9.1's readers can crash, loop for ever or allocate without end on a
// corrupt file (fuzzing found all three). The command therefore reads CAD files
// (apps/cad_input.cpp) and mesh / polyline files (apps/mesh_io.cpp) in a child process of its
// own ("wirefur cad-worker" / "wirefur mesh-worker", internal, not part of the contract): a copy
// of this program started on the file with a time limit and a memory cap
// (core/worker_process.h), which writes what it read to a file in a private temporary folder.
// A crash, a hang or exhaustion in the child becomes one line naming the file and exit status 2.
//
// The result file: 8 bytes of magic (one per reader), one byte of kind (0 the result follows,
// 1 an internal error's words, 2 a bad-input message), then the body, written by BlobWriter and
// read back by BlobReader, which checks every length against what is left.
#pragma once

#include <cstdint>
#include <cstring>
#include <functional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace wfapp {

/// The wirefur command's main calls this: it can run its own readers as workers. A program that
/// merely links the app library (tests, benchmarks, fuzz targets) reads in its own process,
/// since /proc/self/exe is not wirefur there and would run itself again.
void enableReaderWorkers();
bool readerWorkersEnabled();

/// A command that reads the same file more than once (the gallery: four scenes draw one CAD
/// part) calls this: from then on a worker's result is kept (up to 256 MiB of them, the oldest
/// dropped first) and served again for the same path, reader and arguments while the file's
/// identity (device, inode, size, modification and change times) is the same; a request made
/// while the same read is under way (scenes load in parallel) waits for it and shares its
/// outcome, the result or the failure (a failure is not kept: a request made after it reads
/// again). Each worker start loads OpenCASCADE's libraries, about 0.25 s
/// here; reading a 170 kB result again takes none. Off by default: a single render would only
/// hold the copy.
void enableReaderCache();

/// The result key of `path` read by `call` (the reader, the path, the file's device, inode, size,
/// modification and change times, the reader's arguments): empty when the file cannot be
/// stat'ed (never kept). A result is served again only for the same key.
struct ReaderWorkerCall;
std::string readerResultKey(const std::string& path, const ReaderWorkerCall& call);

/// Reader workers started so far, and requests served by another's read (enableReaderCache: a
/// result kept, or a read under way).
struct ReaderRuns {
  std::uint64_t workers = 0, reused = 0;
};
ReaderRuns readerRuns();

/// Polyline starts that fit their points: empty together, from 0 to points.size(), never
/// falling (what the renderer indexes by). For a worker's result before anyone uses it.
inline bool polylineStartsFit(const std::vector<std::uint32_t>& starts, size_t points) {
  if (starts.empty()) return points == 0;
  if (starts.front() != 0 || starts.back() != points) return false;
  for (size_t i = 1; i < starts.size(); ++i)
    if (starts[i] < starts[i - 1]) return false;
  return true;
}

class BlobWriter {
 public:
  explicit BlobWriter(std::ostream& out) : out_(out) {}
  template <class T>
  void pod(const T& v) { out_.write(reinterpret_cast<const char*>(&v), sizeof v); }
  template <class T>
  void vec(const std::vector<T>& v) {
    pod(std::uint64_t(v.size()));
    if (!v.empty()) out_.write(reinterpret_cast<const char*>(v.data()), std::streamsize(v.size() * sizeof(T)));
  }
  void str(const std::string& s) {
    pod(std::uint64_t(s.size()));
    out_.write(s.data(), std::streamsize(s.size()));
  }

 private:
  std::ostream& out_;
};

/// Reads what BlobWriter wrote; a length past the end throws std::runtime_error ("truncated").
class BlobReader {
 public:
  explicit BlobReader(const std::string& bytes) : b_(bytes) {}
  template <class T>
  T pod() {
    T v{};
    need(sizeof v);
    std::memcpy(&v, b_.data() + at_, sizeof v);
    at_ += sizeof v;
    return v;
  }
  template <class T>
  std::vector<T> vec() {
    const std::uint64_t n = pod<std::uint64_t>();
    if (n > (b_.size() - at_) / sizeof(T)) throw std::runtime_error("the reader worker's result is truncated");
    std::vector<T> v(static_cast<size_t>(n));
    if (n) std::memcpy(v.data(), b_.data() + at_, size_t(n) * sizeof(T));
    at_ += size_t(n) * sizeof(T);
    return v;
  }
  bool atEnd() const { return at_ == b_.size(); }
  std::string str() {
    const std::uint64_t n = pod<std::uint64_t>();
    need(n);
    std::string s = b_.substr(at_, size_t(n));
    at_ += size_t(n);
    return s;
  }

 private:
  void need(std::uint64_t n) const {
    if (b_.size() - at_ < n) throw std::runtime_error("the reader worker's result is truncated");
  }
  const std::string& b_;
  size_t at_ = 0;
};

/// One reader run in a worker: what to start and how to word its failures.
struct ReaderWorkerCall {
  std::string mode;             ///< the internal command: "cad-worker", "mesh-worker"
  std::string magic;            ///< 8 bytes at the start of its result file
  std::string workerName;       ///< "CAD worker", "mesh worker": in messages
  std::string what;             ///< "reading and meshing", "reading": for the time-limit message
  std::string library;          ///< whose reader runs there: "OpenCASCADE", "VTK's reader"
  std::string cannotRead;       ///< why a crash: "it is corrupt, or uses something OpenCASCADE 7.6 cannot read"
  std::string timeoutHint;      ///< after the time-limit message: "--cad-timeout S sets the limit"
  std::vector<std::string> extra;  ///< the reader's own arguments, after FILE OUT PARENT TIMEOUT
  double timeoutSeconds = 600.0;
  bool inheritStderr = false;   ///< the worker's progress lines go to our stderr (a terminal)
};

/// Starts `wirefur MODE FILE OUT PARENT TIMEOUT EXTRA...` on `path`, waits for it and returns the
/// body of its result (after the magic and the kind byte 0). Throws UsageError("FILE: ...") for
/// bad input (a message from the reader, a crash, the time limit, the memory cap) and
/// std::runtime_error when the worker could not run or write.
std::string runReaderWorker(const std::string& path, const ReaderWorkerCall& call);

/// The worker's side, after becomeWorker: runs `read` on `file`, which writes the body of a
/// result (kind 0); a UsageError it throws becomes kind 2, so does std::bad_alloc (a request
/// past the cap and 64 GiB: a corrupt count), another exception kind 1. The result is written
/// whole beside `out` and renamed onto it (the parent never reads half a result), then the
/// worker ends (endWorker) with status 0, 2 or 1.
[[noreturn]] void finishReaderWorker(const std::string& file, const std::string& out, const std::string& magic,
                                     const std::function<void(BlobWriter&)>& read);

}  // namespace wfapp
