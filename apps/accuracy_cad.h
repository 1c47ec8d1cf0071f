// CAD tessellation (chordal deflection) in `wirefur accuracy`: error against time against a much
// finer deflection; see accuracy_cad.cpp.
#pragma once

#include "cli.h"
#include "plot.h"

#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace wfapp {

nlohmann::ordered_json cadTessellationStudy(bool quick, const Progress& progress,
                                            std::vector<std::pair<std::string, PlotSpec>>& plots);

}  // namespace wfapp
