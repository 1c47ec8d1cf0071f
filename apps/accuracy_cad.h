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
/// Silhouette tracing (surface/silhouette.h): screen error of the drawn chords against a much
/// finer tracing (0.002 px, grid 256), and time, as the tolerance falls; a torus and a sphere in
/// perspective at 1280 x 960.
nlohmann::ordered_json silhouetteStudy(bool quick, const Progress& progress, std::vector<std::pair<std::string, PlotSpec>>& plots);

}  // namespace wfapp
