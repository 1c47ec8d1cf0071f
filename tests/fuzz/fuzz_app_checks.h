// What fuzz_scene and fuzz_mesh check after the code under test returns: the one-line error
// contract (docs/design.md: "one line on stderr naming the file, the place in it and what is wrong")
// and the geometry the readers hand to the renderer (indices in range, array sizes that agree).
// A broken check is a finding: the program prints one FINDING line and aborts, so that libFuzzer
// keeps the input (run_fuzz.sh counts these as WireFur's own).
#pragma once

#include "render/scene.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace wffuzz {

inline std::string g_dir;  // this process's temporary folder (libFuzzer -fork/-jobs run several)

[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "\n==WIREFUR-FUZZ== FINDING: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

inline void removeDir() {
  std::error_code ec;
  if (!g_dir.empty()) std::filesystem::remove_all(g_dir, ec);
}

/// Makes this process's folder (temp/wf-<name>fuzz-XXXXXX), removed at exit.
inline void makeDir(const char* name) {
  std::string tmpl = (std::filesystem::temp_directory_path() / (std::string("wf-") + name + "fuzz-XXXXXX")).string();
  if (!mkdtemp(tmpl.data())) {
    std::perror("mkdtemp");
    std::exit(1);
  }
  g_dir = tmpl;
  std::atexit(removeDir);
}

/// A UsageError's message: one line, not empty, naming `file` (the contract's "FILE: problem").
inline void checkMessage(const std::string& message, const std::string& file) {
  if (message.empty()) finding("empty error message");
  if (message.find_first_of("\r\n") != std::string::npos) finding("error message of more than one line: " + message);
  if (message.find(file) == std::string::npos) finding("error message does not name the file " + file + ": " + message);
}

inline void checkMesh(const wf::TriangleMesh& m, const std::string& what) {
  const size_t n = m.positions.size();
  auto sized = [&](size_t k, const char* name) {
    if (k != 0 && k != n)
      finding(what + ": " + name + " has " + std::to_string(k) + " entries for " + std::to_string(n) + " positions");
  };
  sized(m.normals.size(), "normals");
  sized(m.tangents.size(), "tangents");
  sized(m.derivU.size(), "derivU");
  sized(m.derivV.size(), "derivV");
  sized(m.uvs.size(), "uvs");
  sized(m.colours.size(), "colours");
  for (size_t t = 0; t < m.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (m.triangles[t][k] >= n)
        finding(what + ": triangle " + std::to_string(t) + " names vertex " + std::to_string(m.triangles[t][k]) + " of " +
                std::to_string(n));
}

inline void checkLines(const wf::PolylineSet& l, const std::string& what) {
  if (l.starts.empty()) {
    if (!l.points.empty()) finding(what + ": points without polylines");
  } else {
    if (l.starts.front() != 0) finding(what + ": the first polyline does not start at 0");
    for (size_t i = 1; i < l.starts.size(); ++i)
      if (l.starts[i] < l.starts[i - 1]) finding(what + ": polyline starts decrease at " + std::to_string(i));
    if (l.starts.back() != l.points.size())
      finding(what + ": the last polyline ends at " + std::to_string(l.starts.back()) + " of " + std::to_string(l.points.size()) +
              " points");
  }
  if (!l.colours.empty() && l.colours.size() != l.points.size())
    finding(what + ": " + std::to_string(l.colours.size()) + " colours for " + std::to_string(l.points.size()) + " points");
}

}  // namespace wffuzz
