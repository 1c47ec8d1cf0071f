#include "cli.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

namespace wfapp {

Progress::Progress(bool quiet) {
  const char* ci = std::getenv("CI");
  enabled_ = !quiet && isatty(STDERR_FILENO) && !(ci && *ci && std::string(ci) != "false");
}

void Progress::say(const std::string& line) const {
  if (enabled_) std::cerr << "wirefur: " << line << "\n";
}

int parsePositiveInt(const std::string& option, const std::string& value) {
  try {
    if (value.empty() || value.find_first_not_of("0123456789") != std::string::npos) throw std::invalid_argument("digits");
    size_t used = 0;
    const long v = std::stol(value, &used);
    if (used != value.size() || v <= 0 || v > 1000000) throw std::invalid_argument("range");
    return int(v);
  } catch (const std::exception&) {
    throw UsageError("option " + option + ": expected a positive integer, got '" + value + "'");
  }
}

void ensureDirectory(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir))
    throw UsageError(dir + ": cannot create directory (" + ec.message() + ")");
}

}  // namespace wfapp
