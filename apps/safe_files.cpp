#include "safe_files.h"

#include "cli.h"

#include "core/cleanup_on_signal.h"
#include "core/worker_process.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace wfapp {

namespace {

const char* kindOf(mode_t m) {
  if (S_ISDIR(m)) return "a folder";
  if (S_ISFIFO(m)) return "a FIFO";
  if (S_ISCHR(m)) return "a character device";
  if (S_ISBLK(m)) return "a block device";
  if (S_ISSOCK(m)) return "a socket";
  return "not a regular file";
}

}  // namespace

void requireInputFile(const std::string& path) {
  struct stat st;
  if (stat(path.c_str(), &st) != 0) {
    if (errno == ENOENT || errno == ENOTDIR) throw UsageError(path + ": no such file");
    throw UsageError(path + ": cannot read (" + std::strerror(errno) + ")");
  }
  if (S_ISDIR(st.st_mode)) throw UsageError(path + ": is a folder, not a file");
  if (!S_ISREG(st.st_mode)) throw UsageError(path + ": is " + kindOf(st.st_mode) + ", not a regular file: refused");
}

std::string readInputFile(const std::string& path, const char* what) {
  requireInputFile(path);
  // O_NONBLOCK: were it a FIFO by now, the open itself would not wait for a writer.
  const int fd = open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw UsageError(path + ": cannot open " + what + " (" + std::strerror(errno) + ")");
  struct stat st {};
  if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    const std::string kind = S_ISREG(st.st_mode) || st.st_mode == 0 ? std::string("unreadable") : kindOf(st.st_mode);
    close(fd);
    throw UsageError(path + ": is " + kind + ", not a regular file: refused");
  }
  fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  std::string bytes;
  bytes.reserve(size_t(std::min<off_t>(st.st_size, off_t(1) << 28)));  // (a size is a claim)
  char buffer[1 << 16];
  for (;;) {
    const ssize_t n = read(fd, buffer, sizeof buffer);
    if (n > 0) bytes.append(buffer, size_t(n));
    else if (n == 0) break;
    else if (errno != EINTR) {
      const int err = errno;
      close(fd);
      throw UsageError(path + ": cannot read " + what + " (" + std::strerror(err) + ")");
    }
  }
  close(fd);
  return bytes;
}

void requireOutputPath(const std::string& path) {
  const std::filesystem::path target(path), parent = target.parent_path();
  std::error_code ec;
  if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
    throw UsageError(path + ": the folder " + parent.string() + " does not exist");
  struct stat st;
  if (stat(path.c_str(), &st) == 0) {
    if (S_ISDIR(st.st_mode)) throw UsageError(path + ": is a folder");
    if (!S_ISREG(st.st_mode))
      throw UsageError(path + ": is " + std::string(kindOf(st.st_mode)) + ", not a regular file: not replaced");
  }
}

OutputFile::OutputFile(const std::string& target) : target_(target) {
  const std::filesystem::path t(target);
  const std::string dir = t.parent_path().empty() ? std::string(".") : t.parent_path().string();
  // The name is registered for removal before the file exists (O_EXCL makes sure it is ours):
  // a stopping signal, which any thread may take, then finds it registered whenever it comes.
  // Mode 0666 less the umask, as any new file (the kernel applies it).
  static std::atomic<unsigned> counter{0};
  std::string base = t.filename().string();
  if (base.size() > 120) base.resize(120);  // room for the suffix within NAME_MAX
  int fd = -1, err = 0;
  std::string name;
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    char suffix[48];
    std::snprintf(suffix, sizeof suffix, ".%d.%u.%08x.tmp", int(getpid()), counter++, wf::uniqueishNumber());
    // ... ending in the target's extension: some writers add theirs (vtkPLYWriter, ".ply").
    name = dir + "/." + base + suffix + t.extension().string();
    slot_ = wf::registerCleanup(name, false);
    fd = open(name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    err = errno;
    if (fd < 0) {
      wf::forgetCleanup(slot_);
      slot_ = -1;
      if (err != EEXIST) break;
    }
  }
  if (fd < 0) throw UsageError(target + ": cannot be written here (" + std::strerror(err) + ")");
  close(fd);
  tmp_ = name;
}

OutputFile::~OutputFile() {
  if (!done_) std::remove(tmp_.c_str());
  wf::forgetCleanup(slot_);
}

void OutputFile::commit() {
  struct stat st;
  std::string why;
  if (stat(target_.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) why = std::string("it became ") + kindOf(st.st_mode);
  else if (std::rename(tmp_.c_str(), target_.c_str()) != 0) why = std::strerror(errno);
  if (!why.empty()) {
    std::remove(tmp_.c_str());
    done_ = true;
    throw OutputError(target_ + ": cannot write (" + why + ")");
  }
  done_ = true;
  wf::forgetCleanup(slot_);
  slot_ = -1;
}

void writeOutputText(const std::string& path, const std::string& text) {
  requireOutputPath(path);
  OutputFile out(path);
  {
    std::ofstream f(out.temporaryPath(), std::ios::binary | std::ios::trunc);
    f << text;
    f.close();
    if (!f) throw OutputError(path + ": cannot write");
  }
  out.commit();
}

}  // namespace wfapp
