#include "render_command.h"

#include "texture/grooves.h"

#include "cad_input.h"
#include "cli.h"
#include "image_io.h"
#include "mesh_io.h"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace wfapp {

using json = nlohmann::ordered_json;

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
                           {"note", "statistical: no per-pixel bound; wirefur accuracy measures its RMS against time"}};
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
  // The memory the render (and the reference of --measure-error) will need, with this scene,
  // plus the 8-bit copy the PNG is encoded from: refused before anything large is allocated.
  {
    const std::size_t png = std::size_t(ro.width) * std::size_t(ro.height) * 3;
    wf::RenderOptions check = ro;
    if (check.memoryBudget > 0) check.memoryBudget = check.memoryBudget > png ? check.memoryBudget - png : 1;
    std::string p = wf::memoryProblem(sf.scene, check, o.reference);
    if (p.empty() && o.measureError) p = wf::memoryProblem(sf.scene, check, true);
    if (!p.empty()) throw UsageError("render: " + (o.input.empty() ? std::string("built-in scene") : o.input) + ": " + p);
  }
  // Make sure the outputs can be written before spending time on the render: the folder
  // exists, the name is not a folder, and a file can be created beside it.
  for (const std::string& f : {o.output, o.statsPath}) {
    if (f.empty()) continue;
    const std::filesystem::path target(f), parent = target.parent_path();
    std::error_code ec;
    if (!parent.empty() && !std::filesystem::is_directory(parent, ec))
      throw UsageError(f + ": the folder " + parent.string() + " does not exist");
    if (std::filesystem::is_directory(target, ec)) throw UsageError(f + ": is a folder");
    std::string probeName = target.filename().string();
    probeName.insert(0, 1, '.');
    probeName += ".probe";
    const std::filesystem::path probe = parent / probeName;
    {
      std::ofstream test(probe);
      if (!test) throw UsageError(f + ": cannot be written here");
    }
    std::filesystem::remove(probe, ec);
  }
  if (!o.statsPath.empty() && std::filesystem::absolute(o.statsPath) == std::filesystem::absolute(o.output))
    throw UsageError(o.statsPath + ": --stats and -o name the same file");
  progress.say("rendering " + (o.input.empty() ? std::string("the built-in scene") : o.input) + " at " +
               std::to_string(ro.width) + "x" + std::to_string(ro.height) + (o.reference ? " (reference)" : ""));
  const wf::RenderResult r = o.reference ? wf::renderReference(sf.scene, ro) : wf::render(sf.scene, ro);
  for (const std::string& w : r.stats.warnings) warn((o.input.empty() ? "built-in scene" : o.input) + ": " + w);
  json stats = statsJson(r.stats, ro, o.reference);
  if (o.measureError && !o.reference) {
    progress.say("rendering the brute-force reference for the error measurement");
    wf::RenderOptions rr = ro;
    rr.shading = wf::ShadingPath::Exact;
    // Compared over a transparent background, so that alpha is the coverage itself.
    wf::Scene clear = sf.scene;
    clear.background = glm::vec4(0.0f);
    const wf::RenderResult ref = wf::renderReference(clear, rr);
    const wf::RenderResult mine = sf.scene.background.w > 0.0f ? wf::render(clear, ro) : r;
    const ImageError e = imageError(mine.image, ref.image);
    stats["error_estimate"]["measured_against_reference"] = {{"reference_samples", rr.referenceSamples * rr.referenceSamples},
                                                             {"rgba_rms", e.rms},
                                                             {"rgba_max", e.max},
                                                             {"coverage_rms", e.coverageRms},
                                                             {"coverage_max", e.coverageMax},
                                                             {"reference_seconds", ref.stats.total}};
  }
  const auto tw = std::chrono::steady_clock::now();
  writePng(r.image, o.output);
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
  if (!o.statsPath.empty()) {
    // Both files or neither: a stats file that cannot be written takes the PNG back with it.
    const std::string tmp = o.statsPath + ".tmp";
    std::error_code ec;
    bool ok = false;
    {
      std::ofstream out(tmp);
      out << stats.dump(2) << "\n";
      ok = bool(out);
    }
    if (ok) std::filesystem::rename(tmp, o.statsPath, ec);
    if (!ok || ec) {
      std::filesystem::remove(tmp, ec);
      std::filesystem::remove(o.output, ec);
      throw std::runtime_error(o.statsPath + ": cannot write the stats (the PNG was removed too)");
    }
  }
  progress.say("wrote " + o.output + " in " + std::to_string(r.stats.total) + " s (render)");
  return 0;
}

}  // namespace wfapp
