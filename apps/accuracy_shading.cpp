// The shading paths (render/renderer.h: ShadingPath) in `wirefur accuracy`.
//
// 1. The closed form's lobe table (shading/cylinder_lobe.h): nodes against its measured error
//    and build time, over exponents 1 ... 1e5.
// 2. Per fragment, 7 lights, n = 100, tangents at random, view vectors of a 40-degree image:
//    the paper's map (orthographic assumption), the closed form with the table, with the exact
//    factor, and the quadrature over the normals; each one's time and its largest error against
//    the quadrature at the fragment's own view vector.
// 3. Every scene of data/scenes and a CAD part (data/cad/product.step, brushed steel) rendered
//    on the three paths at <= 320 pixels: time (median of 3), the render's own bound, and the
//    largest difference to the exact path (same geometry and coverage, so it is the shading).
#include "accuracy_shading.h"
#include "cli.h"

#include "accuracy_abuffer.h"
#include "cad_input.h"
#include "render_command.h"
#include "scene_file.h"

#include "shading/cylinder_lobe.h"
#include "shading/cylinder_shading.h"
#include "shading/pseudo_reflectance_map.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>

namespace wfapp {

using json = nlohmann::ordered_json;

namespace {

template <class F>
double nsPerCall(size_t n, F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / double(n) * 1e9;
}

}  // namespace

json shadingPathsStudy(bool quick, const Progress& progress, std::vector<std::pair<std::string, PlotSpec>>& plots) {
  json out;
  // ---- 1. the lobe table ----------------------------------------------------------------------
  progress.say("shading paths: lobe table resolution");
  json table = json::array();
  PlotSeries tableSeries{"lobe table, max over n = 0.5 ... 1e5 (labels: nodes)", {}, {}, {}, "linespoints"};
  const std::vector<int> nodeCounts = quick ? std::vector<int>{16, 64, 256} : std::vector<int>{8, 16, 32, 64, 128, 256, 512, 1024};
  for (int nodes : nodeCounts) {
    double err = 0.0, build = 0.0;
    size_t bytes = 0;
    for (double n : {0.5, 1.0, 20.0, 128.0, 1000.0, 1e5}) {
      const wf::CylinderLobeTable t(n, nodes);
      err = std::max(err, t.measuredError());
      build = std::max(build, t.buildSeconds());
      bytes = t.bytes();
    }
    table.push_back({{"nodes", nodes}, {"max_error", err}, {"build_ms", build * 1e3}, {"bytes", bytes}});
    tableSeries.x.push_back(build * 1e3);
    tableSeries.y.push_back(std::max(err, 1e-16));
    tableSeries.labels.push_back(std::to_string(nodes));
    std::printf("  lobe table %5d nodes: max error %.2e, build %.3f ms (slowest exponent)\n", nodes, err, build * 1e3);
  }
  out["lobe_table"] = table;
  plots.emplace_back("lobe_table.png", PlotSpec{"Lobe table of the closed form: error against build time",
                                                "build time [ms]", "max |G_table - G_exact|", true, true, {tableSeries}, {}});

  // ---- 2. per fragment -------------------------------------------------------------------------
  progress.say("shading paths: cost and error per fragment");
  const wf::LightRig rig = wf::LightRig::studioRig(7).canonical();
  wf::PhongMaterial m;
  m.exponent = 100.0;
  const size_t count = quick ? 500 : 5000;
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  const double halfField = std::tan(glm::radians(20.0));  // a 40-degree image
  std::vector<glm::dvec3> Ts(count), Vs(count);
  for (size_t i = 0; i < count; ++i) {
    Ts[i] = glm::normalize(glm::dvec3(U(rng), U(rng), U(rng)) + glm::dvec3(0.0, 0.0, 1e-9));
    Vs[i] = glm::normalize(glm::dvec3(halfField * U(rng), halfField * U(rng), 1.0));
  }
  std::vector<glm::dvec3> ref(count), got(count);
  const double quadNs = nsPerCall(count, [&] {
    for (size_t i = 0; i < count; ++i) ref[i] = wf::cylinderRadianceExact(Ts[i], Vs[i], m, rig, 1e-12);
  });
  auto errorOf = [&] {
    double e = 0.0;
    for (size_t i = 0; i < count; ++i) e = std::max(e, channelError(got[i], ref[i]));
    return e;
  };
  wf::PseudoReflectanceMap map;
  map.build(m, rig);
  const double mapNs = nsPerCall(count, [&] {
    for (size_t i = 0; i < count; ++i) got[i] = glm::dvec3(map.lookup(Ts[i]));
  });
  const double mapErr = errorOf();
  const wf::CylinderLobeTable lobe(m.exponent);
  const double closedNs = nsPerCall(count, [&] {
    for (size_t i = 0; i < count; ++i) got[i] = wf::cylinderRadianceClosed(Ts[i], Vs[i], m, rig, &lobe);
  });
  const double closedErr = errorOf();
  const double exactNs = nsPerCall(count, [&] {
    for (size_t i = 0; i < count; ++i) got[i] = wf::cylinderRadianceClosed(Ts[i], Vs[i], m, rig, nullptr);
  });
  const double exactErr = errorOf();
  out["per_fragment"] = {{"lights", 7}, {"exponent", m.exponent}, {"field_of_view_deg", 40},
                         {"map_ns", mapNs}, {"map_max_error", mapErr},
                         {"closed_ns", closedNs}, {"closed_max_error", closedErr},
                         {"exact_ns", exactNs}, {"exact_max_error", exactErr},
                         {"quadrature_ns", quadNs}};
  std::printf("  per fragment (7 lights, n = 100, 40-degree image): map %.0f ns (max error %.2e, orthographic), "
              "closed %.0f ns (%.2e), exact %.0f ns (%.2e), quadrature over the normals %.0f ns\n",
              mapNs, mapErr, closedNs, closedErr, exactNs, exactErr, quadNs);
  plots.emplace_back(
      "shading_paths_per_fragment.png",
      PlotSpec{"Cylinder shading per fragment: error at the fragment's own view vector against time (7 lights, n = 100)",
               "time per fragment [ns]", "max error (linear radiance)", true, true,
               {{"paper's map (orthographic view)", {mapNs}, {std::max(mapErr, 1e-16)}, {}, "points pt 5 ps 2"},
                {"closed form, lobe table (the default)", {closedNs}, {std::max(closedErr, 1e-16)}, {}, "points pt 7 ps 2"},
                {"closed form, exact factor", {exactNs}, {std::max(exactErr, 1e-16)}, {}, "points pt 9 ps 2"},
                {"quadrature over the normals (before)", {quadNs}, {1e-16}, {}, "points pt 11 ps 2"}},
               {2e-3}});

  // ---- 3. the gallery's scenes and a CAD part ---------------------------------------------------
  progress.say("shading paths: the gallery's scenes and a CAD part on every path");
  std::vector<std::string> files;
  const std::string scenesDir = dataDir() + "/scenes";
  std::error_code ec;
  if (std::filesystem::is_directory(scenesDir, ec))
    for (const auto& e : std::filesystem::directory_iterator(scenesDir))
      if (e.path().extension() == ".json") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  if (quick) {
    std::vector<std::string> few;
    for (const std::string& f : files)
      for (const char* stem : {"cage_shaded", "jug_burnished", "fur_torus"})
        if (std::filesystem::path(f).stem() == stem) few.push_back(f);
    files = few;
  }
  const std::string cad = dataDir() + "/cad/product.step";
  if (std::filesystem::exists(cad, ec)) files.push_back(cad);
  const int side = quick ? 96 : 320, reps = quick ? 1 : 3;
  json scenes = json::array();
  PlotSeries closedPts{"closed (the default)", {}, {}, {}, "points pt 7"}, mapPts{"maps (the paper's)", {}, {}, {}, "points pt 5"};
  std::printf("  %-26s %22s %22s %10s\n", ("scene (<= " + std::to_string(side) + " px)").c_str(), "closed: s, max err",
              "maps: s, max err", "exact: s");
  double worstClosed = 0.0, worstRatio = 0.0;
  for (const std::string& file : files) {
    const std::string stem = std::filesystem::path(file).stem().string();
    SceneFile sf;
    try {
      sf = file == cad ? sceneForCadFile(file, "burnished", SceneOverrides{}) : loadSceneFile(file);
    } catch (const std::exception& e) {  // a build without CAD support
      std::printf("  %-26s skipped: %s\n", stem.c_str(), e.what());
      continue;
    }
    wf::RenderOptions o = renderOptionsFor(sf);
    const double f = double(side) / std::max(o.width, o.height);
    if (f < 1.0) {
      o.width = std::max(1, int(std::lround(o.width * f)));
      o.height = std::max(1, int(std::lround(o.height * f)));
      reframe(sf, o.width, o.height);
    }
    wf::RenderResult exact, closed, maps;
    o.shading = wf::ShadingPath::Exact;
    const double tExact = medianSeconds(reps, sf.scene, o, exact);
    o.shading = wf::ShadingPath::Closed;
    const double tClosed = medianSeconds(reps, sf.scene, o, closed);
    o.shading = wf::ShadingPath::Maps;
    const double tMaps = medianSeconds(reps, sf.scene, o, maps);
    const ImageError ec2 = imageError(closed.image, exact.image), em = imageError(maps.image, exact.image);
    const json sc = statsJson(closed.stats, o, false), sm = statsJson(maps.stats, o, false);
    const std::string name = file == cad ? "product.step (burnished)" : stem;
    scenes.push_back({{"scene", name}, {"size", {o.width, o.height}},
                      {"closed", {{"seconds", tClosed}, {"bound", sc["error_estimate"]["shading_bound"]}, {"rgba_max", ec2.max}, {"rgba_rms", ec2.rms}}},
                      {"maps", {{"seconds", tMaps}, {"bound", sm["error_estimate"]["shading_bound"]}, {"rgba_max", em.max}, {"rgba_rms", em.rms}}},
                      {"exact", {{"seconds", tExact}}}});
    std::printf("  %-26s %9.4f  %11.2e %9.4f  %11.2e %10.4f\n", name.c_str(), tClosed, ec2.max, tMaps, em.max, tExact);
    worstClosed = std::max(worstClosed, ec2.max);
    worstRatio = std::max(worstRatio, tClosed / tMaps);
    closedPts.x.push_back(tClosed * 1e3);
    closedPts.y.push_back(std::max(ec2.max, 1e-9));
    mapPts.x.push_back(tMaps * 1e3);
    mapPts.y.push_back(std::max(em.max, 1e-9));
  }
  std::printf("  closed path: largest difference to exact %.2e over %zu renders; time at most %.2fx the maps'\n", worstClosed,
              scenes.size(), worstRatio);
  out["scenes"] = scenes;
  out["closed_worst_rgba_max"] = worstClosed;
  out["closed_over_maps_worst_time_ratio"] = worstRatio;
  plots.emplace_back("shading_paths_scenes.png",
                     PlotSpec{"Gallery scenes and a CAD part: largest shading error against exact, against render time "
                              "(one point per scene; 1e-9: below the floor)",
                              "render time [ms]", "max RGBA difference to the exact path", true, true,
                              {closedPts, mapPts}, {2e-3}});
  return out;
}

}  // namespace wfapp
