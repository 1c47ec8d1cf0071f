#include "cli.h"

#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace wfapp {

Progress::Progress(bool quiet) {
  const char* ci = std::getenv("CI");
  enabled_ = !quiet && isatty(STDERR_FILENO) && !(ci && *ci && std::string(ci) != "false");
}

void Progress::say(const std::string& line) const {
  if (enabled_) std::cerr << "wirefur: " << oneLine(line) << "\n";
}

void warn(const std::string& what) { std::cerr << "wirefur: warning: " << oneLine(what) << "\n"; }

std::optional<std::size_t> byteSize(const std::string& value) {
  std::string v = value;
  for (const char* unit : {"iB", "B"})
    if (v.size() > std::strlen(unit) && v.compare(v.size() - std::strlen(unit), std::string::npos, unit) == 0) {
      v.resize(v.size() - std::strlen(unit));
      break;
    }
  double scale = 1.0;
  if (!v.empty()) {
    switch (std::toupper(static_cast<unsigned char>(v.back()))) {
      case 'K': scale = 1024.0; break;
      case 'M': scale = 1024.0 * 1024; break;
      case 'G': scale = 1024.0 * 1024 * 1024; break;
      case 'T': scale = 1024.0 * 1024 * 1024 * 1024; break;
      default: break;
    }
    if (scale > 1.0) v.pop_back();
  }
  if (v.empty() || v.find_first_not_of("0123456789.") != std::string::npos || v.front() == '.') return std::nullopt;
  char* end = nullptr;
  const double n = std::strtod(v.c_str(), &end) * scale;
  if (*end != '\0' || !std::isfinite(n) || n < 0 || n > 1.0e18) return std::nullopt;
  return std::size_t(n);
}

std::string byteSizeProblem(const std::string& value) {
  if (byteSize(value)) return {};
  return "expected bytes or a size such as 512M, 2G (0: unlimited), got '" + value + "'";
}

std::string dataDir() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const std::filesystem::path installed = exe.parent_path().parent_path() / "share" / "wirefur";
    if (std::filesystem::is_directory(installed / "scenes", ec)) return installed.string();
  }
  return std::string(WIREFUR_SOURCE_DIR) + "/data";
}

std::string oneLine(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '\n') {
      out += "\\n";
    } else if (c == '\r') {
      out += "\\r";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c < 0x20 || c == 0x7f) {
      static const char* hex = "0123456789abcdef";
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    } else {
      out += ch;
    }
  }
  return out;
}

std::size_t parseByteSize(const std::string& option, const std::string& value) {
  if (const std::optional<std::size_t> n = byteSize(value)) return *n;
  throw UsageError("option " + option + ": " + byteSizeProblem(value));
}

void ensureDirectory(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw UsageError(dir + ": cannot create directory (" + ec.message() + ")");
}

}  // namespace wfapp
