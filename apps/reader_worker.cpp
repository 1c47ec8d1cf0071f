#include "reader_worker.h"

#include "cli.h"

#include "core/worker_process.h"

#include <signal.h>
#include <unistd.h>

#include <sys/stat.h>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <exception>
#include <map>
#include <memory>
#include <mutex>
#include <cerrno>
#include <cstdio>
#include <new>
#include <fstream>
#include <sstream>

namespace wfapp {

namespace {

std::atomic<bool> workersEnabled{false};

// The results kept by enableReaderCache: key and body, oldest first; and the reads under way,
// whose outcome (a body or the exception) every request for the same key made meanwhile shares.
struct ReaderRead {
  bool done = false;
  std::shared_ptr<const std::string> body;
  std::exception_ptr failure;
};
struct ReaderCache {
  std::mutex mutex;
  std::condition_variable done;
  std::atomic<bool> enabled{false};
  std::deque<std::pair<std::string, std::shared_ptr<const std::string>>> entries;
  std::map<std::string, std::shared_ptr<ReaderRead>> reading;
  size_t bytes = 0;
  std::uint64_t runs = 0, reused = 0;
};
ReaderCache& readerCache() {
  static ReaderCache cache;
  return cache;
}
constexpr size_t kReaderCacheBytes = size_t(256) << 20;

// The worker's last words on stderr, for a worker that left no result.
std::string failureDetail(const std::string& stderrFile) {
  const std::string words = stderrFile.empty() ? std::string() : wf::lastLineOf(stderrFile);
  return words.empty() ? std::string() : ": " + words;
}

}  // namespace

void enableReaderWorkers() { workersEnabled = true; }
bool readerWorkersEnabled() { return workersEnabled; }

void enableReaderCache() { readerCache().enabled = true; }

namespace {
std::string runReaderWorkerUncached(const std::string& path, const ReaderWorkerCall& call);
}  // namespace

std::string readerResultKey(const std::string& path, const ReaderWorkerCall& call) {
  struct stat st{};
  if (stat(path.c_str(), &st) != 0) return {};
  // (The path too: the result names it, in the CAD reader's info and warnings.)
  std::string key = call.mode + '\0' + path;
  for (long long v : {(long long)st.st_dev, (long long)st.st_ino, (long long)st.st_size, (long long)st.st_mtim.tv_sec,
                      (long long)st.st_mtim.tv_nsec, (long long)st.st_ctim.tv_sec, (long long)st.st_ctim.tv_nsec})
    key += '\0' + std::to_string(v);
  for (const std::string& e : call.extra) key += '\0' + e;
  return key;
}

ReaderRuns readerRuns() {
  ReaderCache& c = readerCache();
  std::lock_guard<std::mutex> lock(c.mutex);
  return {c.runs, c.reused};
}

std::string runReaderWorker(const std::string& path, const ReaderWorkerCall& call) {
  ReaderCache& c = readerCache();
  const std::string key = c.enabled ? readerResultKey(path, call) : std::string();
  std::shared_ptr<ReaderRead> mine;
  {
    std::unique_lock<std::mutex> lock(c.mutex);
    if (!key.empty()) {
      for (const auto& [k, body] : c.entries)
        if (k == key) {
          ++c.reused;
          const std::shared_ptr<const std::string> held = body;  // (the entry may go once unlocked)
          lock.unlock();
          return *held;
        }
      // The same file being read for another scene: its outcome, once there.
      if (auto it = c.reading.find(key); it != c.reading.end()) {
        const std::shared_ptr<ReaderRead> other = it->second;
        ++c.reused;
        c.done.wait(lock, [&] { return other->done; });
        lock.unlock();
        if (other->failure) std::rethrow_exception(other->failure);
        return *other->body;
      }
      mine = std::make_shared<ReaderRead>();
      c.reading.emplace(key, mine);
    }
    ++c.runs;
  }
  if (!mine) return runReaderWorkerUncached(path, call);
  // Whatever happens, the requests waiting for this read get its outcome.
  std::shared_ptr<const std::string> body;
  std::exception_ptr failure;
  try {
    body = std::make_shared<const std::string>(runReaderWorkerUncached(path, call));
  } catch (...) {
    failure = std::current_exception();
  }
  // Kept only if the file is still the one read (its identity taken again after the read). Not
  // keeping it is always safe: nothing below may throw before the waiters have the outcome.
  bool keep = false;
  try {
    keep = body && body->size() <= kReaderCacheBytes && readerResultKey(path, call) == key;
  } catch (...) {
  }
  {
    std::lock_guard<std::mutex> lock(c.mutex);
    mine->body = body;
    mine->failure = failure;
    mine->done = true;
    c.reading.erase(key);
    try {
      if (keep) {
        while (!c.entries.empty() && c.bytes + body->size() > kReaderCacheBytes) {
          c.bytes -= c.entries.front().second->size();
          c.entries.pop_front();
        }
        c.entries.emplace_back(key, body);  // (strong guarantee: nothing added if it throws)
        c.bytes += body->size();
      }
    } catch (...) {
    }
  }
  c.done.notify_all();
  if (failure) std::rethrow_exception(failure);
  return *body;
}

namespace {

std::string runReaderWorkerUncached(const std::string& path, const ReaderWorkerCall& call) {
  const wf::TemporaryFolder folder("wirefur-read-");
  if (folder.path().empty()) throw std::runtime_error("cannot make a temporary folder for the reader worker");
  const std::string out = folder.path() + "/result";
  std::vector<std::string> args = {"wirefur", call.mode, path, out, std::to_string(getpid()),
                                   wf::workerNumber(call.timeoutSeconds)};
  args.insert(args.end(), call.extra.begin(), call.extra.end());
  // The worker's stderr carries its progress lines on a terminal; elsewhere it goes to a file,
  // whose last line explains a worker that could not run or write (std::terminate's words or a
  // dying loader's), without adding lines of its own to the one line.
  wf::WorkerOptions run;
  run.timeoutSeconds = call.timeoutSeconds;
  run.stderrPath = call.inheritStderr ? std::string() : folder.path() + "/stderr";
  const wf::WorkerExit e = wf::runWorker("/proc/self/exe", args, run);
  if (!e.started) throw std::runtime_error("cannot start the " + call.workerName + ": " + e.startError);
  if (e.timedOut || (e.signalled && e.signal == SIGALRM))  // (SIGALRM: the worker's own limit)
    throw UsageError(path + ": " + call.what + " did not finish within " + wf::workerNumber(call.timeoutSeconds) +
                     " s (" + call.library + " may loop on a corrupt file; " + call.timeoutHint + ")");
  if (!e.signalled && e.status == wf::kWorkerExitOutOfMemory) {
    char cap[32];
    std::snprintf(cap, sizeof cap, "%.1f", wf::workerMemoryCap() / double(1 << 30));
    throw UsageError(path + ": out of memory in the " + call.workerName + " (its cap is " + cap +
                     " GiB: half the memory this machine or its cgroup allows)");
  }
  // Stopped from outside (a hang-up reaching the process group under nohup, kill): not the
  // file's fault.
  if (e.signalled && (e.signal == SIGHUP || e.signal == SIGINT || e.signal == SIGTERM || e.signal == SIGQUIT))
    throw OutputError(path + ": the " + call.workerName + " was stopped by " + wf::signalDescription(e.signal) +
                      " before it finished reading");
  if (e.signalled)
    throw UsageError(path + ": " + call.library + " crashed reading this file (" + wf::signalDescription(e.signal) +
                     (e.signal == SIGKILL || e.signal == SIGABRT ? ", out of memory?" : "") + "): " + call.cannotRead);
  std::string bytes;
  {
    std::ifstream in(out, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    bytes = ss.str();
  }
  // No result at all: the worker died inside the reader without a signal reaching us (a
  // sanitizer's handler, for one, turns the crash into an exit status), or could not run or
  // write. (Whether the status is known or not: the result is written last.)
  if (bytes.size() < call.magic.size() + 1 || bytes.compare(0, call.magic.size(), call.magic) != 0) {
    if (!e.signalled && !e.statusUnknown && e.status != 0 && e.status != 1 && e.status != 2 &&
        e.status != wf::kWorkerExitOutOfMemory && e.status < 128)
      throw std::runtime_error("the " + call.workerName + " failed (status " + std::to_string(e.status) + ")" +
                               failureDetail(run.stderrPath));
    throw UsageError(path + ": " + call.library + " crashed reading this file (the worker stopped with " +
                     (e.statusUnknown ? std::string("an unknown status") : "status " + std::to_string(e.status)) +
                     " and no result" + failureDetail(run.stderrPath) + "): " + call.cannotRead);
  }
  const char kind = bytes[call.magic.size()];
  bytes.erase(0, call.magic.size() + 1);  // in place: no second copy of a large result
  if (kind == 0) return bytes;
  BlobReader r(bytes);
  const std::string message = r.str();
  if (kind == 2) throw UsageError(message);
  throw std::runtime_error(message);
}

}  // namespace

void finishReaderWorker(const std::string& file, const std::string& out, const std::string& magic,
                        const std::function<void(BlobWriter&)>& read) {
  // Written straight to OUT.part (no second copy in memory under the cap), then renamed: the
  // parent reads no file (a crash) or a whole one. A failure on the way starts the file again
  // with its message.
  const std::string part = out + ".part";
  std::ofstream f(part, std::ios::binary | std::ios::trunc);
  auto restart = [&](char kind) {
    f.close();
    f.open(part, std::ios::binary | std::ios::trunc);
    f.write(magic.data(), std::streamsize(magic.size()));
    f.put(kind);
  };
  int status = 0;
  restart(0);
  BlobWriter w(f);
  try {
    read(w);
  } catch (const std::bad_alloc&) {  // one request past the cap and 64 GiB (worker_malloc.cpp)
    restart(2);
    w.str(file + ": the file asks for more memory than the reader may ever use (a corrupt count)");
    status = 2;
  } catch (const UsageError& e) {
    restart(2);
    w.str(e.what());
    status = 2;
  } catch (const std::exception& e) {
    restart(1);
    w.str(e.what());
    status = 1;
  }
  f.close();
  if (!f || std::rename(part.c_str(), out.c_str()) != 0) {
    std::fprintf(stderr, "cannot write the result to %s: %s\n", out.c_str(), std::strerror(errno));
    wf::endWorker(wf::kWorkerExitWriteFailed);
  }
  wf::endWorker(status);
}

}  // namespace wfapp
