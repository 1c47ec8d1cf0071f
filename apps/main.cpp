// wirefur: the command-line face of WireFur (see docs/cli.md for the contract).
#include "accuracy.h"
#include "cad_input.h"
#include "cli.h"
#include "cli_options.h"
#include "gallery.h"
#include "mesh_io.h"
#include "reader_worker.h"
#include "export_command.h"
#include "render_command.h"
#ifdef WIREFUR_WITH_VIEW
#include "view_command.h"
#endif

#include "core/cleanup_on_signal.h"

#include <vtkLogger.h>
#include <vtkObject.h>

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

namespace {

const std::vector<std::string> kStyles = {"wire", "wire-over-surface", "burnished", "fur", "scales"};
const char* const kStyleHelp =
    "how a mesh, polyline or CAD file is drawn: wire, wire-over-surface (default), burnished, fur or scales "
    "(a file of polylines only: wire or wire-over-surface; docs/scenes.md, Styles)";
const char* const kInputHelp =
    "scene .json, CAD .step .stp .iges .igs .brep .FCStd, or mesh .vtp .vtk .stl .obj .ply";

void declareGallery(CLI::App& wirefur, wfapp::GalleryOptions& o) {
  CLI::App* c = wfapp::addCommand(wirefur, "gallery",
                                  "every scene of data/scenes (and the shading tables) as PNG files with index.html");
  wfapp::addOutputOption(*c, o.outDir, "DIR", "output folder (default out/gallery)");
  c->add_option("--scenes", o.scenesDir, "the scene files to render (default: share/wirefur/scenes of the install, or data/scenes of the source tree)")
      ->type_name("DIR")
      ->trigger_on_parse();
  wfapp::addIntegerOption(*c, "--size", o.size, 16, wf::kMaxImageSide,
                          "scale every scene down so that its longer side is at most N pixels, {range}");
  wfapp::addQuietOption(*c, o.quiet);
}

void declareAccuracy(CLI::App& wirefur, wfapp::AccuracyOptions& o) {
  CLI::App* c = wfapp::addCommand(wirefur, "accuracy", "error against run time of every shading approximation");
  c->add_option("--json", o.jsonPath, "write the study as JSON")->type_name("FILE")->trigger_on_parse();
  c->add_option("--plots", o.plotsDir, "write the PNG plots (gnuplot) into DIR")->type_name("DIR")->trigger_on_parse();
  wfapp::addFlag(*c, "--quick", o.quick, "smaller sets (for tests; about 9 s)");
  wfapp::addQuietOption(*c, o.quiet);
}

void declareRender(CLI::App& wirefur, wfapp::RenderCommandOptions& o) {
  CLI::App* c = wfapp::addCommand(wirefur, "render", "draw INPUT with the A-buffer into an 8-bit sRGB PNG");
  wfapp::addInputArgument(*c, o.input, std::string(kInputHelp) + "; none: the built-in scene");
  wfapp::addOutputOption(*c, o.output, "OUT.png", "the PNG to write (required)");
  wfapp::addSizeOption(*c, o.width, o.height, "default: the scene's");
  wfapp::addStyleOption(*c, o.style, kStyles, kStyleHelp);
  wfapp::addMaskOption(*c, o.mask);
  wfapp::addThreadsOption(*c, o.threads);
  c->add_option("--stats", o.statsPath, "write the render's statistics and error estimate as JSON")
      ->type_name("FILE")
      ->trigger_on_parse();
  wfapp::addIntegerOption(*c, "--budget", o.budget, 1, wf::kMaxListBudget,
                          "fragments kept exactly per pixel, {range} (default: the scene's, else 64)", "K");
  wfapp::addFlag(*c, "--deep-shares,!--no-deep-shares", o.deepShares,
                 "in pixels over a surface, weigh what is hidden by the samples it owns (dense fur over a body: less error; "
                 "the default); --no-deep-shares: every fragment its area times the share of its samples it owns");
  c->add_option("--shading", o.shading,
                "closed (default): closed-form cylinder integral; exact: the same computed exactly; maps: "
                "the paper's pseudo-reflectance maps")
      ->check(wfapp::oneOf({"closed", "maps", "exact"}))
      ->type_name("closed|maps|exact")
      ->trigger_on_parse();
  wfapp::addFlag(*c, "--reference", o.reference, "render the brute-force reference instead (exact shading)");
  wfapp::addIntegerOption(*c, "--samples", o.samples, 1, wf::kMaxReferenceSamples,
                          "the reference's N x N samples per pixel, {range} (default 16)");
  wfapp::addFlag(*c, "--measure-error", o.measureError, "render the reference too and put the measured difference in the stats");
  wfapp::addIntegerOption(*c, "--view-grid", o.viewGrid, 1, wf::kMaxViewGrid,
                          "with --shading maps: tables for N x N view directions, {range} (default: the scene's, else 1)");
  c->add_option_function<std::string>(
       "--memory-budget", [&o](const std::string& v) { o.memoryBudget = wfapp::parseByteSize("--memory-budget", v); },
       "refuse (exit 2) a render estimated to need more (default: half the RAM; 0: no limit)")
      ->check(wfapp::checkedBy(wfapp::byteSizeProblem))
      ->type_name("BYTES|NNM|NNG")
      ->trigger_on_parse();
  c->add_option_function<std::string>(
       "--simplify",
       [&o](const std::string& v) {
         if (v == "off") o.simplify.reset();
         else o.simplify = std::strtod(v.c_str(), nullptr);
       },
       "draw dense fur by stochastic simplification to hairs of WIDTH pixels, 0.1 ... 64 (default off)")
      ->check(wfapp::checkedBy([](const std::string& v) -> std::string {
        if (v == "off" || wfapp::numberProblem(v, 0.1, 64).empty()) return {};
        return "expected off or a width in pixels, 0.1 ... 64, got '" + v + "'";
      }))
      ->type_name("WIDTH|off")
      ->trigger_on_parse();
  c->add_option("--wire-depth", o.wireDepth, "round (default): the depth of the round cylinder; flat: the paper's flat polygon")
      ->check(wfapp::oneOf({"round", "flat"}))
      ->type_name("round|flat")
      ->trigger_on_parse();
  wfapp::addHiddenOption(*c, o.hidden);
  wfapp::addSilhouettesOption(*c, o.silhouettes);
  wfapp::addEdgeOptions(*c, o.edges);
  wfapp::addBurnishOptions(*c, o.burnish);
  wfapp::addTimeOption(*c, o.time);
  wfapp::addQuietOption(*c, o.quiet);
  wfapp::addCadOptions(*c, o.cad);
}

void declareExport(CLI::App& wirefur, wfapp::ExportOptions& o) {
  CLI::App* c = wfapp::addCommand(wirefur, "export",
                                  "the geometry INPUT draws (tessellations, scales, wires, fur) with normals, tangents, "
                                  "(u, v) and colours, through VTK's writers");
  wfapp::addInputArgument(*c, o.input, std::string(kInputHelp) + " (required)");
  wfapp::addOutputOption(*c, o.output, "OUT.vtp|.vtk|.obj|.ply", "the file to write (required)");
  wfapp::addStyleOption(*c, o.style, kStyles, kStyleHelp);
  wfapp::addTimeOption(*c, o.overrides.time);
  wfapp::addSilhouettesOption(*c, o.overrides.silhouettes);
  wfapp::addEdgeOptions(*c, o.overrides.edges);
  wfapp::addBurnishOptions(*c, o.overrides.burnish);
  wfapp::addFlag(*c, "--visibility", o.visibility,
                 "split every wire-frame where the opaque surfaces start and stop hiding it from the camera; cell array "
                 "Visible (1 seen, 0 hidden)");
  wfapp::addSizeOption(*c, o.width, o.height, "the image the camera is framed for (default: the scene's)");
  wfapp::addQuietOption(*c, o.quiet);
  wfapp::addCadOptions(*c, o.overrides.cad);
}

#ifdef WIREFUR_WITH_VIEW
void declareView(CLI::App& wirefur, wfapp::ViewOptions& o) {
  CLI::App* c = wfapp::addCommand(wirefur, "view",
                                  "an interactive VTK window over INPUT, drawn as render draws it (keys: w f s m q); --frames N: a benchmark");
  wfapp::addInputArgument(*c, o.input, std::string(kInputHelp) + "; none: the built-in scene");
  wfapp::addStyleOption(*c, o.style, kStyles, kStyleHelp);
  wfapp::addSizeOption(*c, o.width, o.height, "default 800x600");
  wfapp::addMaskOption(*c, o.mask);
  wfapp::addThreadsOption(*c, o.threads);
  wfapp::addIntegerOption(*c, "--frames", o.frames, 1, 100000,
                          "render N frames turning the camera, still and moving (at the interactive reduction), and print the median frame times, {range}");
  wfapp::addIntegerOption(*c, "--interactive-reduction", o.interactiveReduction, 1, 8,
                          "while the camera moves, render at 1/F of the size and scale up; the still frame is "
                          "full size (1: off; default 2), {range}");
  wfapp::addFlag(*c, "--offscreen", o.offscreen, "with --frames: no window shown (still needs an X display)");
  c->add_option("--png", o.png, "with --frames: write the last frame as a PNG")->type_name("F")->trigger_on_parse();
  wfapp::addHiddenOption(*c, o.hidden);
  wfapp::addSilhouettesOption(*c, o.silhouettes);
  wfapp::addEdgeOptions(*c, o.edges);
  wfapp::addBurnishOptions(*c, o.burnish);
  wfapp::addQuietOption(*c, o.quiet);
  wfapp::addCadOptions(*c, o.cad);
}
#endif

int run(const std::vector<std::string>& a) {
  if (a.empty()) throw wfapp::UsageError("no command (try wirefur --help)");
  // The CAD worker process (apps/cad_input.cpp): internal, not in the contract, its own arguments.
  if (a[0] == "cad-worker") return wfapp::runCadWorker(std::vector<std::string>(a.begin() + 1, a.end()));
  if (a[0] == "mesh-worker") return wfapp::runMeshWorker(std::vector<std::string>(a.begin() + 1, a.end()));
  // A stopped command leaves no temporary output, reader folder or worker behind (apps/safe_files.h),
  // and reads untrusted files in workers that are copies of itself (apps/reader_worker.h).
  wf::installCleanupOnSignals();
  wfapp::enableReaderWorkers();

  CLI::App wirefur("WireFur: shaded wires, fur and hair drawn with an A-buffer.", "wirefur");
  wirefur.set_version_flag("--version", "wirefur 0.1.0");
  wirefur.require_subcommand(0, 1);  // one command; a word after it is its INPUT, never a second command
  wirefur.allow_extras();            // an unknown command or option: reported by parseCommandLine
  wirefur.get_formatter()->column_width(34);
  wirefur.get_formatter()->label("SUBCOMMAND", "COMMAND");
  wfapp::GalleryOptions gallery;
  wfapp::AccuracyOptions accuracy;
  wfapp::RenderCommandOptions render;
  wfapp::ExportOptions exportOptions;
  declareGallery(wirefur, gallery);
  declareAccuracy(wirefur, accuracy);
  declareRender(wirefur, render);
  declareExport(wirefur, exportOptions);
#ifdef WIREFUR_WITH_VIEW
  wfapp::ViewOptions view;
  declareView(wirefur, view);
#else
  wfapp::addCommand(wirefur, "view", "an interactive VTK window (not in this build: needs the VTK module)");
#endif
  wirefur.footer("wirefur COMMAND --help: the command's options. The contract: docs/cli.md.");

  if (a[0] == "help") {
    std::cout << wirefur.help();
    return 0;
  }
  if (!wfapp::parseCommandLine(wirefur, a)) return 0;  // --help or --version answered
  const std::string command = wfapp::chosenCommand(wirefur)->get_name();
  if (command == "gallery") return wfapp::runGallery(gallery);
  if (command == "accuracy") return wfapp::runAccuracy(accuracy);
  if (command == "render") return wfapp::runRender(render);
  if (command == "export") return wfapp::runExport(exportOptions);
#ifdef WIREFUR_WITH_VIEW
  return wfapp::runView(view);
#else
  std::cerr << "wirefur: 'view' needs the VTK module (configure with WIREFUR_BUILD_VTK_MODULE=ON)\n";
  return 1;
#endif
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
  } catch (const wfapp::OutputError& e) {
    std::cerr << "wirefur: " << e.what() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "wirefur: internal error: " << wfapp::oneLine(e.what()) << "\n";
    return 1;
  }
}
