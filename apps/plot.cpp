#include "plot.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace wfapp {
namespace {

std::string quoted(const std::string& s) {
  std::string r = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') r += '\\';
    r += c;
  }
  return r + "\"";
}

}  // namespace

void plotPng(const PlotSpec& spec, const std::string& pngPath) {
  namespace fs = std::filesystem;
  // A folder of this call's own: mkdtemp, so no other process and no folder left by an earlier
  // process with the same pid can share it.
  std::string tmpl = (fs::temp_directory_path() / "wirefur-plot-XXXXXX").string();
  if (::mkdtemp(tmpl.data()) == nullptr) throw std::runtime_error(pngPath + ": cannot make a folder for gnuplot in " + fs::temp_directory_path().string());
  const fs::path dir = tmpl;
  const fs::path script = dir / "plot.gp";
  std::ofstream gp(script);
  gp << "set terminal pngcairo size 900,720 font 'Sans,10'\n";
  gp << "set output " << quoted(fs::absolute(pngPath).string() + ".tmp") << "\n";
  gp << "set title " << quoted(spec.title) << "\n";
  gp << "set xlabel " << quoted(spec.xlabel) << "\nset ylabel " << quoted(spec.ylabel) << "\n";
  gp << "set grid\nset key below Left reverse\nset format y '%.0e'\n";
  if (spec.logx) gp << "set logscale x\n";
  if (spec.logy) gp << "set logscale y\n";
  for (double h : spec.hlines) gp << "set arrow from graph 0, first " << h << " to graph 1, first " << h
                                  << " nohead dt 2 lc rgb '#aa0000'\n";
  std::string plots;
  for (size_t i = 0; i < spec.series.size(); ++i) {
    const PlotSeries& s = spec.series[i];
    std::string dataName = std::to_string(i);
    dataName += ".dat";
    const fs::path data = dir / dataName;
    std::ofstream d(data);
    d.precision(10);
    for (size_t k = 0; k < s.x.size(); ++k)
      d << s.x[k] << " " << std::max(s.y[k], 1e-12) << " "
        << (k < s.labels.size() ? quoted(s.labels[k]) : "\"\"") << "\n";
    if (!plots.empty()) plots += ", ";
    plots += quoted(data.string()) + " using 1:2 with " + s.style + " lw 2 title " + quoted(s.title);
    if (!s.labels.empty())
      plots += ", " + quoted(data.string()) + " using 1:2:3 with labels offset 1.2,0.6 font ',8' notitle";
  }
  gp << "plot " << plots << "\n";
  gp.close();
  const std::string cmd = "gnuplot " + quoted(script.string()) + " 2>" + quoted((dir / "err.txt").string());
  const int rc = std::system(cmd.c_str());
  std::error_code ec;
  if (rc != 0 || !fs::exists(pngPath + ".tmp")) {
    std::ifstream err(dir / "err.txt");
    std::string first;
    std::getline(err, first);
    fs::remove_all(dir, ec);
    fs::remove(pngPath + ".tmp", ec);
    throw std::runtime_error(pngPath + ": gnuplot failed (" + (first.empty() ? "is gnuplot-nox installed?" : first) + ")");
  }
  fs::rename(pngPath + ".tmp", pngPath, ec);
  fs::remove_all(dir, ec);
  if (ec) throw std::runtime_error(pngPath + ": cannot write plot (" + ec.message() + ")");
}

}  // namespace wfapp
