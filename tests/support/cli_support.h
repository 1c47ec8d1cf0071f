// Running the wirefur executable from the command-line tests: exit status and stderr.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace wf::test {

struct CliResult {
  int status;       ///< exit status (-1 when killed by a signal)
  std::string err;  ///< everything written to stderr
};

/// Runs `WIREFUR_EXE args` through the shell, stdout discarded.
inline CliResult runWirefur(const std::string& args) {
  const std::filesystem::path errFile =
      std::filesystem::temp_directory_path() / ("wirefur-cli-err-" + std::to_string(::getpid()));
  const std::string cmd = std::string("'") + WIREFUR_EXE + "' " + args + " >/dev/null 2>'" + errFile.string() + "'";
  const int raw = std::system(cmd.c_str());
  std::ifstream f(errFile);
  std::stringstream ss;
  ss << f.rdbuf();
  std::filesystem::remove(errFile);
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, ss.str()};
}

inline int lineCount(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

}  // namespace wf::test
