// The shading paths in `wirefur accuracy`: the closed form's lobe table (resolution against
// build time), the cost and error per fragment of every way to shade a cylinder, and the three
// render paths (closed, maps, exact) on every gallery scene and on a CAD part; see
// accuracy_shading.cpp.
#pragma once

#include "cli.h"
#include "plot.h"

#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace wfapp {

/// Runs the study; returns its JSON and appends (file name, plot) pairs to `plots`.
nlohmann::ordered_json shadingPathsStudy(bool quick, const Progress& progress,
                                         std::vector<std::pair<std::string, PlotSpec>>& plots);

}  // namespace wfapp
