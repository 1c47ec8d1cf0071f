// Running the wirefur executable from the command-line tests: exit status and stderr.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <stdexcept>
#include <sstream>
#include <string>
#include <vector>

extern char** environ;

namespace wf::test {

/// This test process's own folder, made by mkdtemp on first use (so no other process, nor a
/// folder left by an earlier process that had the same pid, can be in it) and removed when the
/// process exits.
inline const std::filesystem::path& processScratchRoot() {
  // Never destroyed: the exit handler below runs after static destructors registered later.
  static const std::filesystem::path* const root = [] {
    std::string tmpl = (std::filesystem::temp_directory_path() / "wirefur-test-XXXXXX").string();
    if (::mkdtemp(tmpl.data()) == nullptr) throw std::runtime_error("mkdtemp failed for " + tmpl);
    auto* p = new std::filesystem::path(tmpl);
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(processScratchRoot(), ec);
    });
    return p;
  }();
  return *root;
}

struct CliResult {
  int status;       ///< exit status (-1 when killed by a signal)
  std::string err;  ///< everything written to stderr
};

/// Runs a shell command line, stdout discarded.
inline CliResult runCommand(const std::string& command) {
  const std::filesystem::path errFile = processScratchRoot() / "stderr.txt";
  const std::string cmd = command + " >/dev/null 2>'" + errFile.string() + "'";
  const int raw = std::system(cmd.c_str());
  std::ifstream f(errFile);
  std::stringstream ss;
  ss << f.rdbuf();
  std::filesystem::remove(errFile);
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, ss.str()};
}

/// Runs `WIREFUR_EXE args` through the shell, stdout discarded.
inline CliResult runWirefur(const std::string& args) { return runCommand(std::string("'") + WIREFUR_EXE + "' " + args); }

/// Starts `WIREFUR_EXE args` (stdout and stderr to /dev/null, this process's environment) without
/// waiting: for tests that signal it or run several at once. Returns its pid, -1 on failure.
inline pid_t spawnWirefur(std::vector<std::string> args) {
  args.insert(args.begin(), WIREFUR_EXE);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&fa, 2, "/dev/null", O_WRONLY, 0);
  pid_t pid = -1;
  if (posix_spawn(&pid, WIREFUR_EXE, &fa, nullptr, argv.data(), environ) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&fa);
  return pid;
}

/// Kills and reaps a spawned process when a test leaves early (a failed ASSERT); set pid to -1
/// once it has been waited for.
struct ProcessGuard {
  pid_t pid = -1;
  ~ProcessGuard() {
    if (pid > 0) {
      kill(pid, SIGKILL);
      waitpid(pid, nullptr, 0);
    }
  }
};

struct CliOutput {
  int status;       ///< exit status (-1 when killed by a signal)
  std::string out;  ///< everything written to stdout
  std::string err;  ///< everything written to stderr
};

/// Runs `WIREFUR_EXE args` through the shell, keeping stdout too (help texts).
inline CliOutput runWirefurWithOutput(const std::string& args) {
  const std::filesystem::path outFile = processScratchRoot() / "stdout.txt", errFile = processScratchRoot() / "stderr.txt";
  const std::string cmd = std::string("'") + WIREFUR_EXE + "' " + args + " >'" + outFile.string() + "' 2>'" + errFile.string() + "'";
  const int raw = std::system(cmd.c_str());
  auto slurp = [](const std::filesystem::path& p) {
    std::ifstream f(p);
    std::stringstream ss;
    ss << f.rdbuf();
    std::filesystem::remove(p);
    return ss.str();
  };
  const std::string out = slurp(outFile);
  return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, out, slurp(errFile)};
}

/// A folder of this test process's own under processScratchRoot(), emptied on first use.
inline std::filesystem::path scratchDir(const std::string& prefix) {
  const std::filesystem::path p = processScratchRoot() / prefix;
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
