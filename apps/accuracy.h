// `wirefur accuracy`: error against run time for every approximation of the shading core
// (map resolution and samples, the orthographic view assumption).
#pragma once

#include <string>

namespace wfapp {

struct AccuracyOptions {
  std::string jsonPath;  ///< empty: no JSON
  std::string plotsDir;  ///< empty: no plots
  bool quick = false;    ///< smaller sets, for tests
  bool quiet = false;
};

/// Runs the study, prints a summary table on stdout, writes JSON and plots. Returns exit status.
int runAccuracy(const AccuracyOptions& options);

}  // namespace wfapp
