// Textures and grooves in `wirefur accuracy`: the A-buffer's box filter over each pixel's (u, v)
// footprint against the reference's per-sample point sampling; see accuracy_textures.cpp.
#pragma once

#include "cli.h"
#include "plot.h"

#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace wfapp {

nlohmann::ordered_json texturesStudy(bool quick, const Progress& progress,
                                     std::vector<std::pair<std::string, PlotSpec>>& plots);

/// Tessellation resolution of a smooth surface against a much finer one (exact shading).
nlohmann::ordered_json tessellationStudy(bool quick, const Progress& progress,
                                         std::vector<std::pair<std::string, PlotSpec>>& plots);

}  // namespace wfapp
