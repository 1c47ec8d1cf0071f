// wirefur: the command-line face of WireFur (see docs/cli.md for the contract).
#include "accuracy.h"
#include "cad_input.h"
#include "cli.h"
#include "gallery.h"
#include "export_command.h"
#include "render_command.h"
#ifdef WIREFUR_WITH_VIEW
#include "view_command.h"
#endif

#include <vtkLogger.h>
#include <vtkObject.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

namespace {

constexpr const char* kUsage =
    "usage: wirefur <command> [options]\n"
    "  gallery  [-o DIR] [--scenes DIR] [--size N] [--quiet]\n"
    "                                               every scene of data/scenes (and the shading tables) into DIR\n"
    "                                               (default out/gallery) with index.html; --size N: longer side at most N\n"
    "  accuracy [--json FILE] [--plots DIR] [--quick] [--quiet]\n"
    "                                               error against run time of every shading approximation\n"
    "  render   [INPUT] -o OUT.png [--size WxH] [--style STYLE] [--mask 4x4|8x4|8x8] [--threads N]\n"
    "           [--stats FILE] [--budget K] [--shading closed|maps|exact] [--reference [--samples N]]\n"
    "           [--time T] [--simplify WIDTH|off] [--wire-depth round|flat]\n"
    "           [--view-grid N] [--measure-error] [--memory-budget BYTES|NNM|NNG] [--quiet] [CAD options]\n"
    "                                               INPUT: scene .json, CAD .step .stp .iges .igs .brep .FCStd,\n"
    "                                               or mesh .vtp .vtk .stl .obj .ply; none: built-in scene\n"
    "           --memory-budget: refuse (exit 2) a render estimated to need more (default: half the RAM; 0: no limit)\n"
    "           STYLE for CAD: wire, wire-over-surface (default), burnished, fur; for meshes: wire, wire-over-surface\n"
    "           CAD options: --deflection D (of the model's size, default 0.001) | --linear-deflection L (world)\n"
    "                        --angular-deflection DEG (default 20) --isos N (u and v iso lines per face)\n"
    "                        --cad-timeout S (read and mesh in a worker process limited to S s, default 600)\n"
    "  export   INPUT -o OUT.vtp|.vtk|.obj|.ply [--style STYLE] [--time T] [--quiet] [CAD options]\n"
    "                                               the scene's geometry as drawn (tessellations, scales, wires,\n"
    "                                               fur) with normals, tangents, (u, v) and colours\n"
    "  view     [INPUT] [--style STYLE] [--size WxH] [--mask 4x4|8x4|8x8] [--threads N] [CAD options]\n"
    "           [--frames N [--offscreen] [--png F]] interactive VTK window (keys: w f s m a q); --frames N renders\n"
    "                                               N frames turning the camera and prints the median frame time\n"
    "  --help, --version\n";

std::string need(const std::vector<std::string>& a, size_t& i) {
  if (i + 1 >= a.size()) throw wfapp::UsageError("option " + a[i] + " needs a value");
  return a[++i];
}

int run(const std::vector<std::string>& a) {
  if (a.empty()) throw wfapp::UsageError("no command (try wirefur --help)");
  if (a[0] == "--help" || a[0] == "-h" || a[0] == "help") {
    std::cout << kUsage;
    return 0;
  }
  if (a[0] == "--version") {
    std::cout << "wirefur 0.1.0\n";
    return 0;
  }
  const std::string cmd = a[0];
  if (cmd == "gallery") {
    wfapp::GalleryOptions o;
    for (size_t i = 1; i < a.size(); ++i) {
      if (a[i] == "-o" || a[i] == "--out") o.outDir = need(a, i);
      else if (a[i] == "--size") o.size = wfapp::parsePositiveInt("--size", need(a, i));
      else if (a[i] == "--scenes") o.scenesDir = need(a, i);
      else if (a[i] == "--quiet") o.quiet = true;
      else throw wfapp::UsageError("gallery: unknown option '" + a[i] + "'");
    }
    if (o.size != 0 && (o.size < 16 || o.size > wf::kMaxImageSide))
      throw wfapp::UsageError("option --size: expected 16 ... " + std::to_string(wf::kMaxImageSide));
    return wfapp::runGallery(o);
  }
  if (cmd == "accuracy") {
    wfapp::AccuracyOptions o;
    for (size_t i = 1; i < a.size(); ++i) {
      if (a[i] == "--json") o.jsonPath = need(a, i);
      else if (a[i] == "--plots") o.plotsDir = need(a, i);
      else if (a[i] == "--quick") o.quick = true;
      else if (a[i] == "--quiet") o.quiet = true;
      else throw wfapp::UsageError("accuracy: unknown option '" + a[i] + "'");
    }
    return wfapp::runAccuracy(o);
  }
  if (cmd == "render") {
    wfapp::RenderCommandOptions o;
    for (size_t i = 1; i < a.size(); ++i) {
      if (a[i] == "-o" || a[i] == "--out") o.output = need(a, i);
      else if (a[i] == "--size") {
        const std::string v = need(a, i);
        const size_t x = v.find('x');
        if (x == std::string::npos) throw wfapp::UsageError("option --size: expected WxH, got '" + v + "'");
        o.width = wfapp::parsePositiveInt("--size", v.substr(0, x));
        o.height = wfapp::parsePositiveInt("--size", v.substr(x + 1));
        if (o.width > wf::kMaxImageSide || o.height > wf::kMaxImageSide)
          throw wfapp::UsageError("option --size: at most " + std::to_string(wf::kMaxImageSide) + "x" + std::to_string(wf::kMaxImageSide));
      } else if (a[i] == "--style") {
        o.style = need(a, i);
        if (o.style != "wire" && o.style != "wire-over-surface" && o.style != "burnished" && o.style != "fur" && o.style != "scales")
          throw wfapp::UsageError("option --style: expected wire, wire-over-surface, burnished, fur or scales");
      } else if (a[i] == "--mask") o.mask = need(a, i);
      else if (a[i] == "--threads") o.threads = wfapp::parsePositiveInt("--threads", need(a, i));
      else if (a[i] == "--stats") o.statsPath = need(a, i);
      else if (a[i] == "--budget") o.budget = wfapp::parsePositiveInt("--budget", need(a, i));
      else if (a[i] == "--memory-budget") o.memoryBudget = wfapp::parseByteSize("--memory-budget", need(a, i));
      else if (a[i] == "--shading") {
        const std::string v = need(a, i);
        if (v != "closed" && v != "maps" && v != "exact")
          throw wfapp::UsageError("option --shading: expected closed, maps or exact");
        o.shading = v;
      } else if (a[i] == "--reference") o.reference = true;
      else if (a[i] == "--measure-error") o.measureError = true;
      else if (a[i] == "--samples") o.samples = wfapp::parsePositiveInt("--samples", need(a, i));
      else if (a[i] == "--view-grid") {
        o.viewGrid = wfapp::parsePositiveInt("--view-grid", need(a, i));
        if (o.viewGrid > wf::kMaxViewGrid) throw wfapp::UsageError("option --view-grid: expected 1 ... " + std::to_string(wf::kMaxViewGrid));
      }
      else if (a[i] == "--simplify") {
        const std::string v = need(a, i);
        if (v != "off") {
          char* end = nullptr;
          const double w = std::strtod(v.c_str(), &end);
          if (v.empty() || *end != '\0' || !(w >= 0.1 && w <= 64))
            throw wfapp::UsageError("option --simplify: expected off or a width in pixels, 0.1 ... 64, got '" + v + "'");
          o.simplify = w;
        }
      } else if (a[i] == "--wire-depth") {
        o.wireDepth = need(a, i);
        if (o.wireDepth != "round" && o.wireDepth != "flat") throw wfapp::UsageError("option --wire-depth: expected round or flat");
      }
      else if (a[i] == "--time") {
        const std::string v = need(a, i);
        char* end = nullptr;
        const double t = std::strtod(v.c_str(), &end);
        if (v.empty() || *end != '\0' || !std::isfinite(t) || std::abs(t) > wf::kMaxWindTime)
          throw wfapp::UsageError("option --time: expected a number in [-1e9, 1e9], got '" + v + "'");
        o.time = t;
      }
      else if (a[i] == "--quiet") o.quiet = true;
      else if (wfapp::parseCadOption(a, i, o.cad)) {
      } else if (!a[i].empty() && a[i][0] == '-') throw wfapp::UsageError("render: unknown option '" + a[i] + "'");
      else if (o.input.empty()) o.input = a[i];
      else throw wfapp::UsageError("render: more than one input ('" + o.input + "' and '" + a[i] + "')");
    }
    return wfapp::runRender(o);
  }
  if (cmd == "cad-worker") return wfapp::runCadWorker(std::vector<std::string>(a.begin() + 1, a.end()));
  if (cmd == "export") return wfapp::runExport(std::vector<std::string>(a.begin() + 1, a.end()));
  if (cmd == "view") {
#ifdef WIREFUR_WITH_VIEW
    return wfapp::runView(std::vector<std::string>(a.begin() + 1, a.end()));
#else
    std::cerr << "wirefur: 'view' needs the VTK module (configure with WIREFUR_BUILD_VTK_MODULE=ON)\n";
    return 1;
#endif
  }
  throw wfapp::UsageError("unknown command '" + cmd + "' (try wirefur --help)");
}

}  // namespace

int main(int argc, char** argv) {
  // VTK's logger would print reader warnings as extra lines on stderr; WireFur reports every
  // problem itself, in one line (docs/cli.md).
  vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  try {
    return run(std::vector<std::string>(argv + 1, argv + argc));
  } catch (const wfapp::UsageError& e) {
    std::cerr << "wirefur: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "wirefur: internal error: " << e.what() << "\n";
    return 1;
  }
}
