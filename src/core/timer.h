// Wall-clock time for the reports (stats, benchmarks, frame times): one definition for the core,
// the apps, the VTK module and the tests.
#pragma once

#include <chrono>

namespace wf {

/// Seconds from t0 to now on the steady clock.
inline double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace wf
