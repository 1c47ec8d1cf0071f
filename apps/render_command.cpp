#include "render_command.h"

#include "texture/grooves.h"

#include "cad_input.h"
#include "cli.h"
#include "safe_files.h"
#include "image_io.h"
#include "mesh_io.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace wfapp {

using json = nlohmann::ordered_json;

long currentRssBytes() {
  long pages = 0, resident = 0;
  if (FILE* f = std::fopen("/proc/self/statm", "r")) {
    if (std::fscanf(f, "%ld %ld", &pages, &resident) != 2) resident = 0;
    std::fclose(f);
  }
  return resident * sysconf(_SC_PAGESIZE);
}

long peakRssBytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return long(u.ru_maxrss) * 1024;
}

SceneFile loadInput(const std::string& input, const std::string& style, const SceneOverrides& overrides) {
  if (input.empty()) {
    if (!style.empty()) throw UsageError("--style applies to a mesh or CAD input, not to the built-in scene");
    return defaultScene(overrides);
  }
  requireInputFile(input);  // a FIFO or a device is refused at once, before its type is guessed
  if (isCadFile(input)) return sceneForCadFile(input, style.empty() ? "wire-over-surface" : style, overrides);
  if (isGeometryFile(input)) return sceneForGeometryFile(input, style.empty() ? "wire-over-surface" : style, overrides);
  std::string e = std::filesystem::path(input).extension().string();
  if (e == ".json") {
    if (!style.empty()) throw UsageError("--style applies to mesh and CAD files, not to scene files");
    return loadSceneFile(input, overrides);
  }
  throw UsageError(input + ": unknown input type (expected a scene .json, a CAD file .step .stp .iges .igs .brep .FCStd, or a mesh .vtp .vtk .stl .obj .ply)");
}

wf::RenderOptions renderOptionsFor(const SceneFile& sf) {
  wf::RenderOptions o;
  o.width = sf.width;
  o.height = sf.height;
  o.mask = sf.mask;
  o.budget = sf.budget;
  o.viewGrid = sf.viewGrid;
  return o;
}

wf::ShadingPath shadingPathNamed(const std::string& name) {
  return name == "maps" ? wf::ShadingPath::Maps : name == "exact" ? wf::ShadingPath::Exact : wf::ShadingPath::Closed;
}

const char* shadingPathName(wf::ShadingPath path) {
  switch (path) {
    case wf::ShadingPath::Maps: return "maps";
    case wf::ShadingPath::Exact: return "exact";
    case wf::ShadingPath::Closed: break;
  }
  return "closed";
}

json statsJson(const wf::RenderStats& st, const wf::RenderOptions& o, bool reference) {
  json j;
  j["renderer"] = reference ? "reference" : "abuffer";
  j["seconds"] = {{"total", st.total},     {"setup", st.setup},   {"maps", st.maps},
                  {"binning", st.binning}, {"raster_resolve", st.raster}};
  j["segments"] = st.segments;
  j["triangles"] = st.triangles;
  j["fragments"] = st.abuffer.fragments;
  j["hidden_line_fragments"] = st.abuffer.xray;  // x-ray copies of wires drawn dashed or ghosted
  j["max_fragments_per_pixel"] = st.abuffer.maxFragmentsPerPixel;
  j["peak_bytes"] = st.peakBytes;
  j["bin_bands"] = st.binBands;  // tile-row bands binned one after another (their items not all held at once)
  json e;
  e["coverage_quantisation"] = st.coverageQuantisation;
  e["map_max"] = st.mapError;
  e["sphere_max"] = st.sphereError;
  e["orthographic_max"] = st.orthographicError;
  e["lobe_max"] = st.lobeError;
  e["budget_tail_share"] = st.budgetTailShare;
  e["occlusion_epsilon"] = st.occlusionEpsilon;
  e["shading_bound"] = st.mapError + st.sphereError + st.orthographicError + st.lobeError;
  if (o.simplify.enabled)
    e["simplification"] = {{"hairs", st.simplifiedHairs},
                           {"drawn", st.simplifiedKept},
                           {"smallest_fraction", st.simplifiedLambda},
                           {"target_width_pixels", o.simplify.targetWidth},
                           {"note", "statistical: no per-pixel bound; --measure-error measures it against the full render "
                                    "(simplification off), wirefur accuracy its RMS against time"}};
  e["notes"] =
      "coverage: exact area per fragment; masks (1/N per subpixel) decide hiding where fragments "
      "overlap. occlusion_epsilon: bound per pixel of what occlusion culling leaves out. map_max / "
      "sphere_max: max |table - exact| over 192 test directions at a node of the view grid; "
      "orthographic_max: the same with the view-direction approximation where it is worst (the "
      "image corner for one orthographic table, the corner cell's centre for a grid of them). "
      "lobe_max: closed path (the default), where shading is exact at each fragment's own view "
      "vector but for the tabulated factor of the cylinder integral: its measured error times the "
      "specular colour and the lights' sum (for unit wire and vertex colours; the image is float, "
      "so closed and exact can also differ by its rounding, ~6e-8). Radiance units.";
  j["error_estimate"] = e;
  j["options"] = {{"size", {o.width, o.height}},
                  {"wire_depth", o.wireDepth == wf::WireDepth::Round ? "round" : "flat"},
                  {"simplify", o.simplify.enabled ? json(o.simplify.targetWidth) : json("off")},
                  {"mask", o.mask.name()},
                  {"budget", o.budget},
                  {"deep_shares", o.deepShares},
                  {"occlusion_epsilon", o.occlusionEpsilon},
                  {"shading", shadingPathName(o.shading)},
                  {"threads", o.threads},
                  {"tile_size", o.tileSize},
                  {"map_resolution", o.map.resolution},
                  {"map_samples", o.map.samples},
                  {"view_grid", st.viewGrid}};
  if (reference) j["options"]["reference_samples"] = o.referenceSamples * o.referenceSamples;
  j["left_out"] = {{"pseudo_reflectance_maps_built", st.pseudoReflectanceMaps},
                   {"reflectance_spheres_built", st.reflectanceSpheres},
                   {"lobe_tables_built", st.lobeTables},
                   {"tiles", st.tiles},
                   {"tiles_empty", st.tilesEmpty},
                   {"covered_pixels", st.abuffer.coveredPixels},
                   {"pixels_with_list", st.abuffer.pixelsWithList},
                   {"pixels_deep", st.abuffer.pixelsDeep},
                   {"pixels_solid_without_list", st.abuffer.pixelsSolidOnly},
                   {"fragments_culled", st.abuffer.culled},
                   {"fragments_merged", st.abuffer.merged},
                   {"primitives_occluded_per_tile", st.primitivesOccluded},
                   {"raster_work", {{"items", st.work.items}, {"rows", st.work.rows}, {"rows_culled", st.work.rowsCulled},
                                    {"pixels", st.work.pixels}, {"pixels_culled", st.work.pixelsCulled},
                                    {"masks_hidden", st.work.masksHidden}, {"emitted", st.work.emitted}}}};
  j["budget"] = {{"k", o.budget},
                 {"pixels_over_budget", st.abuffer.pixelsOverBudget},
                 {"tail_fragments", st.abuffer.tail},
                 {"max_list_length", st.abuffer.maxListLength}};
  j["input"] = {{"primitives", st.primitives},
                {"rejected_non_finite", st.rejectedNonFinite},
                {"dropped_zero_length", st.droppedZeroLength},
                {"clipped_away", st.clippedAway},
                {"end_on_discs", st.endOnDiscs}};
  j["warnings"] = st.warnings;
  return j;
}

ImageError imageError(const wf::ImageRGBA& a, const wf::ImageRGBA& ref) {
  ImageError e;
  if (a.pixels.size() != ref.pixels.size() || a.pixels.empty()) return e;
  double sq = 0, sqA = 0;
  for (size_t i = 0; i < a.pixels.size(); ++i) {
    for (int c = 0; c < 4; ++c) {
      const double d = double(a.pixels[i][c]) - double(ref.pixels[i][c]);
      sq += d * d;
      e.max = std::max(e.max, std::abs(d));
      if (c == 3) sqA += d * d, e.coverageMax = std::max(e.coverageMax, std::abs(d));
    }
  }
  e.rms = std::sqrt(sq / (4.0 * double(a.pixels.size())));
  e.coverageRms = std::sqrt(sqA / double(a.pixels.size()));
  return e;
}

int runRender(const RenderCommandOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  if (o.output.empty()) throw UsageError("render: -o OUT.png is required");
  if (o.reference && o.measureError) throw UsageError("render: --measure-error compares against --reference; give one of them");
  if (!o.style.empty() && o.input.empty()) throw UsageError("render: --style applies to a mesh or CAD input");
  {
    std::string e = std::filesystem::path(o.output).extension().string();
    for (char& c : e) c = char(std::tolower(static_cast<unsigned char>(c)));
    if (e != ".png") throw UsageError(o.output + ": the output must be a .png file");
  }
  // The outputs, before anything is read or rendered: their folders exist and can be written
  // (a probe file made and removed), and neither is a folder, a device, a FIFO or a socket
  // (apps/safe_files.h). Each is written at the end under a unique temporary beside it and renamed.
  requireOutputPath(o.output);
  if (!o.statsPath.empty()) requireOutputPath(o.statsPath);
  if (!o.statsPath.empty() &&
      std::filesystem::weakly_canonical(o.statsPath) == std::filesystem::weakly_canonical(o.output))
    throw UsageError(o.statsPath + ": --stats and -o name the same file");
  OutputFile::probe(o.output);
  if (!o.statsPath.empty()) OutputFile::probe(o.statsPath);
  const Progress progress(o.quiet);
  SceneOverrides overrides;
  overrides.time = o.time;
  overrides.cad = o.cad;
  overrides.hidden = o.hidden;
  overrides.silhouettes = o.silhouettes;
  overrides.edges = o.edges;
  overrides.burnish = o.burnish;
  overrides.cad.threads = o.threads;
  overrides.cad.showProgress = progress.enabled();
  SceneFile sf = loadInput(o.input, o.style, overrides);
  const double readSeconds = secondsSince(t0);
  wf::RenderOptions ro = renderOptionsFor(sf);
  if (o.width > 0) {
    ro.width = o.width, ro.height = o.height;
    reframe(sf, ro.width, ro.height);  // an automatically framed camera fits the new aspect
  }
  if (!o.mask.empty() && !wf::MaskLayout::parse(o.mask, ro.mask))
    throw UsageError("option --mask: expected 4x4, 8x4 or 8x8, got '" + o.mask + "'");
  if (o.budget > 0) ro.budget = o.budget;
  ro.deepShares = o.deepShares;
  ro.threads = o.threads;
  ro.shading = o.reference ? wf::ShadingPath::Exact : shadingPathNamed(o.shading);
  ro.referenceSamples = o.samples;
  if (o.viewGrid > 0) ro.viewGrid = o.viewGrid;
  if (ro.viewGrid > 1 && ro.shading != wf::ShadingPath::Maps)
    std::cerr << "wirefur: warning: the view grid (" << ro.viewGrid << ") belongs to --shading maps; "
              << (o.reference ? std::string("the reference") : std::string("the ") + shadingPathName(ro.shading) + " path")
              << " shades at every fragment's own view vector\n";
  if (o.simplify) {
    ro.simplify.enabled = true;
    ro.simplify.targetWidth = *o.simplify;
  }
  if (o.wireDepth == "flat") ro.wireDepth = wf::WireDepth::Flat;
  if (o.memoryBudget) ro.memoryBudget = *o.memoryBudget;
  if (const std::string p = ro.problem(); !p.empty()) throw UsageError("render: " + p);
  // --measure-error's other renders: the brute-force reference (exact shading, every hair: the
  // truth, so that with --simplify the whole error is measured) and, with --simplify, the
  // A-buffer's render of every hair (the simplification's own share).
  wf::RenderOptions referenceOptions = ro, fullOptions = ro;
  referenceOptions.shading = wf::ShadingPath::Exact;
  referenceOptions.simplify.enabled = fullOptions.simplify.enabled = false;
  // The memory the whole command will hold at its peak, refused before anything large is
  // allocated: what it holds now (the program, its libraries and the scene it read), then the
  // largest of what it holds during each render it makes in turn: the images of the renders
  // before it and its own working memory (renderer.h, estimateRenderBytes: image, tile buffers,
  // primitives, bins, tables). A render's large blocks are given back once it is done
  // (releaseRenderMemory), so that they are not held beside the next one's; the PNG's 8-bit copy
  // is made once the renders are done. With --measure-error the renders are the command's own,
  // the brute-force reference, the second render over a transparent background and, with
  // --simplify, the render of every hair. Each render is given the budget less what the command
  // holds beside it, so that its bands of tile items (binBands) fit what is left. An upper bound
  // on the peak resident memory (tests/apps: MemoryEstimateBoundsThePeak and ...DenseFursPeak).
  const double image = double(ro.width) * double(ro.height) * double(sizeof(glm::vec4));
  // (Loading freed its own large blocks, a texture's decoded PNG: given back first, not counted
  // as held beside a render that would take them again.)
  wf::releaseRenderMemory();
  // (Plus what no count here sees: libpng's and zlib's buffers, the threads' stacks, the
  // allocator's slack: 32 MiB and 3 % of the rest.)
  const double held = double(currentRssBytes()) + 32.0 * double(1 << 20);
  auto budgetBeside = [&](double images) -> size_t {
    if (ro.memoryBudget == 0) return 0;  // (no limit)
    const double left = (double(ro.memoryBudget) - held) / 1.03 - images * image;
    return left >= 1.0 ? size_t(left) : 1;
  };
  const bool second = o.measureError && !o.reference && sf.scene.background.w > 0.0f;
  wf::RenderOptions mainOptions = ro, secondOptions = ro;
  mainOptions.memoryBudget = budgetBeside(0);
  referenceOptions.memoryBudget = budgetBeside(1);
  secondOptions.memoryBudget = budgetBeside(2);
  fullOptions.memoryBudget = budgetBeside(second ? 3 : 2);
  const double memoryEstimate = [&] {
    double images = 0.0, most = 0.0;  // the images kept so far; the most held beside them at once
    auto renderHolds = [&](double bytes) {
      most = std::max(most, images + bytes);
      images += image;
    };
    renderHolds(double(wf::estimateRenderBytes(sf.scene, mainOptions, o.reference)));
    if (o.measureError && !o.reference) {
      renderHolds(double(wf::estimateRenderBytes(sf.scene, referenceOptions, true)));
      if (second) renderHolds(double(wf::estimateRenderBytes(sf.scene, secondOptions, false)));
      if (ro.simplify.enabled) renderHolds(double(wf::estimateRenderBytes(sf.scene, fullOptions, false)));
    }
    most = std::max(most, images + double(ro.width) * double(ro.height) * 3.0);
    return held + 1.03 * most;
  }();
  const long peakBeforeRender = peakRssBytes();
  if (ro.memoryBudget > 0 && memoryEstimate > double(ro.memoryBudget)) {
    char need[64], budget[64];
    std::snprintf(need, sizeof need, "%.3g GiB", memoryEstimate / double(1 << 30));
    std::snprintf(budget, sizeof budget, "%.3g GiB", double(ro.memoryBudget) / double(1 << 30));
    throw UsageError("render: " + (o.input.empty() ? std::string("built-in scene") : o.input) + ": image of " +
                     std::to_string(ro.width) + "x" + std::to_string(ro.height) + " needs about " + need +
                     (o.measureError ? " with the renders of --measure-error" : "") + ", over the memory budget of " +
                     budget + " (--memory-budget; half the machine's memory by default)");
  }
  progress.say("rendering " + (o.input.empty() ? std::string("the built-in scene") : o.input) + " at " +
               std::to_string(ro.width) + "x" + std::to_string(ro.height) + (o.reference ? " (reference)" : ""));
  // A render the library finds over its share of the budget once it has counted the tile items
  // (one tile row holding more than the room left) is refused as the estimate's are: one line,
  // exit 2.
  auto withinBudget = [&](auto&& draw) {
    try {
      return draw();
    } catch (const std::length_error& e) {
      throw UsageError("render: " + (o.input.empty() ? std::string("built-in scene") : o.input) + ": " + e.what());
    }
  };
  const wf::RenderResult r = withinBudget(
      [&] { return o.reference ? wf::renderReference(sf.scene, mainOptions) : wf::render(sf.scene, mainOptions); });
  wf::releaseRenderMemory();  // (the estimate counts no render's blocks beside the next one's)
  const std::string inputName = o.input.empty() ? std::string("built-in scene") : o.input;
  for (const std::string& w : r.stats.warnings) warn(inputName + ": " + w);
  // An image of the background alone says why. Nothing could be drawn (no finite geometry, no
  // primitive accepted, or, with a camera framed on the input, all its points in one place or
  // spread past the camera's depth range, 1e15; a mesh file's 1e308 reads as 3.4e38): bad
  // input, exit 2 and no PNG. Otherwise the view missed what is there (a scene's camera looking
  // away, an edge selection that drew nothing inside it): a warning, the background is written.
  // (The reference path keeps no A-buffer counters: there, no primitive left after clipping.)
  if (o.reference ? r.stats.primitives == 0 : r.stats.abuffer.coveredPixels == 0) {
    const wf::RenderStats& st = r.stats;
    glm::dvec3 lo, hi;
    const bool finite = sf.scene.bounds(lo, hi);
    const double extent = finite ? std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}) : 0.0;
    std::string why;
    if (!finite) why = "no finite point";
    else if (st.triangles + st.segments == 0) why = "no triangle or segment is left once the degenerate are dropped";
    else if (sf.framed && extent == 0.0) why = "all its points are in one place";
    else if (sf.framed && !(extent <= 1e15)) why = "its points span more than 1e15, beyond the camera's depth range";
    const std::string counts = std::to_string(st.triangles) + " triangles and " + std::to_string(st.segments) +
                               " segments accepted, " + std::to_string(st.rejectedNonFinite) + " rejected as not finite, " +
                               std::to_string(st.droppedZeroLength) + " of zero length, " + std::to_string(st.clippedAway) +
                               " outside the view";
    if (!why.empty()) throw UsageError(inputName + ": nothing could be drawn: " + why + " (" + counts + ")");
    warn(inputName + ": nothing was drawn (" + counts + "): the image is the background alone");
  }
  json stats = statsJson(r.stats, ro, o.reference);
  if (o.measureError && !o.reference) {
    progress.say("rendering the brute-force reference for the error measurement");
    // Compared over a transparent background, so that alpha is the coverage itself.
    // (The scene's own background set aside and put back: no copy of its meshes and hairs.)
    const glm::vec4 background = sf.scene.background;
    sf.scene.background = glm::vec4(0.0f);
    const wf::RenderResult ref = withinBudget([&] { return wf::renderReference(sf.scene, referenceOptions); });
    wf::releaseRenderMemory();
    std::optional<wf::RenderResult> transparent;  // (a reference to r otherwise: no copy of its image)
    if (second) {
      transparent = withinBudget([&] { return wf::render(sf.scene, secondOptions); });
      wf::releaseRenderMemory();
    }
    // Stochastic simplification against its exact path (every hair drawn, the same shading
    // path): its own share of the error, and what drawing them all costs.
    std::optional<wf::RenderResult> full;
    if (ro.simplify.enabled) {
      progress.say("rendering every hair (simplification off) for the simplification's error");
      full = withinBudget([&] { return wf::render(sf.scene, fullOptions); });
      wf::releaseRenderMemory();
    }
    sf.scene.background = background;
    const wf::RenderResult& mine = transparent ? *transparent : r;
    if (full) {
      const ImageError s = imageError(mine.image, full->image);
      stats["error_estimate"]["simplification"]["measured_against_full"] = {{"rgba_rms", s.rms},
                                                                            {"rgba_max", s.max},
                                                                            {"coverage_rms", s.coverageRms},
                                                                            {"coverage_max", s.coverageMax},
                                                                            {"full_seconds", full->stats.total}};
    }
    const ImageError e = imageError(mine.image, ref.image);
    const int samples = referenceOptions.referenceSamples;
    stats["error_estimate"]["measured_against_reference"] = {{"reference_samples", samples * samples},
                                                             {"rgba_rms", e.rms},
                                                             {"rgba_max", e.max},
                                                             {"coverage_rms", e.coverageRms},
                                                             {"coverage_max", e.coverageMax},
                                                             {"reference_seconds", ref.stats.total}};
  }
  const auto tw = std::chrono::steady_clock::now();
  OutputFile png(o.output);
  std::optional<OutputFile> statsFile;
  if (!o.statsPath.empty()) statsFile.emplace(o.statsPath);
  writePngFile(r.image, png.temporaryPath(), o.output);
  stats["seconds"]["read_input"] = readSeconds;
  stats["seconds"]["generate"] = sf.generateSeconds;  // fur and scales, part of read_input
  stats["generated"] = {{"hairs", sf.hairsGrown}, {"scales", sf.scalesGrown}};
  {
    // Brushed steel: its grain laid out per face (surface/grain_layout.h), and its grooves.
    json b = json::object();
    for (const wf::Material& m : sf.scene.materials)
      if (m.burnish.active() && m.burnish.grooves) {
        b["grooves_per_unit"] = m.burnish.grooves->count();
        b["groove_depth"] = m.burnish.grooves->depth();
        break;
      }
    if (sf.grainFaces > 0) b["faces"] = {{"laid_out", sf.grainFaces}, {"along_u", sf.grainAlongU}, {"along_v", sf.grainAlongV}};
    if (!b.empty()) stats["burnish"] = b;
  }
  {
    // The materials the drawn surfaces and wires use, by name, in the scene's order.
    const int nm = std::max(1, int(sf.scene.materials.size()));
    std::vector<bool> used(size_t(nm), false);
    for (const wf::SceneSurface& s : sf.scene.surfaces) used[size_t(std::clamp(s.material, 0, nm - 1))] = true;
    for (const wf::SceneWire& w : sf.scene.wires) used[size_t(std::clamp(w.material, 0, nm - 1))] = true;
    json names = json::array();
    for (int i = 0; i < nm && i < int(sf.scene.materials.size()); ++i)
      if (used[size_t(i)]) names.push_back(sf.scene.materials[size_t(i)].name);
    stats["materials"] = names;
  }
  if (!sf.inputStats.empty()) {
    stats["input"]["cad"] = sf.inputStats;
    stats["seconds"]["cad_read"] = sf.inputStats["seconds_read"];
    stats["seconds"]["cad_mesh"] = sf.inputStats["seconds_mesh"];
    // The tessellation's chordal deflection in pixels at the model's centre: how far a facet may
    // stand off the true surface on screen (normals, (u, v) and tangents are exact).
    if (sf.scene.camera) {
      const wf::Camera& c = *sf.scene.camera;
      const double d = sf.inputStats["linear_deflection"].get<double>();
      const double worldPerPixel = c.projection == wf::Camera::Projection::Orthographic
                                       ? c.orthoHeight / ro.height
                                       : 2.0 * glm::length(c.eye - c.target) * std::tan(glm::radians(c.fovYDegrees) / 2) / ro.height;
      stats["error_estimate"]["tessellation_deflection_px"] = worldPerPixel > 0 ? d / worldPerPixel : 0.0;
    }
  }
  if (!sf.silhouettes.empty()) {
    // Silhouettes of curved faces, traced for this camera (surface/silhouette.h): what was
    // traced, and the bound each drawn chord keeps from the true curve on screen.
    const wf::SilhouetteStats& ss = sf.silhouetteStats;
    stats["silhouettes"] = {{"faces", ss.faces},           {"curves", ss.curves},     {"points", ss.points},
                            {"non_finite", ss.nonFinite}, {"cut_short", ss.cutShort}, {"evaluations", ss.evaluations}};
    stats["seconds"]["silhouettes"] = sf.silhouetteSeconds;
    stats["error_estimate"]["silhouette_chord_px"] = sf.silhouettes.front().options.tolerancePx;
  }
  {
    // The classified lines drawn (a model's edges by class, silhouettes): render/edge_classes.h.
    std::size_t byClass[wf::kEdgeClasses] = {};
    bool any = false;
    for (const wf::SceneWire& w : sf.scene.wires)
      for (wf::EdgeClass c : w.edgeClasses) ++byClass[std::size_t(c)], any = true;
    if (any) {
      nlohmann::ordered_json j = nlohmann::ordered_json::object();
      for (int c = 0; c < wf::kEdgeClasses; ++c) j[wf::edgeClassName(wf::EdgeClass(c))] = byClass[c];
      stats["edges_drawn"] = j;
    }
  }
  stats["seconds"]["write_png"] = secondsSince(tw);
  stats["peak_rss_bytes"] = peakRssBytes();
  // (A peak already passed, the reading, counts in the bound the stats report, not in the check.)
  stats["memory"] = {{"estimate_bytes", std::max(memoryEstimate, double(peakBeforeRender))},
                     {"peak_rss_bytes", peakRssBytes()},
                     {"budget_bytes", ro.memoryBudget}};
  // Both files or neither: each is written whole under its temporary name, then both are renamed.
  if (statsFile) {
    std::ofstream out(statsFile->temporaryPath());
    out << stats.dump(2) << "\n";
    out.close();
    if (!out) throw OutputError(o.statsPath + ": cannot write the stats (nothing was written)");
  }
  png.commit();
  if (statsFile) {
    try {
      statsFile->commit();
    } catch (const OutputError&) {
      std::remove(o.output.c_str());
      throw OutputError(o.statsPath + ": cannot write the stats (the PNG was removed too)");
    }
  }
  progress.say("wrote " + o.output + " in " + std::to_string(r.stats.total) + " s (render)");
  return 0;
}

}  // namespace wfapp
