// Running the wirefur executable from the command-line tests: exit status and stderr.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
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

/// A folder of this test process's own, emptied on first use: temp/<prefix>-<pid>.
inline std::filesystem::path scratchDir(const std::string& prefix) {
  const std::filesystem::path p = std::filesystem::temp_directory_path() / (prefix + "-" + std::to_string(::getpid()));
  static std::set<std::string> cleared;  // each prefix is emptied once per process
  if (cleared.insert(prefix).second) std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p;
}

/// The whole of a file (empty when it cannot be read).
inline std::string readFile(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// Writes `bytes` to `dir / name` and returns the path.
inline std::string writeFile(const std::filesystem::path& dir, const std::string& name, const std::string& bytes) {
  const std::filesystem::path p = dir / name;
  std::ofstream(p, std::ios::binary) << bytes;
  return p.string();
}

inline int lineCount(const std::string& s) {
  int n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

}  // namespace wf::test
