// Files the wirefur command reads and writes, made safe against what a shell can hand it.
//
// Inputs (scene files, mesh and CAD files, textures, files a scene names) must be regular files:
// a FIFO would block the read for ever, /dev/zero or /dev/urandom would grow it without end.
// Outputs (-o, --stats, export files) never replace something that is not a regular file (run
// as root, a rename onto /dev/full replaced the device), are written under a unique name beside
// the target and renamed onto it (so concurrent renders to one path leave one whole image), and
// the temporary is removed when the command fails or is stopped by SIGINT, SIGTERM or SIGHUP
// (core/cleanup_on_signal.h).
#pragma once

#include <string>

namespace wfapp {

/// Throws UsageError("FILE: no such file" / "is a folder" / "is a FIFO, not a regular file") unless
/// `path` (links followed) is a regular file.
void requireInputFile(const std::string& path);

/// The whole of a regular file, opened once and checked on the open descriptor (a name swapped
/// for a FIFO after requireInputFile cannot block the read). `what` names it in messages ("a
/// scene file", "a PNG image"). Throws UsageError.
std::string readInputFile(const std::string& path, const char* what);

/// Throws UsageError unless `path` can be an output: its folder exists, and the path is nothing
/// yet or a regular file (links followed), not a folder, device, FIFO or socket.
void requireOutputPath(const std::string& path);

/// Writes `text` to `path` as OutputFile does (checked with requireOutputPath, a unique
/// temporary renamed onto it). Throws UsageError for a bad path, OutputError when a write fails.
void writeOutputText(const std::string& path, const std::string& text);

/// A temporary ".NAME.PID.N.RANDOM.tmp.EXT" beside `target` (EXT its extension), made with O_EXCL (no other process's),
/// removed on a stopping signal and when this object goes without commit().
class OutputFile {
 public:
  explicit OutputFile(const std::string& target);
  ~OutputFile();
  OutputFile(const OutputFile&) = delete;
  OutputFile& operator=(const OutputFile&) = delete;
  const std::string& temporaryPath() const { return tmp_; }
  /// Makes and removes a temporary beside `target`: throws UsageError now, before a long
  /// render, when the folder cannot be written; leaves nothing behind a later crash.
  static void probe(const std::string& target) { const OutputFile made{target}; }
  /// Renames the temporary onto the target (checked again: still not a device). Throws
  /// std::runtime_error("TARGET: cannot write (why)") and removes the temporary on failure.
  void commit();

 private:
  std::string target_, tmp_;
  int slot_ = -1;
  bool done_ = false;
};

}  // namespace wfapp
