// Plots through gnuplot (Debian's gnuplot-nox, pngcairo terminal): data and script go to a
// temporary folder, gnuplot draws the PNG. No drawing code of our own.
#pragma once

#include <string>
#include <vector>

namespace wfapp {

struct PlotSeries {
  std::string title;
  std::vector<double> x, y;
  std::vector<std::string> labels;  ///< optional point labels, drawn beside the points
  std::string style = "linespoints";
};

struct PlotSpec {
  std::string title, xlabel, ylabel;
  bool logx = false, logy = true;
  std::vector<PlotSeries> series;
  std::vector<double> hlines;  ///< horizontal reference lines (targets)
};

/// Draws `spec` into `pngPath` (900x720, legend below). Throws std::runtime_error when gnuplot is missing or fails.
void plotPng(const PlotSpec& spec, const std::string& pngPath);

}  // namespace wfapp
