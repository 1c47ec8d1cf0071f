// What the peer and scaling benchmarks (peer_hair, peer_raycast, bench_scaling) share: the
// median of repeated timings, a peer's time at a given error, the peak resident memory, the hair benchmark's camera and
// segments as a WireFur scene's parts, and running one measurement in a forked child so that its
// peak memory (ru_maxrss) is its own.
#pragma once

#include "hair_torus.h"

#include "render/camera.h"
#include "render/scene.h"

#include <nlohmann/json.hpp>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

namespace wfbench {

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : (v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]));
}

/// A peer's time at error e, from its (time, error) curve, time rising and error falling (its
/// settings from the fastest to the most accurate): log-log interpolation between the two
/// points that bracket e (`how` "interpolated"); the fastest point's time where e is at or above
/// its error ("above the fastest run's error"); extrapolation along the last two points where e
/// is below them all ("extrapolated"); "n/a" (0) for no curve, or one point above e.
inline double timeAtError(const std::vector<std::pair<double, double>>& curve, double e, std::string& how) {
  for (size_t k = 0; k + 1 < curve.size(); ++k) {
    const auto [t0, e0] = curve[k];
    const auto [t1, e1] = curve[k + 1];
    if (e <= e0 && e >= e1 && e0 > e1) {
      how = "interpolated";
      const double f = std::log(e0 / e) / std::log(e0 / e1);
      return std::exp(std::log(t0) + f * std::log(t1 / t0));
    }
  }
  if (!curve.empty() && e >= curve.front().second) {
    how = "above the fastest run's error";
    return curve.front().first;
  }
  if (curve.size() < 2) {
    how = "n/a";
    return 0;
  }
  const auto [t0, e0] = curve[curve.size() - 2];
  const auto [t1, e1] = curve.back();
  how = "extrapolated";
  if (!(e0 > e1)) return t1;
  const double p = std::log(t1 / t0) / std::log(e0 / e1);  // time ~ error^-p
  return t1 * std::pow(e1 / e, p);
}

/// Peak resident memory of this process so far, bytes.
inline long peakRssBytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return long(u.ru_maxrss) * 1024;
}

/// The hair benchmark's camera (hair_torus.h) as a WireFur camera.
inline wf::Camera camera(const HairCamera& hc = {}) {
  wf::Camera cam;
  cam.eye = hc.eye;
  cam.target = hc.target;
  cam.up = hc.up;
  cam.fovYDegrees = hc.fovYDegrees;
  cam.nearPlane = hc.nearPlane;
  cam.farPlane = hc.farPlane;
  return cam;
}

/// One two-point polyline per segment.
inline wf::PolylineSet polylines(const std::vector<HairSegment>& segs) {
  wf::PolylineSet lines;
  lines.points.reserve(segs.size() * 2);
  lines.starts.reserve(segs.size() + 1);
  lines.starts.push_back(0);
  for (const HairSegment& s : segs) {
    lines.points.push_back(s.p0);
    lines.points.push_back(s.p1);
    lines.starts.push_back(std::uint32_t(lines.points.size()));
  }
  return lines;
}

/// Runs `work(json&)` in a forked child, which adds its peak_rss_bytes and writes the JSON to
/// `path`; the parent reads it into `out` and removes the file. False when the child failed (its
/// exception is printed, prefixed by `program`).
template <class F>
bool inChild(const char* program, const std::string& path, nlohmann::ordered_json& out, F&& work) {
  std::fflush(nullptr);
  const pid_t pid = fork();
  if (pid < 0) return false;
  if (pid == 0) {
    int rc = 0;
    try {
      nlohmann::ordered_json j;
      work(j);
      j["peak_rss_bytes"] = peakRssBytes();
      std::ofstream(path) << j.dump();
    } catch (const std::exception& e) {
      std::cerr << program << ": " << e.what() << "\n";
      rc = 1;
    }
    std::fflush(nullptr);
    _exit(rc);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return false;
  std::ifstream in(path);
  if (!in) return false;
  in >> out;
  std::remove(path.c_str());
  return true;
}

}  // namespace wfbench
