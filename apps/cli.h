// Small helpers shared by the wirefur subcommands: argument errors, progress, timing.
#pragma once

#include "core/limits.h"  // the limits every command and scene file checks
#include "core/timer.h"

#include <chrono>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>

namespace wfapp {

/// `text` with its control characters written out (\n, \r, \t, \xHH for the rest of C0 and DEL),
/// so that a message quoting a file name, a JSON key or a value stays one line.
std::string oneLine(const std::string& text);

/// The folder holding scenes/ and cad/: <prefix>/share/wirefur beside an installed wirefur
/// (bin/wirefur), else data/ of the source tree this program was built from.
std::string dataDir();

/// Bad input from the user: reported as one line on stderr, exit status 2. The message is made one
/// line here (oneLine), whatever names or values it quotes: a file name or a scene key with a
/// newline in it cannot split it.
struct UsageError : std::runtime_error {
  explicit UsageError(const std::string& what) : std::runtime_error(oneLine(what)) {}
  explicit UsageError(const char* what) : UsageError(std::string(what)) {}
};

/// The system failed, not the input: a file could not be written on the way (a full disk, a
/// quota), a reader worker was stopped by a signal from outside. One line on stderr, exit
/// status 1, without "internal error".
struct OutputError : std::runtime_error {
  explicit OutputError(const std::string& what) : std::runtime_error(oneLine(what)) {}
};

/// One "wirefur: warning: ..." line on stderr, made one line by oneLine (a warning quotes file
/// and object names).
void warn(const std::string& what);

/// Progress lines on stderr only when stderr is a terminal, not in CI and not --quiet.
class Progress {
 public:
  explicit Progress(bool quiet);
  void say(const std::string& line) const;
  bool enabled() const { return enabled_; }

 private:
  bool enabled_;
};

using wf::secondsSince;  // core/timer.h

/// A byte count: plain bytes ("1500000000") or a number with a binary suffix K, M, G or T
/// ("512M", "1.5G"; an optional trailing "iB" or "B"); "0" means unlimited. Nothing when `value`
/// is not one.
std::optional<std::size_t> byteSize(const std::string& value);

/// What is wrong with `value` as a byte count ("expected bytes or a size such as 512M, 2G (0:
/// unlimited), got 'x'"); empty when nothing is.
std::string byteSizeProblem(const std::string& value);

/// byteSize, or UsageError naming the option.
std::size_t parseByteSize(const std::string& option, const std::string& value);

/// Creates a directory (and parents); throws UsageError if it cannot.
void ensureDirectory(const std::string& dir);

}  // namespace wfapp
