// The A-buffer knobs of `wirefur accuracy` (mask size, fragment budget K) against the
// brute-force reference; see accuracy_abuffer.cpp.
#pragma once

#include "cli.h"
#include "plot.h"

#include "render/renderer.h"

#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace wfapp {

/// Renders `reps` times with the A-buffer; the median total seconds, `last` the last result.
double medianSeconds(int reps, const wf::Scene& s, const wf::RenderOptions& o, wf::RenderResult& last);

/// Runs the study; returns its JSON and appends (file name, plot) pairs to `plots`.
nlohmann::ordered_json abufferStudy(bool quick, const Progress& progress,
                                    std::vector<std::pair<std::string, PlotSpec>>& plots);

}  // namespace wfapp
