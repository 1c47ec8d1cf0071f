// The A-buffer knobs of `wirefur accuracy` (mask size, fragment budget K) against the
// brute-force reference; see accuracy_abuffer.cpp.
#pragma once

#include "cli.h"
#include "plot.h"

#include "render/renderer.h"

#include <nlohmann/json.hpp>

#include <glm/glm.hpp>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

namespace wfapp {

/// The largest difference of any colour channel.
inline double channelError(const glm::dvec3& a, const glm::dvec3& b) {
  const glm::dvec3 d = glm::abs(a - b);
  return std::max({d.x, d.y, d.z});
}

/// Renders `reps` times with the A-buffer; the median total seconds, `last` the last result.
double medianSeconds(int reps, const wf::Scene& s, const wf::RenderOptions& o, wf::RenderResult& last);

/// Runs the study; returns its JSON and appends (file name, plot) pairs to `plots`.
nlohmann::ordered_json abufferStudy(bool quick, const Progress& progress,
                                    std::vector<std::pair<std::string, PlotSpec>>& plots);

}  // namespace wfapp
